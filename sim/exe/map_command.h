// uwsim map: an output folder of uwsim generate -> sim/survey_map.h's
// WriteSurveyMap -> a top-view image.
#pragma once

#include <string>

#include "common/cli/command.h"
#include "report/survey_map.h"

namespace uw::sim {

struct MapCommandOptions {
  std::string sim;  // output folder of uwsim generate
  std::string out;  // .png, .jpg or .jpeg
  SurveyMapOptions map;

  void Check() const { map.Check(); }
};

Subcommand MapCommand();

}  // namespace uw::sim
