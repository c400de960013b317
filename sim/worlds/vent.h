// The vent world: a ~10 m hydrothermal chimney with overhanging flanges on
// a rough mound, like the thesis's Lucky Strike model.
#pragma once

#include "common/util/random.h"
#include "sim/worlds/relief.h"
#include "sim/worlds/rocks.h"

namespace uw::sim {

struct VentOptions {
  double ground_size_m = 30.0;  // square, centred on the chimney
  double ground_vertex_spacing_m = 0.05;
  ReliefOptions ground_relief = {0.25, 8.0, 0.05, 0.6};
  RockOptions ground_rocks = {30, 0.2, 1.2};
  // A sulfide debris mound under the chimney (Gaussian profile).
  double mound_height_m = 1.5;
  double mound_radius_m = 7.0;
  double chimney_height_m = 10.0;  // above the ground at its centre
  double chimney_base_radius_m = 2.8;
  double chimney_top_radius_m = 1.4;
  // Relative standard deviation of the radius with angle and height.
  double chimney_radius_noise = 0.12;
  // Standard deviation of the chimney axis' horizontal wander (m).
  double chimney_lean_m = 0.3;
  // Flanges: ledges whose radius exceeds the body below them (overhangs),
  // between 30 % and 85 % of the height, each covering part of the
  // circumference.
  int flange_count = 3;
  double flange_min_width_m = 0.5;
  double flange_max_width_m = 1.2;
  double chimney_vertex_spacing_m = 0.03;

  void Check() const;
};

struct World;  // sim/world.h
// The ground (a heightfield ground_size_m square around the origin) and the
// chimney standing on it at the origin (a closed tube of rings with a domed
// cap); `options` are checked (MakeWorld).
World MakeVent(const VentOptions& options, SplitMix64Stream& random);

}  // namespace uw::sim
