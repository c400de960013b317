#include "calib/exe/uwcalib_commands.h"

#include "calib/exe/calibrate_command.h"
#include "calib/exe/detect_command.h"
#include "calib/exe/export_command.h"
#include "calib/exe/lasers_command.h"
#include "calib/exe/lasers_from_mission_command.h"

namespace uw {

const std::vector<Subcommand>& UwcalibCommands() {
  static const std::vector<Subcommand> commands = {
      CalibDetectCommand(), CalibrateCommand(),         CalibExportCommand(),
      CalibLasersCommand(), LasersFromMissionCommand(),
  };
  return commands;
}

}  // namespace uw
