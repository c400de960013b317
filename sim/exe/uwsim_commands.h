// The commands of `uwsim`, in the order `uwsim --help` lists them.
#pragma once

#include <vector>

#include "common/cli/command.h"

namespace uw::sim {

const std::vector<Subcommand>& UwsimCommands();

}  // namespace uw::sim
