#include "calib/exe/lasers_command.h"

#include <cstdio>

#include <fmt/format.h>

#include "calib/camera_export.h"
#include "calib/exe/board_flag.h"
#include "calib/mrcal_calibration.h"
#include "common/util/file.h"
#include "laserscale/laser_setup.h"

namespace uw {
namespace {

void AddCalibLasersFlags(CommandLine* cli, CalibLasersOptions* options) {
  cli->Add("--images", &options->images_dir, "Folder of the board images")
      ->required();
  cli->Add("--image_list_path", &options->image_list_path,
           "Only these images (names relative to --images, one a line)");
  AddBoardFlag(cli, &options->board,
               "the board, as for uwcalib detect (chessboard, aprilgrid, "
               "charuco)");
  cli->Add("--cameramodel", &options->cameramodel_path,
           "the camera's .cameramodel (uwcalib calibrate); a lens model "
           "uwcalib export takes")
      ->required();
  // Required: no default to show.
  cli->Add("--num_lasers", &options->lasers.num_lasers,
           "lasers on in the images")
      ->required()
      ->default_str("");
  cli->AddThreeArguments("--colour", &options->lasers.spots.colour,
                         "the lasers' colour, linear R G B");
  cli->Add("--min_excess", &options->lasers.spots.min_excess,
           "a spot's colour excess over the board around it, levels");
  cli->Add("--inlier_distance_m", &options->lasers.fit.inlier_distance_m,
           "a spot further from its laser's line is an outlier (m)");
  cli->Add("--min_depth_span_m", &options->lasers.fit.min_depth_span_m,
           "the spots of a laser must span this much depth (m)");
  cli->Add("--setup_name", &options->lasers.setup_name,
           "the set-up's name in lasers.json");
  cli->Add("--out", &options->out, "lasers.json to write")->required();
}

void RunCalibLasers(const CalibLasersOptions& options) {
  const Camera camera = ColmapCameraFromMrcal(
      ReadCameraModel(options.cameramodel_path), options.cameramodel_path);
  const std::vector<std::string> names =
      ListImages(options.images_dir, options.image_list_path);
  const BoardLaserCalibration result = CalibrateLasersFromBoardImages(
      camera, options.board, options.images_dir, names, options.lasers,
      [](const std::string& image, bool board_found, size_t num_spots) {
        fmt::print(stderr, "[lasers] {}: {}, {} spots\n", image.c_str(),
                   board_found ? "board found" : "no board (skipped)",
                   num_spots);
      });
  for (const LaserLineFit& fit : result.fits) {
    fmt::print("{}\n", DescribeLaserLineFit(fit).c_str());
  }
  WriteFilesAtomically({{options.out,
                         [&](std::ostream& stream) {
                           stream << LasersJsonText({result.setup});
                         }}},
                       false);
  fmt::print("[lasers] {} of {} images with the board; {}\n",
             result.num_images_with_board, names.size(), options.out.c_str());
}

}  // namespace

Subcommand CalibLasersCommand() {
  return MakeSubcommand<CalibLasersOptions>(
      "lasers", "laser lines from board images at many distances (lasers.json)",
      "Laser lines from images of a calibration board held at many "
      "distances, the lasers on (thesis ch. 3 §2.4; underwater, so that the "
      "housings' refraction is in): in each image the board's pose from its "
      "corners (the camera from --cameramodel) and the spots of the lasers' "
      "colour; each spot's ray cut with the board's plane; the points "
      "sorted into --num_lasers lines by sequential RANSAC and a line "
      "fitted to each. Writes lasers.json: per laser the origin on the "
      "camera plane, the direction and their covariances (docs/uwcalib.md)."
      "\n\nExample:\n"
      "  uwcalib lasers --images laser_boards --board chessboard:9x7:0.08 "
      "--cameramodel cal/camera-0.cameramodel --num_lasers 4 --out "
      "lasers.json",
      AddCalibLasersFlags, RunCalibLasers);
}

}  // namespace uw
