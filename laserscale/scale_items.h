// What a laser image measures, method by method: the "items" whose scale
// each estimator gives (a laser for FUM, a pair of lasers for PCM and the
// direct baseline, the four lasers together for Davis-Tusting), and their
// evaluation from spots, a pose, a calibration and the model's mesh (the
// chain "ray casting, origin estimation, scale" of ch4 spec §4.2 d-e).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "colmap_plugins/scene/model.h"
#include "common/mesh/ray_caster.h"
#include "laserscale/laser_setup.h"

namespace uw {

enum class ScaleMethod { kFum, kPcm, kDirect, kDavisTusting };
std::string ScaleMethodName(ScaleMethod method);  // fum, pcm, direct, ...
// Throws uw::Error listing the names for an unknown one.
ScaleMethod ScaleMethodFromName(const std::string& name);

struct ScaleItem {
  std::string name;           // "L1" (FUM), "L1-L2" (pairs), "all" (DT)
  std::vector<int> lasers;    // indices into the set-up's lasers
  double known_length_m = 0;  // pairs: the separation the method compares
};

// FUM: one item per laser. PCM: the pairs whose origins are equidistant
// from the optical centre to within pcm_equidistance_m (the thesis's
// precondition [L3301-L3304]), with their perpendicular separation across
// the pair's mean direction. A pair symmetric about the centre is exact;
// any other pair (the adjacent lasers of a square) errs where the hits'
// depths differ, by up to several % on rough terrain (thesis: 1.5-2.9 %).
// Whether the beams are parallel is the calibration's business; a
// non-parallel pair shows as a distance-dependent bias. Direct: every pair,
// with the distance between the origins. Davis-Tusting: one item of the
// four lasers (its own checks refuse other set-ups). Throws uw::Error when
// a method has no item on this set-up.
std::vector<ScaleItem> ScaleItems(ScaleMethod method, const LaserSetup& setup,
                                  double pcm_equidistance_m = 0.01);

// One spot per laser of the set-up (std::nullopt: not detected).
using SpotPixels = std::vector<std::optional<Eigen::Vector2d>>;

struct ItemScale {
  std::optional<double> scale;  // s = m / m̂; see scale_estimators.h
  std::string problem;          // why there is none
};

// The items' scales for one pose, one calibration and one set of spots.
// Spots are cast onto the mesh through `camera` (spot_ray.h); an item
// without all its spots, or whose ray misses, has no scale and says why.
std::vector<ItemScale> EvaluateItems(ScaleMethod method,
                                     const std::vector<ScaleItem>& items,
                                     const std::vector<Laser>& lasers,
                                     const RayCaster& caster,
                                     const Camera& camera,
                                     const Rigid3d& cam_from_world,
                                     const SpotPixels& spots);

}  // namespace uw
