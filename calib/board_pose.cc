#include "calib/board_pose.h"

#include <Eigen/Geometry>
#include <opencv2/calib3d.hpp>

#include "colmap_plugins/cameras/camera_models.h"

namespace uw {

std::optional<Rigid3d> EstimateBoardPose(const Camera& camera,
                                         const CalibrationBoard& board,
                                         const BoardObservation& observation) {
  if (!observation.Found()) return std::nullopt;
  const std::vector<Eigen::Vector3d> corners = board.CornersInBoard();
  std::vector<cv::Point3d> object_points;
  std::vector<cv::Point2d> normalised;
  for (size_t k = 0; k < corners.size(); ++k) {
    if (observation.weights[k] <= 0.0) continue;
    const Eigen::Vector3d ray = CameraModelCamFromImg(
        camera.model_id, camera.params.data(),
        observation.pixels[k] + Eigen::Vector2d(0.5, 0.5));
    if (!(ray.z() > 0.0)) continue;
    object_points.emplace_back(corners[k].x(), corners[k].y(), corners[k].z());
    normalised.emplace_back(ray.x() / ray.z(), ray.y() / ray.z());
  }
  if (object_points.size() < 4) return std::nullopt;
  cv::Mat rvec;
  cv::Mat tvec;
  if (!cv::solvePnP(object_points, normalised, cv::Mat::eye(3, 3, CV_64F),
                    cv::Mat(), rvec, tvec, false, cv::SOLVEPNP_ITERATIVE)) {
    return std::nullopt;
  }
  const Eigen::Vector3d r(rvec.at<double>(0), rvec.at<double>(1),
                          rvec.at<double>(2));
  Rigid3d cam_from_board;
  cam_from_board.rotation =
      r.norm() > 0.0
          ? Eigen::Quaterniond(Eigen::AngleAxisd(r.norm(), r.normalized()))
          : Eigen::Quaterniond::Identity();
  cam_from_board.translation = Eigen::Vector3d(
      tvec.at<double>(0), tvec.at<double>(1), tvec.at<double>(2));
  if (!(cam_from_board.translation.z() > 0.0)) return std::nullopt;
  return cam_from_board;
}

}  // namespace uw
