#include "sim/exe/uwsim_commands.h"

#include "sim/exe/generate_command.h"
#include "sim/exe/map_command.h"
#include "sim/exe/observe_command.h"

namespace uw::sim {

const std::vector<Subcommand>& UwsimCommands() {
  static const std::vector<Subcommand> commands = {
      GenerateCommand(),
      MapCommand(),
      ObserveCommand(),
  };
  return commands;
}

}  // namespace uw::sim
