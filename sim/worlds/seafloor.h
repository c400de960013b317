// The seafloor world: rough fBm relief with boulders, z up.
#pragma once

#include "common/util/random.h"
#include "sim/worlds/relief.h"
#include "sim/worlds/rocks.h"

namespace uw::sim {

struct SeafloorOptions {
  double length_m = 24.0;  // along x
  double width_m = 16.0;   // along y
  // 2.5 cm: relief stays smooth at 1-3 m altitude with ~1.2 M triangles.
  double vertex_spacing_m = 0.025;
  ReliefOptions relief;
  RockOptions rocks;

  void Check() const;
};

struct World;  // sim/world.h
// A length_m x width_m heightfield centred on the origin; `options` are
// checked (MakeWorld).
World MakeSeafloor(const SeafloorOptions& options, SplitMix64Stream& random);

}  // namespace uw::sim
