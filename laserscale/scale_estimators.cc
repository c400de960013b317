#include "laserscale/scale_estimators.h"

#include <cmath>
#include <sstream>

#include <Eigen/Geometry>
#include <Eigen/QR>

namespace uw {
namespace {

bool Finite(const Eigen::Vector3d& v) { return v.allFinite(); }

ScaleEstimate Invalid(const std::string& problem) { return {{}, problem}; }

// m / m̂ when both are positive and finite.
ScaleEstimate Ratio(double known, double measured, const char* what) {
  if (!(std::isfinite(measured) && measured > 0.0)) {
    std::ostringstream message;
    message << what << " measured through the model is " << measured;
    return Invalid(message.str());
  }
  return {known / measured, ""};
}

}  // namespace

ScaleEstimate FumScale(const Laser& laser, const Eigen::Vector3d& hit_in_cam) {
  if (!Finite(hit_in_cam)) return Invalid("the hit is not finite");
  if (!(hit_in_cam.z() > 0.0)) {
    return Invalid("the hit is not in front of the camera (z <= 0)");
  }
  const Eigen::Vector3d& v = laser.direction_in_cam;
  const double known = laser.origin_in_cam.norm();
  // Beams nearly parallel to Π trace back to no point of it; a laser at the
  // optical centre has no displacement to compare.
  if (!(Finite(v) && v.z() > 1e-6 * v.norm())) {
    return Invalid("laser '" + laser.name +
                   "' runs parallel to the camera plane: no origin on it");
  }
  if (!(std::isfinite(known) && known > 0.0)) {
    return Invalid("laser '" + laser.name +
                   "' starts at the optical centre: FUM needs its origin "
                   "displaced from it");
  }
  const Eigen::Vector3d origin_estimate =
      hit_in_cam - (hit_in_cam.z() / v.z()) * v;
  return Ratio(known, origin_estimate.norm(),
               "the laser origin's distance from the optical centre");
}

ScaleEstimate PcmScale(const Eigen::Vector3d& hit1_in_world,
                       const Eigen::Vector3d& hit2_in_world,
                       const Eigen::Vector3d& camera_center_in_world,
                       double separation_m) {
  if (!Finite(hit1_in_world) || !Finite(hit2_in_world) ||
      !Finite(camera_center_in_world)) {
    return Invalid("a hit or the camera centre is not finite");
  }
  if (!(std::isfinite(separation_m) && separation_m > 0.0)) {
    return Invalid("the lasers' separation must be positive");
  }
  const Eigen::Vector3d between = hit2_in_world - hit1_in_world;
  const Eigen::Vector3d to_middle =
      0.5 * (hit1_in_world + hit2_in_world) - camera_center_in_world;
  if (!(to_middle.norm() > 0.0)) {
    return Invalid("the hits' midpoint is the camera centre");
  }
  // |between| sin(α): the part of `between` perpendicular to the beams.
  const double perpendicular = between.cross(to_middle.normalized()).norm();
  return Ratio(separation_m, perpendicular,
               "the beams' perpendicular separation");
}

ScaleEstimate DirectScale(const Eigen::Vector3d& hit1_in_world,
                          const Eigen::Vector3d& hit2_in_world,
                          double separation_m) {
  if (!Finite(hit1_in_world) || !Finite(hit2_in_world)) {
    return Invalid("a hit is not finite");
  }
  if (!(std::isfinite(separation_m) && separation_m > 0.0)) {
    return Invalid("the lasers' separation must be positive");
  }
  return Ratio(separation_m, (hit2_in_world - hit1_in_world).norm(),
               "the distance between the hits");
}

ScaleEstimate DavisTustingScale(
    const std::vector<Laser>& lasers,
    const std::vector<Eigen::Vector2d>& spots_normalized,
    const std::vector<Eigen::Vector3d>& hits_in_world) {
  if (lasers.size() != 4 || spots_normalized.size() != 4 ||
      hits_in_world.size() != 4) {
    return Invalid("Davis-Tusting needs the spots and hits of four lasers");
  }
  const double min_cos = std::cos(kDavisTustingMaxAxisAngleDeg * M_PI / 180.0);
  for (const Laser& laser : lasers) {
    if (!(laser.direction_in_cam.normalized().z() >= min_cos)) {
      std::ostringstream message;
      message << "Davis-Tusting needs lasers parallel to the optical axis; '"
              << laser.name << "' is "
              << std::acos(
                     std::min(1.0, laser.direction_in_cam.normalized().z())) *
                     180.0 / M_PI
              << " deg off it";
      return Invalid(message.str());
    }
  }
  for (int i = 0; i < 4; ++i) {
    if (!spots_normalized[i].allFinite() || !Finite(hits_in_world[i])) {
      return Invalid("a spot or a hit is not finite");
    }
  }
  Eigen::Matrix<double, 6, 3> design;
  Eigen::Matrix<double, 6, 1> inverse_depths;
  int row = 0;
  for (int i = 0; i < 4; ++i) {
    for (int j = i + 1; j < 4; ++j, ++row) {
      const double spacing = (spots_normalized[i] - spots_normalized[j]).norm();
      const double baseline =
          (lasers[i].origin_in_cam - lasers[j].origin_in_cam).norm();
      if (!(spacing > 0.0 && baseline > 0.0)) {
        return Invalid("two lasers or two spots coincide");
      }
      const Eigen::Vector2d middle =
          0.5 * (spots_normalized[i] + spots_normalized[j]);
      design.row(row) << 1.0, middle.x(), middle.y();
      inverse_depths(row) = spacing / baseline;
    }
  }
  const Eigen::Vector3d plane =
      design.colPivHouseholderQr().solve(inverse_depths);
  std::vector<Eigen::Vector3d> on_plane;
  for (const Eigen::Vector2d& n : spots_normalized) {
    const double inverse_depth = plane.dot(Eigen::Vector3d(1.0, n.x(), n.y()));
    if (!(inverse_depth > 0.0)) {
      return Invalid("the fitted plane passes behind the camera at a spot");
    }
    on_plane.push_back(Eigen::Vector3d(n.x(), n.y(), 1.0) / inverse_depth);
  }
  double metres = 0.0;
  double model = 0.0;
  for (int i = 0; i < 4; ++i) {
    for (int j = i + 1; j < 4; ++j) {
      metres += (on_plane[i] - on_plane[j]).norm();
      model += (hits_in_world[i] - hits_in_world[j]).norm();
    }
  }
  return Ratio(metres, model, "the distances between the hits");
}

}  // namespace uw
