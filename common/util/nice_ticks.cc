#include "common/util/nice_ticks.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

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
  // A span of a few ulps (0.1 + 0.2 against 0.3), or one a double cannot
  // hold: no step counts it, so the ends are the ticks.
  const double span = hi - lo;
  if (!std::isfinite(span) ||
      std::max(std::abs(lo), std::abs(hi)) > 1e12 * span) {
    ticks.step = std::isfinite(span) ? span : 1.0;
    ticks.values = {lo, hi};
    return ticks;
  }
  // From a step that may give a few ticks too many up to the first that
  // gives no more than max_ticks: 0 to 10 in 2s (6 ticks), not in 5s.
  ticks.step = NiceStep(span / (max_ticks + 1));
  for (;;) {
    // A tick within rounding of an end still counts as inside.
    const double slack = 1e-9 * ticks.step;
    const double first = std::ceil((lo - slack) / ticks.step);
    const double last = std::floor((hi + slack) / ticks.step);
    if (last - first + 1 <= max_ticks) {
      // Counted in integers: the multiples are below 1e13 here.
      const auto count = static_cast<int64_t>(last - first) + 1;
      for (int64_t i = 0; i < count; ++i) {
        ticks.values.push_back((first + static_cast<double>(i)) * ticks.step);
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
