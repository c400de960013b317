// For tests over every uwsim world: a survey's plan and truth (no images
// rendered) per world and seed.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "sim/generate.h"

namespace uw::testing {

inline const std::vector<sim::WorldKind>& AllWorlds() {
  static const std::vector<sim::WorldKind> worlds = {
      sim::WorldKind::kSeafloor, sim::WorldKind::kVent, sim::WorldKind::kCanyon,
      sim::WorldKind::kScarp, sim::WorldKind::kBreakwater};
  return worlds;
}

// uwsim's default survey of `world` with `seed`, without images or laser
// shots, in dir/<world><seed>; returns that folder.
inline std::filesystem::path WorldPlan(const std::filesystem::path& dir,
                                       sim::WorldKind world, uint64_t seed) {
  sim::SimConfig config;
  config.world = world;
  config.seed = seed;
  config.lasers.every_nth_image = 0;
  const std::filesystem::path out =
      dir / (sim::WorldKindName(world) + std::to_string(seed));
  sim::Generate(config, out, nullptr, false);
  return out;
}

}  // namespace uw::testing
