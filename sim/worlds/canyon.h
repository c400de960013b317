// The canyon world: a ~60 m long winding canyon along x, a 6-10 m wide
// rocky floor between two steep rough walls 8-15 m high, open at both
// ends, like the thesis's Sant Feliu canyon.
#pragma once

#include "common/util/random.h"
#include "sim/worlds/relief.h"
#include "sim/worlds/rocks.h"

namespace uw::sim {

// A canyon winding along x: its axis y = c(x) meanders within
// +-meander_amplitude_m. Across it: a floor floor_width_m wide (at z = 0),
// walls rising at wall_slope_deg with rounded foot and rim, and a rim
// plateau out to y = +-width_m / 2. Each wall's height varies along the
// canyon within wall_height_m +- wall_height_variation_m; the walls'
// horizontal position wanders by up to wall_relief_m (buttresses, gullies,
// ledges). Rocks lie on the floor only.
struct CanyonOptions {
  double length_m = 60.0;  // along x
  double width_m = 36.0;   // along y, rims included
  double floor_width_m = 8.0;
  double wall_height_m = 11.0;
  double wall_height_variation_m = 2.5;
  double wall_slope_deg = 65.0;
  double meander_amplitude_m = 2.5;
  double meander_wavelength_m = 36.0;
  double wall_relief_m = 0.8;
  double wall_relief_wavelength_m = 4.0;
  // 6 cm: ~1.2 M triangles; walls are heightfield cells stretched ~2.4x.
  double vertex_spacing_m = 0.06;
  ReliefOptions relief = {0.2, 6.0, 0.05, 0.6};
  RockOptions rocks = {40, 0.3, 1.6};

  void Check() const;
};

struct World;  // sim/world.h
// Floor, walls and rims as one heightfield; `options` are checked
// (MakeWorld).
World MakeCanyon(const CanyonOptions& options, SplitMix64Stream& random);

}  // namespace uw::sim
