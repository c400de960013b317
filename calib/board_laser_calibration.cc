#include "calib/board_laser_calibration.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <optional>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "calib/board_detection.h"
#include "calib/board_pose.h"
#include "common/util/error.h"

namespace uw {

void BoardLaserCalibrationOptions::Check() const {
  spots.Check();
  fit.Check();
}

BoardLaserCalibration CalibrateLasersFromBoardImages(
    const Camera& camera, const CalibrationBoard& board,
    const std::string& images_dir, const std::vector<std::string>& names,
    const BoardLaserCalibrationOptions& options,
    const BoardLaserImageCallback& on_image) {
  BoardLaserCalibration result;
  std::vector<LaserBoardSpot> spots;
  for (const std::string& name : names) {
    const std::filesystem::path path = std::filesystem::path(images_dir) / name;
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
        FindColourSpots(bgr, options.spots);
    if (on_image) on_image(name, pose.has_value(), found.size());
    if (!pose) continue;
    ++result.num_images_with_board;
    for (const Eigen::Vector2d& pixel : found) {
      spots.push_back({name, *pose, pixel});
    }
  }
  if (result.num_images_with_board < options.fit.min_distances) {
    throw ErrorAt(images_dir, ": the board was found in ",
                  result.num_images_with_board, " of ", names.size(),
                  " images; at least ", options.fit.min_distances,
                  " distances are needed; nothing written");
  }
  result.fits = FitLaserLines(camera, spots, options.num_lasers, options.fit);
  result.setup.name = options.setup_name;
  for (LaserLineFit& fit : result.fits) {
    fit.laser.colour = options.spots.colour;
    result.setup.lasers.push_back(fit.laser);
  }
  result.setup.Check();
  return result;
}

std::string DescribeLaserLineFit(const LaserLineFit& fit) {
  double min_z = 1e300;
  double max_z = 0.0;
  for (const Eigen::Vector3d& p : fit.points_in_cam) {
    min_z = std::min(min_z, p.z());
    max_z = std::max(max_z, p.z());
  }
  const Laser& laser = fit.laser;
  return fmt::format(
      "laser {}: {} spots from {:.2f} to {:.2f} m; origin ({:.4f}, {:.4f}) m "
      "(sigma {:.2f} mm), direction ({:.5f}, {:.5f}, {:.5f}) (sigma {:.4f} "
      "deg); line RMS {:.2f} mm",
      laser.name, fit.points_in_cam.size(), min_z, max_z,
      laser.origin_in_cam.x(), laser.origin_in_cam.y(),
      1000.0 * std::sqrt(laser.origin_cov.trace()), laser.direction_in_cam.x(),
      laser.direction_in_cam.y(), laser.direction_in_cam.z(),
      std::sqrt(laser.direction_cov.trace()) * 180.0 / M_PI,
      1000.0 * fit.rms_distance_m);
}

}  // namespace uw
