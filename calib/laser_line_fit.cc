#include "calib/laser_line_fit.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

#include "colmap_plugins/cameras/camera_models.h"
#include "common/util/error.h"
#include "common/util/random.h"

namespace uw {
namespace {

// Distance of `point` from the line through `a` with unit direction `d`.
double DistanceFromLine(const Eigen::Vector3d& point, const Eigen::Vector3d& a,
                        const Eigen::Vector3d& d) {
  const Eigen::Vector3d offset = point - a;
  return (offset - offset.dot(d) * d).norm();
}

}  // namespace

void LaserLineFitOptions::Check() const {
  if (!(inlier_distance_m > 0.0)) {
    throw Error("laser line fit: inlier_distance_m must be > 0");
  }
  if (ransac_iterations < 1) {
    throw Error("laser line fit: ransac_iterations must be >= 1");
  }
  if (min_distances < 3) {
    throw Error("laser line fit: min_distances must be >= 3");
  }
}

RobustLine FitRobustLine(const std::vector<Eigen::Vector3d>& points_in_cam,
                         const std::vector<double>& tolerance,
                         double min_pair_depth_gap, int ransac_iterations,
                         uint64_t seed) {
  const int n = static_cast<int>(points_in_cam.size());
  if (n < 3 || tolerance.size() != points_in_cam.size()) {
    throw ErrorAt("line fit: ", n, " points (and ", tolerance.size(),
                  " tolerances); needs at least 3");
  }
  RobustLine fit;
  // RANSAC on pairs far enough apart in depth to define a direction.
  SplitMix64Stream random(seed);
  fit.inliers.assign(n, false);
  int best_count = 0;
  for (int iteration = 0; iteration < ransac_iterations; ++iteration) {
    const int i = static_cast<int>(random.Next() % n);
    const int j = static_cast<int>(random.Next() % n);
    const Eigen::Vector3d& a = points_in_cam[i];
    const Eigen::Vector3d& b = points_in_cam[j];
    if (std::abs(a.z() - b.z()) < min_pair_depth_gap) continue;
    const Eigen::Vector3d d = (b - a).normalized();
    std::vector<bool> inliers(n);
    int count = 0;
    for (int k = 0; k < n; ++k) {
      inliers[k] = DistanceFromLine(points_in_cam[k], a, d) <= tolerance[k];
      count += inliers[k];
    }
    if (count > best_count) {
      best_count = count;
      fit.inliers = inliers;
    }
  }
  if (best_count < 3) {
    fit.num_inliers = best_count;
    return fit;
  }
  std::vector<Eigen::Vector3d> inlier_points;
  for (int k = 0; k < n; ++k) {
    if (fit.inliers[k]) inlier_points.push_back(points_in_cam[k]);
  }
  RobustLine line = FitLineByDepth(inlier_points);
  line.inliers = fit.inliers;
  return line;
}

RobustLine FitLineByDepth(const std::vector<Eigen::Vector3d>& points_in_cam) {
  const int n = static_cast<int>(points_in_cam.size());
  if (n < 3) throw ErrorAt("line fit: ", n, " points; needs at least 3");
  RobustLine fit;
  fit.inliers.assign(n, true);
  fit.num_inliers = n;
  // x = Ox + a z and y = Oy + b z by weighted least squares on the inliers.
  // A point's error grows with its depth (the spot's angular noise; a
  // board's pose, a model's surface), so each is weighted by 1/z^2.
  Eigen::MatrixXd design(n, 2);
  Eigen::VectorXd xs(n);
  Eigen::VectorXd ys(n);
  Eigen::VectorXd weights(n);
  for (int k = 0, row = 0; k < n; ++k) {
    const Eigen::Vector3d& point = points_in_cam[k];
    design.row(row) << 1.0, point.z();
    xs(row) = point.x();
    ys(row) = point.y();
    weights(row) = 1.0 / (point.z() * point.z());
    ++row;
  }
  const Eigen::MatrixXd weighted_design_t =
      design.transpose() * weights.asDiagonal();
  const Eigen::Matrix2d normal_inverse = (weighted_design_t * design).inverse();
  const Eigen::Vector2d x_fit = normal_inverse * weighted_design_t * xs;
  const Eigen::Vector2d y_fit = normal_inverse * weighted_design_t * ys;
  const Eigen::VectorXd x_residuals = design * x_fit - xs;
  const Eigen::VectorXd y_residuals = design * y_fit - ys;
  const double weighted_squares =
      x_residuals.dot(weights.asDiagonal() * x_residuals) +
      y_residuals.dot(weights.asDiagonal() * y_residuals);
  const int dof = 2 * n - 4;
  const double variance = dof > 0 ? weighted_squares / dof : 0.0;
  fit.rms_distance =
      std::sqrt((x_residuals.squaredNorm() + y_residuals.squaredNorm()) / n);

  Laser& laser = fit.laser;
  laser.origin_in_cam = Eigen::Vector3d(x_fit(0), y_fit(0), 0.0);
  const Eigen::Vector3d slope(x_fit(1), y_fit(1), 1.0);
  laser.direction_in_cam = slope.normalized();
  // Covariances of (Ox, a) and (Oy, b); x and y are fitted independently.
  const Eigen::Matrix2d parameter_cov = variance * normal_inverse;
  laser.origin_cov.setZero();
  laser.origin_cov(0, 0) = parameter_cov(0, 0);
  laser.origin_cov(1, 1) = parameter_cov(0, 0);
  // The unit direction's covariance through d = s / |s|, s = (a, b, 1).
  const double norm = slope.norm();
  const Eigen::Matrix3d unit_jacobian =
      (Eigen::Matrix3d::Identity() -
       laser.direction_in_cam * laser.direction_in_cam.transpose()) /
      norm;
  Eigen::Matrix3d slope_cov = Eigen::Matrix3d::Zero();
  slope_cov(0, 0) = parameter_cov(1, 1);
  slope_cov(1, 1) = parameter_cov(1, 1);
  laser.direction_cov = unit_jacobian * slope_cov * unit_jacobian.transpose();
  laser.direction_cov =
      0.5 * (laser.direction_cov + laser.direction_cov.transpose());
  return fit;
}

LaserLineFit FitLaserLine(const std::string& name, const Camera& camera,
                          const std::vector<LaserBoardSpot>& spots,
                          const LaserLineFitOptions& options) {
  options.Check();
  LaserLineFit fit;
  fit.laser.name = name;
  for (const LaserBoardSpot& spot : spots) {
    if (!spot.pixel.allFinite()) {
      throw ErrorAt("laser ", name, ": ", spot.image,
                    ": the spot's pixel is not finite");
    }
    const Eigen::Vector3d ray = CameraModelCamFromImg(
        camera.model_id, camera.params.data(), spot.pixel);
    const Eigen::Vector3d normal = spot.cam_from_board.RotationMatrix().col(2);
    const double along = normal.dot(ray.normalized());
    if (std::abs(along) < 1e-3) {
      throw ErrorAt("laser ", name, ": ", spot.image,
                    ": the spot's ray runs along the board");
    }
    const double s =
        normal.dot(spot.cam_from_board.translation) / normal.dot(ray);
    if (!(s > 0.0)) {
      throw ErrorAt("laser ", name, ": ", spot.image,
                    ": the board is behind the camera");
    }
    fit.points_in_cam.push_back(s * ray);
  }
  const int n = static_cast<int>(fit.points_in_cam.size());
  if (n < options.min_distances) {
    throw ErrorAt("laser ", name, ": ", n, " spots; a line needs at least ",
                  options.min_distances, " board distances");
  }

  const RobustLine line = FitRobustLine(
      fit.points_in_cam,
      std::vector<double>(fit.points_in_cam.size(), options.inlier_distance_m),
      0.5 * options.min_depth_span_m, options.ransac_iterations, options.seed);
  fit.inliers = line.inliers;
  double min_z = std::numeric_limits<double>::infinity();
  double max_z = -std::numeric_limits<double>::infinity();
  for (int k = 0; k < n; ++k) {
    if (!fit.inliers[k]) continue;
    min_z = std::min(min_z, fit.points_in_cam[k].z());
    max_z = std::max(max_z, fit.points_in_cam[k].z());
  }
  if (line.num_inliers < options.min_distances ||
      max_z - min_z < options.min_depth_span_m) {
    throw ErrorAt("laser ", name, ": the spots do not line up over ",
                  options.min_depth_span_m, " m of depth (", line.num_inliers,
                  " of ", n,
                  " within the inlier distance); move the board further "
                  "between images");
  }
  fit.laser = line.laser;
  fit.laser.name = name;
  fit.rms_distance_m = line.rms_distance;
  return fit;
}

std::vector<LaserLineFit> FitLaserLines(
    const Camera& camera, const std::vector<LaserBoardSpot>& spots,
    int num_lasers, const LaserLineFitOptions& options) {
  if (num_lasers < 1) throw Error("laser line fit: num_lasers must be >= 1");
  std::vector<LaserBoardSpot> remaining = spots;
  std::vector<LaserLineFit> fits;
  for (int l = 0; l < num_lasers; ++l) {
    LaserLineFit fit = FitLaserLine(
        "laser " + std::to_string(l + 1) + " of " + std::to_string(num_lasers),
        camera, remaining, options);
    std::vector<LaserBoardSpot> rest;
    std::vector<LaserBoardSpot> own;
    for (size_t k = 0; k < remaining.size(); ++k) {
      (fit.inliers[k] ? own : rest).push_back(remaining[k]);
    }
    // Refitted on its own spots alone: the inlier and point lists are then
    // those of its spots.
    fit = FitLaserLine(fit.laser.name, camera, own, options);
    fits.push_back(std::move(fit));
    remaining = std::move(rest);
  }
  std::sort(fits.begin(), fits.end(),
            [](const LaserLineFit& a, const LaserLineFit& b) {
              const auto angle = [](const LaserLineFit& f) {
                return std::atan2(f.laser.origin_in_cam.y(),
                                  f.laser.origin_in_cam.x());
              };
              return angle(a) < angle(b);
            });
  for (size_t l = 0; l < fits.size(); ++l) {
    fits[l].laser.name = "L" + std::to_string(l);
  }
  return fits;
}

}  // namespace uw
