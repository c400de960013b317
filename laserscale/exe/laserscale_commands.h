// The commands of `laserscale`, in the order `laserscale --help` lists them.
#pragma once

#include <vector>

#include "common/cli/command.h"

namespace uw {

const std::vector<Subcommand>& LaserscaleCommands();

}  // namespace uw
