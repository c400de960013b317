#include "common/util/nice_ticks.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "common/util/error.h"

namespace uw {

double NiceStep(double raw) {
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  for (const double mantissa : {1.0, 2.0, 5.0}) {
    if (mantissa * power >= raw * (1.0 - 1e-9)) return mantissa * power;
  }
  return 10.0 * power;
}

Ticks NiceTicks(double lo, double hi, int max_ticks) {
  if (!(std::isfinite(lo) && std::isfinite(hi) && lo < hi) || max_ticks < 2) {
    throw ErrorAt("NiceTicks: need finite lo < hi and max_ticks >= 2, got ", lo,
                  ", ", hi, ", ", max_ticks);
  }
  Ticks ticks;
  // From a step that may give a few ticks too many up to the first that
  // gives no more than max_ticks: 0 to 10 in 2s (6 ticks), not in 5s.
  ticks.step = NiceStep((hi - lo) / (max_ticks + 1));
  // A tick within rounding of an end still counts as inside.
  const double slack = 1e-9 * ticks.step;
  for (;;) {
    const double first = std::ceil((lo - slack) / ticks.step);
    const double last = std::floor((hi + slack) / ticks.step);
    if (last - first + 1 <= max_ticks) {
      for (double k = first; k <= last; ++k) {
        ticks.values.push_back(k * ticks.step);
      }
      return ticks;
    }
    ticks.step = NiceStep(ticks.step * (1.0 + 1e-6));
  }
}

std::string TickLabel(double value, double step) {
  const int decimals =
      std::max(0, static_cast<int>(-std::floor(std::log10(step) + 1e-9)));
  if (std::abs(value) < 1e-9 * step) value = 0.0;
  return fmt::format("{:.{}f}", value, decimals);
}

}  // namespace uw
