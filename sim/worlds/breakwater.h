// The breakwater world: a ~40 m long, ~5 m high rubble-mound breakwater
// along x, armoured with tilted rounded-cube blocks, seaward side -y, like
// the thesis's Sant Feliu harbour and UWSim scenes.
#pragma once

#include "common/util/random.h"
#include "sim/worlds/relief.h"
#include "sim/worlds/rocks.h"

namespace uw::sim {

// A rubble mound: a trapezoidal core covered with block_layers layers of
// armour blocks, on a rough seafloor. The design profile (the mean outer
// surface of the armour) rises from the seafloor (z = 0) at slope_deg to a
// crest height_m high and crest_width_m wide; its crest runs length_m along
// x, and both ends (roundheads) slope down like the sides. Seaward is -y.
struct BreakwaterOptions {
  double length_m = 40.0;  // of the crest, along x
  double height_m = 5.0;
  double crest_width_m = 4.0;
  double slope_deg = 33.0;  // 1:1.5, typical of armoured slopes
  // Seafloor around the toe of the design profile.
  double apron_width_m = 6.0;
  // 6 cm: ~1.2 M triangles; a block spans ~27 vertices.
  double vertex_spacing_m = 0.06;
  ReliefOptions relief = {0.15, 8.0, 0.04, 0.6};  // seafloor and core
  RockOptions rocks = {60, 0.3, 1.2};  // on the seafloor, off the mound
  // Armour: rounded cubes (superellipsoids of exponent 6) of edge
  // block_size_m, each edge scaled by up to 1 +- block_size_variation and
  // sheared a little, laid on jittered grids, one per layer, and tilted by
  // up to block_tilt_deg from the slope. The surface is a heightfield (no
  // hollows under blocks) whose slopes are capped at 72 deg, so block
  // sides become skirts a few vertices wide rather than one-cell cliffs.
  double block_size_m = 1.6;
  double block_size_variation = 0.2;
  int block_layers = 2;
  double block_tilt_deg = 20.0;
  // Standard deviation of the blocks' surface roughness (armourstone).
  double block_roughness_m = 0.03;

  void Check() const;
};

struct World;  // sim/world.h
// Seafloor, core and armour as one heightfield; `options` are checked
// (MakeWorld).
World MakeBreakwater(const BreakwaterOptions& options,
                     SplitMix64Stream& random);

}  // namespace uw::sim
