// Axis ticks a reader can use: multiples of 1, 2 or 5 x 10^k, labelled with
// the decimals their step needs (0.5, 1.0, 1.5 rather than 0.4875,
// 1.0125), as matplotlib and gnuplot place them.
#pragma once

#include <string>
#include <vector>

namespace uw {

// The smallest 1, 2 or 5 x 10^k not below `raw` (> 0).
double NiceStep(double raw);

struct Ticks {
  double step = 1.0;
  std::vector<double> values;  // increasing, within [lo, hi]
};

// The multiples of the smallest nice step that puts at most `max_ticks`
// (>= 2) of them in [lo, hi] (lo < hi, both finite).
Ticks NiceTicks(double lo, double hi, int max_ticks);

// `value` with as many decimals as `step` needs; a value within rounding of
// 0 is "0" (never "-0.0").
std::string TickLabel(double value, double step);

}  // namespace uw
