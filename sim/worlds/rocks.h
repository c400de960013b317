// Boulders on a heightfield: rounded, irregular, partly buried bumps.
#pragma once

#include <functional>
#include <string>

#include <Eigen/Core>

#include "common/util/random.h"
#include "sim/worlds/height_grid.h"

namespace uw::sim {

// Diameters follow a power law (many small, few large).
struct RockOptions {
  int count = 40;
  double min_diameter_m = 0.2;
  double max_diameter_m = 1.0;

  // `where` names the section in messages ("seafloor.rocks").
  void Check(const std::string& where) const;
};

// Where a rock of some radius may lie, by its centre.
using RockPlace = std::function<bool(const Eigen::Vector2d& centre, double)>;

// Anywhere further than keep_out_radius from the origin (0: anywhere).
RockPlace OutsideDisc(double keep_out_radius);

// Boulders merged into a heightfield: each is a superellipsoid cap with
// an irregular outline and a bumpy top, partly buried in the local ground
// (`ground`(x, y), the surface without rocks), and the surface is the
// higher of ground and rock. A rock for which 64 draws of its centre find
// no place `allowed` is left out.
void AddRocks(const RockOptions& options,
              const std::function<double(double, double)>& ground,
              const RockPlace& allowed, SplitMix64Stream& random,
              HeightGrid* grid);

}  // namespace uw::sim
