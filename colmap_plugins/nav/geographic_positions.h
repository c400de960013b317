// Positions given as latitude, longitude and height — COLMAP's GPS
// references (model_aligner --ref_is_gps 1) and its WGS84 pose priors — put
// into the local east-north-up frame (m) the adjuster and the aligner work
// in, at a stated origin or the automatic one a geographic nav.csv gets
// (geodesy.h). docs/formats.md, "Geographic logs".
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "colmap_plugins/nav/geodesy.h"
#include "colmap_plugins/nav/nav_csv.h"
#include "colmap_plugins/scene/database.h"

namespace uw {

// Converts each (latitude deg, longitude deg, height m) of `positions` to
// east-north-up metres at `origin`, or at AutomaticOrigin of the first one.
// `frame` receives the origin and `what` as its position columns. Throws
// uw::Error naming names[i] when a latitude or longitude is out of range
// (x,y,z metres given for degrees).
std::vector<Eigen::Vector3d> GeographicToLocal(
    const std::vector<Eigen::Vector3d>& positions,
    const std::vector<std::string>& names,
    const std::optional<GeoOrigin>& origin, const std::string& what,
    NavLogFrame* frame);

// A database's pose priors with their WGS84 positions in the local frame
// (coordinate system then cartesian); unchanged when none is WGS84. The
// covariance of a WGS84 prior is dropped, since COLMAP defines no unit for
// it (deg² or m²): `warnings` says how many were, and the caller's
// --position_sigma then stands in. Throws uw::Error when the database
// mixes WGS84 and cartesian priors (two frames), or when an origin is
// given for priors none of which is WGS84 (it would be ignored). `database`
// names it in messages; `frame` (if any) receives the origin.
std::vector<PosePrior> WithLocalPositions(
    const std::vector<PosePrior>& priors,
    const std::optional<GeoOrigin>& origin, const std::string& database,
    NavLogFrame* frame, std::vector<std::string>* warnings);

}  // namespace uw
