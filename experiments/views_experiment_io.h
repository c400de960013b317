// The text of the chapter-3 accuracy study (`laserscale simulate`): a noise
// level as the user writes it, and the two CSV tables of the results.
#pragma once

#include <string>
#include <vector>

#include "experiments/laser_experiment.h"

namespace uw {

// "feature_px:spot_px[:direction_deg[:origin_m]]"; throws uw::Error naming
// --noise for anything else or a negative sigma.
ShotNoise ParseShotNoise(const std::string& text);
// The inverse, each number at its shortest exact form ("0.5:0.25"); the
// direction and origin only when not zero.
std::string ShotNoiseText(const ShotNoise& noise);

// accuracy.csv: one line per row (set-up, distance, noise, method) with the
// items' and images' error statistics in percent.
std::string AccuracyCsvText(const std::vector<ViewsExperimentRow>& rows);
// views.csv: one line per image of each row, its pitch, roll and scale
// error in percent (empty without a scale).
std::string ViewsCsvText(const std::vector<ViewsExperimentRow>& rows);

}  // namespace uw
