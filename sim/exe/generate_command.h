// uwsim generate: a configuration (a file, the defaults, and the flags
// that override them) -> sim/generate.h's Generate -> progress and a
// summary on stdout.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "common/cli/command.h"
#include "sim/sim_config.h"

namespace uw::sim {

struct GenerateCommandOptions {
  std::string out;  // new or empty folder
  // JSON with any of the sections of truth/sim.json; empty: the defaults.
  std::string config_path;
  // Given, these replace the configuration's.
  std::optional<WorldKind> world;
  std::optional<SurveyKind> survey;
  std::optional<uint64_t> seed;
  std::optional<int> max_images;  // negative: as if not given
  int num_threads = -1;           // <= 0: all cores; never changes the output
  bool render_images = true;      // false: the plan and truth, no images

  // Every value is checked where it applies (SimConfig::Check, Generate).
  void Check() const {}
};

// The configuration file (or the defaults) with the flags given applied.
SimConfig GenerateConfig(const GenerateCommandOptions& options);

Subcommand GenerateCommand();

}  // namespace uw::sim
