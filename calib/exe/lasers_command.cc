#include <cstdio>
#include <filesystem>
#include <optional>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "calib/board.h"
#include "calib/board_detection.h"
#include "calib/board_pose.h"
#include "calib/camera_export.h"
#include "calib/colour_spots.h"
#include "calib/exe/commands.h"
#include "calib/laser_line_fit.h"
#include "calib/mrcal_calibration.h"
#include "common/cli/command.h"
#include "common/util/error.h"
#include "common/util/file.h"
#include "laserscale/laser_setup.h"

namespace uw {

int RunCalibLasers(int argc, char** argv) {
  CLI::App app(
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
      "uwcalib lasers");
  std::string images_dir;
  std::string image_list_path;
  std::string board_spec;
  std::string model_path;
  std::string out;
  std::string setup_name = "board";
  int num_lasers = 0;
  std::vector<double> colour = {1.0, 0.0, 0.0};
  LaserLineFitOptions fit_options;
  ColourSpotOptions spot_options;
  app.add_option("--images", images_dir, "Folder of the board images")
      ->required();
  app.add_option("--image_list_path", image_list_path,
                 "Only these images (names relative to --images, one a line)");
  app.add_option("--board", board_spec,
                 "the board, as for uwcalib detect (chessboard, aprilgrid, "
                 "charuco)")
      ->required();
  app.add_option("--cameramodel", model_path,
                 "the camera's .cameramodel (uwcalib calibrate); a lens model "
                 "uwcalib export takes")
      ->required();
  app.add_option("--num_lasers", num_lasers, "lasers on in the images")
      ->required();
  app.add_option("--colour", colour, "the lasers' colour, linear R G B")
      ->expected(3)
      ->capture_default_str();
  app.add_option("--min_excess", spot_options.min_excess,
                 "a spot's colour excess over the board around it, levels")
      ->capture_default_str();
  app.add_option("--inlier_distance_m", fit_options.inlier_distance_m,
                 "a spot further from its laser's line is an outlier (m)")
      ->capture_default_str();
  app.add_option("--min_depth_span_m", fit_options.min_depth_span_m,
                 "the spots of a laser must span this much depth (m)")
      ->capture_default_str();
  app.add_option("--setup_name", setup_name, "the set-up's name in lasers.json")
      ->capture_default_str();
  app.add_option("--out", out, "lasers.json to write")->required();
  return RunCommand(app, argc, argv, [&] {
    const CalibrationBoard board = ParseBoard(board_spec);
    const Camera camera =
        ColmapCameraFromMrcal(ReadCameraModel(model_path), model_path);
    spot_options.colour = Eigen::Vector3d(colour[0], colour[1], colour[2]);
    spot_options.Check();
    fit_options.Check();
    const std::vector<std::string> names =
        ListImages(images_dir, image_list_path);
    std::vector<LaserBoardSpot> spots;
    int used = 0;
    for (const std::string& name : names) {
      const std::filesystem::path path =
          std::filesystem::path(images_dir) / name;
      const cv::Mat bgr = cv::imread(path.string(), cv::IMREAD_COLOR);
      if (bgr.empty()) throw ErrorAt(path.string(), ": cannot read the image");
      if (bgr.cols != static_cast<int>(camera.width) ||
          bgr.rows != static_cast<int>(camera.height)) {
        throw ErrorAt(path.string(), ": ", bgr.cols, "x", bgr.rows,
                      ", but the camera model is ", camera.width, "x",
                      camera.height);
      }
      cv::Mat grey;
      cv::cvtColor(bgr, grey, cv::COLOR_BGR2GRAY);
      const BoardObservation corners = DetectBoardCorners(grey, board, name);
      const std::optional<Rigid3d> pose =
          EstimateBoardPose(camera, board, corners);
      const std::vector<Eigen::Vector2d> found =
          FindColourSpots(bgr, spot_options);
      std::fprintf(stderr, "[lasers] %s: %s, %zu spots\n", name.c_str(),
                   pose ? "board found" : "no board (skipped)", found.size());
      if (!pose) continue;
      ++used;
      for (const Eigen::Vector2d& pixel : found) {
        spots.push_back({name, *pose, pixel});
      }
    }
    if (used < fit_options.min_distances) {
      throw ErrorAt(images_dir, ": the board was found in ", used, " of ",
                    names.size(), " images; at least ",
                    fit_options.min_distances,
                    " distances are needed; nothing written");
    }
    const std::vector<LaserLineFit> fits =
        FitLaserLines(camera, spots, num_lasers, fit_options);
    LaserSetup setup;
    setup.name = setup_name;
    for (const LaserLineFit& fit : fits) {
      Laser laser = fit.laser;
      laser.colour = spot_options.colour;
      setup.lasers.push_back(laser);
      double min_z = 1e300;
      double max_z = 0.0;
      for (const Eigen::Vector3d& p : fit.points_in_cam) {
        min_z = std::min(min_z, p.z());
        max_z = std::max(max_z, p.z());
      }
      std::printf(
          "laser %s: %zu spots from %.2f to %.2f m; origin (%.4f, %.4f) m "
          "(sigma %.2f mm), direction (%.5f, %.5f, %.5f) (sigma %.4f "
          "deg); line RMS %.2f mm\n",
          laser.name.c_str(), fit.points_in_cam.size(), min_z, max_z,
          laser.origin_in_cam.x(), laser.origin_in_cam.y(),
          1000.0 * std::sqrt(laser.origin_cov.trace()),
          laser.direction_in_cam.x(), laser.direction_in_cam.y(),
          laser.direction_in_cam.z(),
          std::sqrt(laser.direction_cov.trace()) * 180.0 / M_PI,
          1000.0 * fit.rms_distance_m);
    }
    setup.Check();
    WriteFilesAtomically(
        {{out,
          [&](std::ostream& stream) { stream << LasersJsonText({setup}); }}},
        false);
    std::printf("[lasers] %d of %zu images with the board; %s\n", used,
                names.size(), out.c_str());
  });
}

}  // namespace uw
