// The commands of `uwcolmap`, in the order `uwcolmap --help` lists them.
#pragma once

#include <vector>

#include "common/cli/command.h"

namespace uw {

const std::vector<Subcommand>& UwcolmapCommands();

}  // namespace uw
