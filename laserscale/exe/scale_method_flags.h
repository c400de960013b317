// Flags naming scale methods (fum, pcm, direct, davis_tusting), for
// `laserscale estimate` and `laserscale simulate`.
#pragma once

#include <string>
#include <vector>

#include "common/cli/flags.h"
#include "laserscale/scale_items.h"

namespace uw {

CLI::Option* AddScaleMethodFlag(CommandLine* cli, const std::string& flag,
                                ScaleMethod* field, const std::string& help);
// Comma-separated.
CLI::Option* AddScaleMethodsFlag(CommandLine* cli, const std::string& flag,
                                 std::vector<ScaleMethod>* field,
                                 const std::string& help);

}  // namespace uw
