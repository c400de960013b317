#include "laserscale/exe/laserscale_commands.h"

#include "laserscale/exe/apply_command.h"
#include "laserscale/exe/detect_command.h"
#include "laserscale/exe/estimate_command.h"
#include "laserscale/exe/localize_command.h"
#include "laserscale/exe/simulate_command.h"
#include "laserscale/exe/sparse_surface_command.h"

namespace uw {

const std::vector<Subcommand>& LaserscaleCommands() {
  static const std::vector<Subcommand> commands = {
      DetectCommand(),   LocalizeCommand(), SparseSurfaceCommand(),
      EstimateCommand(), ApplyCommand(),    SimulateCommand(),
  };
  return commands;
}

}  // namespace uw
