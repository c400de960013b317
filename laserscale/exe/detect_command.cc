#include "laserscale/exe/detect_command.h"

#include <filesystem>

#include <fmt/format.h>

#include "common/util/file.h"
#include "common/util/png_file.h"
#include "laserscale/spot_overlay.h"
#include "laserscale/spots_io.h"

namespace uw {
namespace {

namespace fs = std::filesystem;

void AddDetectFlags(CommandLine* cli, DetectOptions* options) {
  LaserImageDetectionOptions& detection = options->detection;
  cli->Add("--images", &detection.images_dir, "Folder of the laser images")
      ->required();
  cli->Add("--image_list_path", &detection.image_list_path,
           "Images to use, one name per line (default: every image of "
           "the folder but the *_aux ones)");
  cli->Add("--aux", &detection.aux,
           "Auxiliary images: auto (NAME_aux.EXT beside NAME.EXT, else "
           "the next image of the list), none, or a CSV of "
           "image,aux lines");
  cli->Add("--lasers", &detection.lasers_path, "lasers.json")->required();
  cli->Add("--setup", &detection.setup_name,
           "Set-up of lasers.json (default: the only one)");
  cli->Add("--input_path", &detection.input_path,
           "COLMAP model whose camera --camera_id the images have");
  cli->Add("--camera_id", &detection.camera_id, "Camera of --input_path");
  cli->Add("--camera_model", &detection.camera_model,
           "COLMAP camera model (without --input_path)");
  cli->Add("--camera_params", &detection.camera_params,
           "Its parameters, comma-separated, COLMAP order");
  cli->Add("--out", &options->out, "spots.json to write")->required();
  cli->Add("--overlays", &options->overlays_dir,
           "Folder for overlays (NAME_spots.png) with 68 / 95 % "
           "ellipses");
  cli->Add("--seed", &detection.seed, "Seed of the detection Monte Carlo");
  SpotDetectorOptions& detector = detection.detector;
  cli->Add("--mc", &detector.monte_carlo_iterations,
           "Detection Monte Carlo iterations");
  cli->Add("--min_detection_rate", &detector.min_detection_rate,
           "Stable: detected in at least this fraction of iterations");
  cli->Add("--min_range_m", &detector.min_range_m,
           "Nearest scene distance, for the spot regions");
  cli->Add("--max_range_m", &detector.max_range_m,
           "Farthest scene distance, for the spot regions");
  cli->Add("--noise_sigma", &detector.noise_sigma,
           "Image noise sigma (0-255 units); < 0: estimate");
  cli->Add("--require_texture_removal", &detector.require_texture_removal,
           "Do not use a spot in a region where the auxiliary image did not "
           "match (the texture left in, a shell or highlight can pass for "
           "the laser); 0 keeps it");
  cli->Add("--max_colour_angle_deg", &detector.max_colour_angle_deg,
           "A spot's colour (its amplitude per channel in linear light) "
           "within this angle of the laser's (lasers.json colour), or it "
           "is not detected; 180: no colour test");
  cli->Add("--colour_noise_sigmas", &detector.colour_noise_sigmas,
           "Noise allowance of the colour test, in sigmas");
  cli->Add("--srgb_levels", &detector.srgb_levels,
           "Image levels are sRGB-encoded (camera files); 0: linear");
  cli->Add("--num_threads", &detector.num_threads, "Threads (<= 0: all)");
}

void RunDetect(const DetectOptions& options) {
  size_t num_stable = 0;
  size_t num_spots = 0;
  const std::vector<ImageSpots> results = DetectLaserImages(
      options.detection, [&](size_t i, size_t count, const cv::Mat& image,
                             const ImageSpots& spots) {
        size_t stable = 0;
        for (const DetectedSpot& spot : spots.spots) stable += spot.stable;
        num_stable += stable;
        num_spots += spots.spots.size();
        fmt::print("[detect {}/{}] {}: {} of {} lasers stable\n", i + 1, count,
                   spots.name.c_str(), stable, spots.spots.size());
        std::fflush(stdout);
        if (!options.overlays_dir.empty()) {
          fs::create_directories(options.overlays_dir);
          WritePngAtomically(
              DrawSpotOverlay(image, spots.spots),
              fs::path(options.overlays_dir) /
                  (fs::path(spots.name).stem().string() + "_spots.png"));
        }
      });
  WriteFilesAtomically(
      {{options.out,
        [&](std::ostream& stream) { stream << SpotsJsonText(results); }}},
      false);
  fmt::print("[detect] {} of {} spots stable in {} images; wrote {}\n",
             num_stable, num_spots, results.size(), options.out.c_str());
}

}  // namespace

Subcommand DetectCommand() {
  return MakeSubcommand<DetectOptions>(
      "detect", "find the laser spots in laser images, with their uncertainty",
      "Finds the laser spots in laser images, with the uncertainty of each "
      "centre: the spot's region is predicted from the calibration, the "
      "texture under it removed with an auxiliary image (aligned by FFT "
      "cross-correlation and an ECC homography, histogram-matched), the "
      "spot segmented by colour and fitted with a 2D Gaussian, and a Monte "
      "Carlo over image noise keeps only stable detections "
      "(docs/laserscale_detector.md).\n\n"
      "Example:\n"
      "  laserscale detect --images laser_images --aux auto --lasers "
      "lasers.json --input_path sparse/0 --out spots.json --overlays "
      "overlays",
      AddDetectFlags, RunDetect);
}

}  // namespace uw
