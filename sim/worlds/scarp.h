// The scarp world: a ~300 m long, ~10 m high fault wall dipping ~82 deg,
// facing -y, with a strip of seafloor at its foot, like AUTT28.
#pragma once

#include "common/util/random.h"
#include "sim/worlds/relief.h"

namespace uw::sim {

struct ScarpOptions {
  double length_m = 300.0;  // along x
  double height_m = 10.0;
  double dip_deg = 82.0;  // angle of the wall from horizontal, (45, 90]
  // Flat seafloor strip in front of the wall's foot and behind its crest.
  double foot_width_m = 6.0;
  double crest_width_m = 3.0;
  // 10 cm: ~1.2 M triangles for the default 300 m; finer detail is texture.
  double vertex_spacing_m = 0.1;
  ReliefOptions relief = {0.35, 6.0, 0.06, 0.8};
  // Horizontal wander of the wall's trace (standard deviation, wavelength).
  double meander_amplitude_m = 1.5;
  double meander_wavelength_m = 60.0;

  void Check() const;
};

struct World;  // sim/world.h
// The wall as one grid: columns along x, rows up its cross-section from
// the foot strip to the crest strip; `options` are checked (MakeWorld).
World MakeScarp(const ScarpOptions& options, SplitMix64Stream& random);

}  // namespace uw::sim
