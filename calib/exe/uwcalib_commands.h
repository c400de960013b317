// The commands of `uwcalib`, in the order `uwcalib --help` lists them.
#pragma once

#include <vector>

#include "common/cli/command.h"

namespace uw {

const std::vector<Subcommand>& UwcalibCommands();

}  // namespace uw
