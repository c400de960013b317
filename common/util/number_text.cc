#include "common/util/number_text.h"

#include <charconv>
#include <cmath>

namespace uw {

std::optional<double> FiniteDouble(std::string_view text) {
  double value = 0.0;
  const auto [end, error] =
      std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || error != std::errc() ||
      end != text.data() + text.size() || !std::isfinite(value)) {
    return std::nullopt;
  }
  return value;
}

std::optional<std::vector<double>> FiniteDoubles(std::string_view text) {
  std::vector<double> values;
  size_t start = 0;
  while (true) {
    const size_t comma = std::min(text.find(',', start), text.size());
    std::string_view item = text.substr(start, comma - start);
    const size_t first = item.find_first_not_of(" \t");
    const size_t last = item.find_last_not_of(" \t");
    const std::optional<double> value =
        first == std::string_view::npos
            ? std::nullopt
            : FiniteDouble(item.substr(first, last - first + 1));
    if (!value) return std::nullopt;
    values.push_back(*value);
    if (comma == text.size()) return values;
    start = comma + 1;
  }
}

}  // namespace uw
