#include "calib/calibration_testing.h"

#include <cmath>

#include <fmt/format.h>
#include <Eigen/Geometry>

#include "calib/corners_vnl.h"
#include "common/util/error.h"
#include "common/util/file.h"
#include "common/util/random.h"
#include "common/util/subprocess.h"
#include "sim/board_images.h"
#include "tests/support/process.h"

namespace uw::testing_calibration {

Camera TrueCamera() {
  Camera camera;
  camera.model_id = CameraModelId::kOpenCV;
  camera.width = 1024;
  camera.height = 768;
  camera.params = {850.0, 848.0, 515.3, 380.9, -0.11, 0.06, 0.0008, -0.0004};
  return camera;
}

std::vector<BoardObservation> ViewsWithNoise(
    const Camera& camera, const CalibrationBoard& board,
    const std::vector<Rigid3d>& cam_from_board, double sigma_px,
    uint64_t seed) {
  SplitMix64Stream noise(seed);
  std::vector<BoardObservation> views;
  for (size_t v = 0; v < cam_from_board.size(); ++v) {
    BoardObservation view;
    view.image = "frame" + std::to_string(100 + v) + ".png";
    for (const Eigen::Vector3d& corner : board.CornersInBoard()) {
      const Eigen::Vector2d truth =
          camera.ImgFromCam(cam_from_board[v] * corner) -
          Eigen::Vector2d(0.5, 0.5);
      view.pixels.push_back(truth + sigma_px * noise.GaussianPair());
      view.weights.push_back(1.0);
    }
    views.push_back(view);
  }
  return views;
}

MrcalCalibrationOptions Options(const std::string& lens_model, double focal_px,
                                int width, int height) {
  MrcalCalibrationOptions options;
  options.lens_model = lens_model;
  options.focal_px = focal_px;
  options.image_width = width;
  options.image_height = height;
  return options;
}

std::string RunMrcalCalibrateCameras(const std::vector<RigCameraViews>& cameras,
                                     const CalibrationBoard& board,
                                     const MrcalCalibrationOptions& options,
                                     const std::vector<std::string>& globs,
                                     const std::filesystem::path& dir) {
  std::vector<BoardObservation> all_views;
  for (const RigCameraViews& camera : cameras) {
    all_views.insert(all_views.end(), camera.views.begin(), camera.views.end());
  }
  WriteFilesAtomically({{dir / "corners.vnl",
                         [&](std::ostream& out) {
                           out << FormatCornersVnl(
                               all_views, CornerWeightColumn::kLevel, {});
                         }}},
                       false);
  const std::string flags = fmt::format(
      " --lensmodel {} --focal {:.17g} --object-spacing {:.17g}"
      " --object-width-n {} --object-height-n {} --imagersize {} {}",
      options.lens_model, options.focal_px, board.spacing_m, board.grid_width,
      board.grid_height, options.image_width, options.image_height);
  std::string quoted_globs;
  for (const std::string& glob : globs) quoted_globs += " '" + glob + "'";
  const ProcessResult tool =
      RunProcess("cd " + testing::Quoted(dir) +
                     " && /usr/bin/python3 /usr/bin/mrcal-calibrate-cameras"
                     " --corners-cache corners.vnl --outdir . " +
                     flags + quoted_globs,
                 true);
  if (tool.exit_code != 0) {
    throw ErrorAt("mrcal-calibrate-cameras failed: ", tool.output);
  }
  return tool.output;
}

CalibrationBoard LaserBoard() { return ParseBoard("chessboard:9x7:0.08"); }

std::vector<LaserBoardView> RenderLaserBoardViews(const Camera& camera,
                                                  const LaserSetup& setup,
                                                  int num_distances,
                                                  uint64_t seed) {
  const CalibrationBoard board = LaserBoard();
  SplitMix64Stream random(seed);
  sim::BoardImageOptions options;
  options.white_level = 150.0;
  options.noise_sigma = 2.0;
  options.supersampling = 2;  // enough for corners and spots; 4x faster
  std::vector<LaserBoardView> views;
  for (int i = 0; i < num_distances; ++i) {
    const double distance = 0.6 + 3.0 * i / (num_distances - 1);
    const double degree = M_PI / 180.0;
    LaserBoardView view;
    view.cam_from_board.rotation =
        Eigen::Quaterniond(Eigen::AngleAxisd(random.Uniform(-10, 10) * degree,
                                             Eigen::Vector3d::UnitX()) *
                           Eigen::AngleAxisd(random.Uniform(-10, 10) * degree,
                                             Eigen::Vector3d::UnitY()));
    view.cam_from_board.translation =
        Eigen::Vector3d(0, 0, distance) -
        view.cam_from_board.rotation * Eigen::Vector3d(0.32, 0.24, 0.0);
    const cv::Mat grey = sim::RenderBoardImage(camera, view.cam_from_board,
                                               board, options, seed + 100 + i)
                             .image;
    cv::Mat bgr(grey.size(), CV_32FC3);
    const Eigen::Vector3d normal = view.cam_from_board.RotationMatrix().col(2);
    for (const Laser& laser : setup.lasers) {
      const double t =
          normal.dot(view.cam_from_board.translation - laser.origin_in_cam) /
          normal.dot(laser.direction_in_cam);
      view.spots.push_back(
          camera.ImgFromCam(laser.origin_in_cam + t * laser.direction_in_cam));
    }
    for (int r = 0; r < grey.rows; ++r) {
      for (int c = 0; c < grey.cols; ++c) {
        const float level = grey.at<uint8_t>(r, c);
        cv::Vec3f pixel(level, level, level);  // B, G, R
        for (const Eigen::Vector2d& spot : view.spots) {
          const double dx = c + 0.5 - spot.x();
          const double dy = r + 0.5 - spot.y();
          const double d2 = dx * dx + dy * dy;
          if (d2 > 100.0) continue;
          const float light = static_cast<float>(100.0 * std::exp(-d2 / 8.0));
          pixel += cv::Vec3f(0.10f * light, 0.15f * light, light);
        }
        bgr.at<cv::Vec3f>(r, c) = pixel;
      }
    }
    bgr.convertTo(view.bgr, CV_8UC3);
    views.push_back(view);
  }
  return views;
}

}  // namespace uw::testing_calibration
