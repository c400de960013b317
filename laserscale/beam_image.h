// A laser beam's image (LSD step 1): where the camera sees the beam's
// points between the nearest and farthest scene depths, as a polyline in
// pixels (COLMAP convention), and which beam a pixel belongs to.
#pragma once

#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "colmap_plugins/scene/model.h"
#include "laserscale/laser_setup.h"
#include "laserscale/spot_detector_options.h"

namespace uw::lsd {

// The beam's points at camera depths [min_range_m, max_range_m] that the
// camera model projects and unprojects consistently (a distortion that
// folds back would put them elsewhere).
// Up to 65 points, nearest first.
std::vector<Eigen::Vector2d> BeamImage(const Camera& camera, const Laser& laser,
                                       const SpotDetectorOptions& options);

// Distance from p to the polyline.
double DistanceToPolyline(const Eigen::Vector2d& p,
                          const std::vector<Eigen::Vector2d>& line);

// The unit direction of the polyline at its point nearest to p.
Eigen::Vector2d DirectionNear(const std::vector<Eigen::Vector2d>& line,
                              const Eigen::Vector2d& p);

// Whether `p` may be laser `own`'s spot: within max_distance of its beam
// and no closer to another's (where the beams converge, a neighbour's spot
// can lie within the margin).
bool OnOwnBeam(const Eigen::Vector2d& p,
               const std::vector<std::vector<Eigen::Vector2d>>& beams,
               size_t own, double max_distance);

}  // namespace uw::lsd
