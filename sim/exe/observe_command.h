// uwsim observe: an output folder of uwsim generate -> sim/observe.h's
// ObserveSimulation -> a COLMAP text model of perfect feature tracks.
#pragma once

#include <string>

#include "common/cli/command.h"
#include "sim/observe.h"

namespace uw::sim {

struct ObserveCommandOptions {
  std::string sim;          // output folder of uwsim generate
  std::string output_path;  // model folder to write (new or empty)
  ObserveOptions observe;

  void Check() const { observe.Check(); }
};

Subcommand ObserveCommand();

}  // namespace uw::sim
