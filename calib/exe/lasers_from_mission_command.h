// uwcalib lasers-from-mission: laser directions from the spots of localized
// mission images (lasers.json; docs/uwcalib.md).
#pragma once

#include <string>

#include "calib/lasers_from_mission.h"
#include "common/cli/command.h"

namespace uw {

struct LasersFromMissionCommandOptions {
  LasersFromMissionOptions mission;  // the inputs and the calibration
  std::string out;                   // lasers.json
  std::string report_path;           // every spot's point; empty: none

  void Check() const { mission.Check(); }
};
Subcommand LasersFromMissionCommand();

}  // namespace uw
