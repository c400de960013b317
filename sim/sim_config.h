// Every parameter of an uwsim simulation: what `uwsim generate --config`
// reads and truth/sim.json records.
#pragma once

#include <cstdint>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "colmap_plugins/scene/model.h"
#include "sim/distractors.h"
#include "sim/laser.h"
#include "sim/logs.h"
#include "sim/navigation.h"
#include "sim/renderer.h"
#include "sim/rig.h"
#include "sim/survey.h"
#include "sim/world.h"

namespace uw::sim {

// Every parameter of a simulation; sim.json in the output records it whole.
struct SimConfig {
  WorldKind world = WorldKind::kSeafloor;
  SurveyKind survey = SurveyKind::kLawnmower;
  uint64_t seed = 1;
  Camera camera = DefaultCamera();
  WorldOptions world_options;
  SurveyOptions survey_options;
  NavigationOptions navigation;
  LogOptions logs;
  RenderOptions render;
  LaserOptions lasers;
  RigOptions rig;  // more cameras besides `camera`
  // Shells, debris and shiny objects scattered on the world (none by
  // default): bright things that are not a laser's spot.
  DistractorOptions distractors;

  // 1024 x 768 SIMPLE_RADIAL with a mild barrel distortion.
  static Camera DefaultCamera();
  void Check() const;
};
void to_json(nlohmann::json& json, const SimConfig& config);
// Reads the sections present ("world", "survey", "camera", ...), keeping
// defaults for the rest; unknown keys and values of the wrong type are
// uw::Errors naming the key.
void from_json(const nlohmann::json& json, SimConfig& config);

// A configuration file (JSON with any of the sections above): every error
// names the file.
SimConfig ReadSimConfig(const std::filesystem::path& path);

}  // namespace uw::sim
