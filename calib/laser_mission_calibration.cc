#include "calib/laser_mission_calibration.h"

#include <algorithm>
#include <cmath>
#include <map>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <Eigen/Dense>

#include "calib/laser_line_fit.h"
#include "colmap_plugins/cameras/camera_models.h"
#include "common/util/error.h"
#include "common/util/random.h"
#include "laserscale/spot_ray.h"

namespace uw {
namespace {

constexpr double kDegree = M_PI / 180.0;

// Pixels per unit of normalised image coordinate at the image's centre.
double FocalLengthPx(const Camera& camera) {
  const Eigen::Vector2d centre = camera.ImgFromCam(Eigen::Vector3d(0, 0, 1));
  const Eigen::Vector2d step = camera.ImgFromCam(Eigen::Vector3d(1e-3, 0, 1));
  return (step - centre).norm() / 1e-3;
}

// A square root of a 2x2 covariance (zero for a zero covariance).
Eigen::Matrix2d SquareRoot(const Eigen::Matrix2d& covariance) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(covariance);
  return eigen.eigenvectors() *
         eigen.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal();
}

Eigen::Vector3d Forward(const Eigen::Vector3d& direction) {
  return direction.z() < 0.0 ? Eigen::Vector3d(-direction) : direction;
}

}  // namespace

void MissionCalibrationOptions::Check() const {
  if (num_iterations < 2) {
    throw Error("lasers from mission: num_iterations must be >= 2");
  }
  if (!(inlier_px > 0.0)) {
    throw Error("lasers from mission: inlier_px must be > 0");
  }
  if (ransac_iterations < 1) {
    throw Error("lasers from mission: ransac_iterations must be >= 1");
  }
  if (min_spots < 3) throw Error("lasers from mission: min_spots must be >= 3");
  if (!(min_depth_ratio > 1.0)) {
    throw Error("lasers from mission: min_depth_ratio must be > 1");
  }
}

double BeamImageDistancePx(const Camera& camera, const Laser& laser,
                           const Eigen::Vector2d& spot_px) {
  const Eigen::Vector3d ray =
      CameraModelCamFromImg(camera.model_id, camera.params.data(), spot_px);
  const Eigen::Vector3d x(ray.x() / ray.z(), ray.y() / ray.z(), 1.0);
  const Eigen::Vector3d normal =
      laser.origin_in_cam.cross(laser.direction_in_cam);
  const double f = FocalLengthPx(camera);
  const double length = normal.head<2>().norm();
  if (length < 1e-12) {
    // A beam through the camera centre images to its vanishing point.
    const Eigen::Vector3d& d = laser.direction_in_cam;
    return f * (x.head<2>() - d.head<2>() / d.z()).norm();
  }
  return f * std::abs(normal.dot(x)) / length;
}

MissionLaserCalibration CalibrateLaserFromMission(
    const Laser& a_priori, const RayCaster& caster,
    const std::vector<MissionSpot>& spots,
    const MissionCalibrationOptions& options) {
  options.Check();
  const std::string& name = a_priori.name;
  MissionLaserCalibration result;
  result.laser = a_priori;
  const size_t n = spots.size();
  result.points_in_cam.assign(n, Eigen::Vector3d::Zero());
  result.inliers.assign(n, false);
  result.problems.assign(n, "");

  // Each spot's point in its camera frame, and how far from a line it may
  // lie: inlier_px seen from its camera, in model units.
  std::vector<size_t> hit_spots;
  std::vector<Eigen::Vector3d> points;
  std::vector<double> tolerance;
  for (size_t k = 0; k < n; ++k) {
    const MissionSpot& spot = spots[k];
    const SpotHit hit =
        CastSpot(caster, spot.camera, spot.cam_from_world, spot.pixel);
    if (!hit.point_in_world) {
      result.problems[k] = hit.problem;
      continue;
    }
    const Eigen::Vector3d point = spot.cam_from_world * *hit.point_in_world;
    result.points_in_cam[k] = point;
    hit_spots.push_back(k);
    points.push_back(point);
    tolerance.push_back(options.inlier_px * point.z() /
                        FocalLengthPx(spot.camera));
  }
  if (static_cast<int>(points.size()) < options.min_spots) {
    throw ErrorAt("laser ", name, ": ", points.size(), " of ", n,
                  " spots meet the surface; at least ", options.min_spots,
                  " are needed");
  }
  std::vector<double> depths;
  for (const Eigen::Vector3d& point : points) depths.push_back(point.z());
  std::nth_element(depths.begin(), depths.begin() + depths.size() / 2,
                   depths.end());
  const double median_depth = depths[depths.size() / 2];
  // Pairs closer in depth than half the required span define no direction.
  const RobustLine line = FitRobustLine(
      points, tolerance, 0.5 * (options.min_depth_ratio - 1.0) * median_depth,
      options.ransac_iterations, options.seed);
  std::vector<size_t> inlier_spots;
  result.min_depth = std::numeric_limits<double>::infinity();
  result.max_depth = 0.0;
  for (size_t i = 0; i < hit_spots.size(); ++i) {
    const size_t k = hit_spots[i];
    if (!line.inliers[i]) {
      result.problems[k] = "off the line fitted to the other spots";
      continue;
    }
    result.inliers[k] = true;
    inlier_spots.push_back(k);
    result.min_depth = std::min(result.min_depth, points[i].z());
    result.max_depth = std::max(result.max_depth, points[i].z());
  }
  result.num_inliers = static_cast<int>(inlier_spots.size());
  if (result.num_inliers < options.min_spots ||
      result.max_depth < options.min_depth_ratio * result.min_depth) {
    throw ErrorAt("laser ", name, ": ", result.num_inliers, " of ",
                  points.size(), " spots on the surface line up, over depths ",
                  result.num_inliers > 0 ? result.min_depth : 0.0, " to ",
                  result.max_depth, " (model units); at least ",
                  options.min_spots, " spots and a farthest ",
                  options.min_depth_ratio,
                  " times as deep as the nearest are needed for a direction");
  }
  result.laser.direction_in_cam = Forward(line.laser.direction_in_cam);

  // Monte Carlo: every inlier spot drawn from its covariance, re-cast and
  // the line re-fitted to the same spots. Iteration i draws from its own
  // counter-based stream, so the result does not depend on the threads.
  std::vector<Eigen::Matrix2d> roots;
  for (const size_t k : inlier_spots) {
    roots.push_back(SquareRoot(spots[k].covariance_px));
  }
  std::vector<Eigen::Vector3d> samples(options.num_iterations);
  std::vector<char> valid(options.num_iterations, 0);
  const auto run = [&](const tbb::blocked_range<int>& range) {
    for (int it = range.begin(); it != range.end(); ++it) {
      SplitMix64Stream random(SplitMix64(options.seed + 1 + it));
      std::vector<Eigen::Vector3d> drawn;
      for (size_t i = 0; i < inlier_spots.size(); ++i) {
        const MissionSpot& spot = spots[inlier_spots[i]];
        const Eigen::Vector2d pixel =
            spot.pixel + roots[i] * random.GaussianPair();
        const SpotHit hit =
            CastSpot(caster, spot.camera, spot.cam_from_world, pixel);
        if (hit.point_in_world) {
          drawn.push_back(spot.cam_from_world * *hit.point_in_world);
        }
      }
      if (static_cast<int>(drawn.size()) < options.min_spots) continue;
      samples[it] = Forward(FitLineByDepth(drawn).laser.direction_in_cam);
      valid[it] = 1;
    }
  };
  tbb::task_arena arena(options.num_threads > 0 ? options.num_threads
                                                : tbb::task_arena::automatic);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<int>(0, options.num_iterations, 16),
                      run);
  });
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (int it = 0; it < options.num_iterations; ++it) {
    if (valid[it]) {
      mean += samples[it];
      ++result.num_iterations_used;
    }
  }
  if (result.num_iterations_used < 2) {
    throw ErrorAt("laser ", name,
                  ": the Monte Carlo's re-cast spots missed the surface in "
                  "all but ",
                  result.num_iterations_used, " of ", options.num_iterations,
                  " iterations");
  }
  mean /= result.num_iterations_used;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (int it = 0; it < options.num_iterations; ++it) {
    if (!valid[it]) continue;
    const Eigen::Vector3d offset = samples[it] - mean;
    covariance += offset * offset.transpose();
  }
  covariance /= result.num_iterations_used - 1;
  // lasers.json keeps a unit direction's covariance across the beam.
  const Eigen::Vector3d& d = result.laser.direction_in_cam;
  const Eigen::Matrix3d across =
      Eigen::Matrix3d::Identity() - d * d.transpose();
  result.laser.direction_cov = across * covariance * across;
  result.laser.direction_cov = 0.5 * (result.laser.direction_cov +
                                      result.laser.direction_cov.transpose());
  result.sigma_deg = std::sqrt(result.laser.direction_cov.trace()) / kDegree;
  result.angle_from_a_priori_deg =
      std::atan2(d.cross(a_priori.direction_in_cam).norm(),
                 d.dot(a_priori.direction_in_cam)) /
      kDegree;

  // The image-line check, per dive.
  std::map<int, std::pair<int, double>> by_dive;  // count, sum of squares
  double sum = 0.0;
  for (const size_t k : inlier_spots) {
    const double distance =
        BeamImageDistancePx(spots[k].camera, result.laser, spots[k].pixel);
    auto& [count, squares] = by_dive[spots[k].dive];
    ++count;
    squares += distance * distance;
    sum += distance * distance;
  }
  for (const auto& [dive, entry] : by_dive) {
    result.rms_by_dive.push_back(
        {dive, entry.first, std::sqrt(entry.second / entry.first)});
  }
  result.rms_px = std::sqrt(sum / inlier_spots.size());
  return result;
}

}  // namespace uw
