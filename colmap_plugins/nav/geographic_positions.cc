#include "colmap_plugins/nav/geographic_positions.h"

#include <cmath>

#include <fmt/format.h>

#include "common/util/error.h"

namespace uw {

std::vector<Eigen::Vector3d> GeographicToLocal(
    const std::vector<Eigen::Vector3d>& positions,
    const std::vector<std::string>& names,
    const std::optional<GeoOrigin>& origin, const std::string& what,
    NavLogFrame* frame) {
  for (size_t i = 0; i < positions.size(); ++i) {
    const Eigen::Vector3d& p = positions[i];
    if (!(std::abs(p.x()) <= 90.0 && p.y() >= -180.0 && p.y() < 360.0)) {
      throw ErrorAt(what, ": image ", names.at(i), " has latitude ", p.x(),
                    " and longitude ", p.y(),
                    ": not degrees (metres in a file read as lat, lon, alt?)");
    }
  }
  if (positions.empty()) return {};
  const GeoOrigin used =
      origin ? *origin
             : AutomaticOrigin(positions.front().x(), positions.front().y());
  const LocalEnu local(used);
  std::vector<Eigen::Vector3d> enu;
  for (const Eigen::Vector3d& p : positions) {
    enu.push_back(local.FromGeodetic(p.x(), p.y(), p.z()));
  }
  if (frame != nullptr) {
    frame->position_columns = what;
    frame->origin = used;
    frame->origin_automatic = !origin.has_value();
  }
  return enu;
}

std::vector<PosePrior> WithLocalPositions(
    const std::vector<PosePrior>& priors,
    const std::optional<GeoOrigin>& origin, const std::string& database,
    NavLogFrame* frame, std::vector<std::string>* warnings) {
  std::vector<Eigen::Vector3d> positions;
  std::vector<std::string> names;
  size_t num_cartesian = 0;
  for (const PosePrior& prior : priors) {
    if (!prior.HasPosition()) continue;
    if (prior.coordinate_system == PosePriorCoordinateSystem::kWGS84) {
      positions.push_back(prior.position);
      names.push_back("id " + std::to_string(prior.image_id));
    } else {
      ++num_cartesian;
    }
  }
  if (positions.empty()) {
    if (origin) {
      throw ErrorAt(database,
                    ": --origin places geographic positions, but "
                    "none of its pose priors is WGS84");
    }
    return priors;
  }
  if (num_cartesian > 0) {
    throw ErrorAt(database, ": ", positions.size(),
                  " pose priors are WGS84 (latitude, longitude) and ",
                  num_cartesian,
                  " are not: two frames in one database cannot be aligned to");
  }
  const std::vector<Eigen::Vector3d> local = GeographicToLocal(
      positions, names, origin, "WGS84 pose priors of " + database, frame);
  std::vector<PosePrior> converted = priors;
  size_t next = 0;
  size_t num_dropped = 0;
  for (PosePrior& prior : converted) {
    if (!prior.HasPosition()) continue;
    prior.position = local[next++];
    prior.coordinate_system = PosePriorCoordinateSystem::kCartesian;
    if (prior.HasPositionCovariance()) {
      prior.position_covariance.setConstant(PosePrior::kNaN);
      ++num_dropped;
    }
  }
  if (num_dropped > 0 && warnings != nullptr) {
    warnings->push_back(fmt::format(
        "{}: the covariances of {} WGS84 pose priors are not used: COLMAP "
        "gives them no unit (deg² or m²); --position_sigma (model_aligner) "
        "or --Nav.position_sigma stands in",
        database, num_dropped));
  }
  return converted;
}

}  // namespace uw
