#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <opencv2/imgcodecs.hpp>

#include "colmap_plugins/scene/model_io.h"
#include "common/cli/command.h"
#include "common/util/error.h"
#include "common/util/file.h"
#include "common/util/plot.h"
#include "laserscale/exe/commands.h"
#include "laserscale/laser_setup.h"
#include "laserscale/spot_detector.h"
#include "laserscale/spot_overlay.h"
#include "laserscale/spots_io.h"

namespace uw {
namespace {

namespace fs = std::filesystem;

bool IsAuxName(const std::string& name) {
  return fs::path(name).stem().string().size() > 4 &&
         fs::path(name).stem().string().substr(
             fs::path(name).stem().string().size() - 4) == "_aux";
}

cv::Mat ReadImage(const fs::path& path) {
  const cv::Mat image = cv::imread(path.string(), cv::IMREAD_COLOR);
  if (image.empty()) throw ErrorAt(path.string(), ": cannot read the image");
  return image;
}

std::vector<double> ParseParams(const std::string& text) {
  std::vector<double> params;
  std::stringstream stream(text);
  std::string part;
  while (std::getline(stream, part, ',')) {
    try {
      size_t used = 0;
      params.push_back(std::stod(part, &used));
      if (used != part.size()) throw 0;
    } catch (...) {
      throw ErrorAt("--camera_params: '", part, "' is not a number");
    }
  }
  return params;
}

}  // namespace

int RunDetect(int argc, char** argv) {
  CLI::App app(
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
      "laserscale detect");
  std::string images_dir;
  std::string image_list_path;
  std::string aux = "auto";
  std::string lasers_path;
  std::string setup_name;
  std::string input_path;
  uint32_t camera_id = 1;
  std::string camera_model;
  std::string camera_params;
  std::string out;
  std::string overlays_dir;
  uint64_t seed = 0;
  SpotDetectorOptions options;
  app.add_option("--images", images_dir, "Folder of the laser images")
      ->required();
  app.add_option("--image_list_path", image_list_path,
                 "Images to use, one name per line (default: every image of "
                 "the folder but the *_aux ones)");
  app.add_option("--aux", aux,
                 "Auxiliary images: auto (NAME_aux.EXT beside NAME.EXT, else "
                 "the next image of the list), none, or a CSV of "
                 "image,aux lines")
      ->capture_default_str();
  app.add_option("--lasers", lasers_path, "lasers.json")->required();
  app.add_option("--setup", setup_name,
                 "Set-up of lasers.json (default: the only one)");
  app.add_option("--input_path", input_path,
                 "COLMAP model whose camera --camera_id the images have");
  app.add_option("--camera_id", camera_id, "Camera of --input_path")
      ->capture_default_str();
  app.add_option("--camera_model", camera_model,
                 "COLMAP camera model (without --input_path)");
  app.add_option("--camera_params", camera_params,
                 "Its parameters, comma-separated, COLMAP order");
  app.add_option("--out", out, "spots.json to write")->required();
  app.add_option("--overlays", overlays_dir,
                 "Folder for overlays (NAME_spots.png) with 68 / 95 % "
                 "ellipses");
  app.add_option("--seed", seed, "Seed of the detection Monte Carlo")
      ->capture_default_str();
  app.add_option("--mc", options.monte_carlo_iterations,
                 "Detection Monte Carlo iterations")
      ->capture_default_str();
  app.add_option("--min_detection_rate", options.min_detection_rate,
                 "Stable: detected in at least this fraction of iterations")
      ->capture_default_str();
  app.add_option("--min_range_m", options.min_range_m,
                 "Nearest scene distance, for the spot regions")
      ->capture_default_str();
  app.add_option("--max_range_m", options.max_range_m,
                 "Farthest scene distance, for the spot regions")
      ->capture_default_str();
  app.add_option("--noise_sigma", options.noise_sigma,
                 "Image noise sigma (0-255 units); < 0: estimate")
      ->capture_default_str();
  app.add_option("--num_threads", options.num_threads, "Threads (<= 0: all)")
      ->capture_default_str();
  return RunCommand(app, argc, argv, [&] {
    options.Check();
    const std::vector<LaserSetup> setups = ReadLasersJson(lasers_path);
    const LaserSetup* setup = nullptr;
    for (const LaserSetup& candidate : setups) {
      if (candidate.name == setup_name ||
          (setup_name.empty() && setups.size() == 1)) {
        setup = &candidate;
      }
    }
    if (setup == nullptr) {
      throw ErrorAt(lasers_path, ": choose a set-up with --setup (",
                    setups.size(), " set-ups)");
    }
    Camera camera;
    if (!input_path.empty()) {
      const Reconstruction model = ReadModel(input_path);
      const Camera* found = model.FindCamera(camera_id);
      if (found == nullptr) {
        throw ErrorAt(input_path, ": no camera ", camera_id);
      }
      camera = *found;
    } else {
      if (camera_model.empty() || camera_params.empty()) {
        throw ErrorAt(
            "give --input_path or --camera_model and "
            "--camera_params");
      }
      camera.model_id = CameraModelNameToId(camera_model);
      if (camera.model_id == CameraModelId::kInvalid) {
        throw ErrorAt("--camera_model: unknown model '", camera_model, "'");
      }
      camera.params = ParseParams(camera_params);
      CheckCameraModelParams(camera.model_id, camera.params.size());
    }
    const std::vector<std::string> names =
        ListImages(images_dir, image_list_path,
                   [](const std::string& name) { return !IsAuxName(name); });
    std::map<std::string, std::string> aux_of;
    if (aux != "auto" && aux != "none") {
      std::ifstream in(aux);
      if (!in) throw ErrorAt(aux, ": cannot open the auxiliary list");
      std::string line;
      for (int number = 1; std::getline(in, line); ++number) {
        if (!line.empty() && line.back() == '\r') line.pop_back();
        if (line.empty()) continue;
        const size_t comma = line.find(',');
        if (comma == std::string::npos) {
          throw ErrorAt(aux, ":", number, ": expected image,aux");
        }
        aux_of[line.substr(0, comma)] = line.substr(comma + 1);
      }
    }
    std::vector<ImageSpots> results;
    size_t num_stable = 0;
    size_t num_spots = 0;
    for (size_t i = 0; i < names.size(); ++i) {
      const fs::path path = fs::path(images_dir) / names[i];
      const cv::Mat image = ReadImage(path);
      if (camera.width == 0) {
        camera.width = static_cast<uint64_t>(image.cols);
        camera.height = static_cast<uint64_t>(image.rows);
      }
      if (static_cast<int>(camera.width) != image.cols ||
          static_cast<int>(camera.height) != image.rows) {
        throw ErrorAt(path.string(), ": ", image.cols, "x", image.rows,
                      " pixels, the camera has ", camera.width, "x",
                      camera.height);
      }
      cv::Mat aux_image;
      if (aux == "auto") {
        const fs::path beside =
            path.parent_path() /
            (path.stem().string() + "_aux" + path.extension().string());
        if (fs::exists(beside)) {
          aux_image = ReadImage(beside);
        } else if (names.size() > 1) {
          aux_image = ReadImage(fs::path(images_dir) /
                                names[i + 1 < names.size() ? i + 1 : i - 1]);
        }
      } else if (aux != "none") {
        const auto found = aux_of.find(names[i]);
        if (found == aux_of.end()) {
          throw ErrorAt(aux, ": no auxiliary image for ", names[i]);
        }
        aux_image = ReadImage(fs::path(images_dir) / found->second);
      }
      ImageSpots spots;
      spots.name = names[i];
      spots.setup = setup->name;
      spots.spots =
          DetectSpots(image, aux_image, camera, *setup, options, seed + i);
      size_t stable = 0;
      for (const DetectedSpot& spot : spots.spots) stable += spot.stable;
      num_stable += stable;
      num_spots += spots.spots.size();
      std::printf("[detect %zu/%zu] %s: %zu of %zu lasers stable\n", i + 1,
                  names.size(), names[i].c_str(), stable, spots.spots.size());
      std::fflush(stdout);
      if (!overlays_dir.empty()) {
        fs::create_directories(overlays_dir);
        WritePngAtomically(
            DrawSpotOverlay(image, spots.spots),
            fs::path(overlays_dir) / (path.stem().string() + "_spots.png"));
      }
      results.push_back(std::move(spots));
    }
    WriteFilesAtomically(
        {{out,
          [&](std::ostream& stream) { stream << SpotsJsonText(results); }}},
        false);
    std::printf("[detect] %zu of %zu spots stable in %zu images; wrote %s\n",
                num_stable, num_spots, names.size(), out.c_str());
  });
}

}  // namespace uw
