// laserscale simulate: the thesis's chapter-3 accuracy study of laser
// set-ups on a uwsim world (experiments/laser_experiment.h).
#pragma once

#include <string>

#include "common/cli/command.h"
#include "experiments/laser_experiment.h"

namespace uw {

struct SimulateOptions {
  ViewsExperimentOptions experiment;
  std::string out;  // folder for accuracy.csv and views.csv

  void Check() const { experiment.Check(); }
};
Subcommand SimulateCommand();

}  // namespace uw
