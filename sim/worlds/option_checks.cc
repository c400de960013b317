#include "sim/worlds/option_checks.h"

#include <cmath>

#include "common/util/error.h"

namespace uw::sim {

std::string OptionName(const std::string& section, const char* name) {
  return "world options: " + section + "." + name;
}

void CheckPositive(double value, const std::string& section, const char* name) {
  if (!(value > 0.0 && std::isfinite(value))) {
    throw ErrorAt(OptionName(section, name), " = ", value,
                  ": must be a positive number");
  }
}

void CheckNonNegative(double value, const std::string& section,
                      const char* name) {
  if (!(value >= 0.0 && std::isfinite(value))) {
    throw ErrorAt(OptionName(section, name), " = ", value,
                  ": must be a non-negative number");
  }
}

void CheckRange(double value, double low, double high,
                const std::string& section, const char* name) {
  if (!(value >= low && value <= high)) {
    throw ErrorAt(OptionName(section, name), " = ", value, ": must be in [",
                  low, ", ", high, "]");
  }
}

void CheckTriangles(double triangles, const std::string& section,
                    const char* spacing_name) {
  if (triangles > kMaxWorldTriangles) {
    throw ErrorAt("world options: ", section, ": about ", triangles,
                  " triangles exceed the limit of ", kMaxWorldTriangles,
                  "; increase ", section, ".", spacing_name,
                  " or reduce the size");
  }
}

}  // namespace uw::sim
