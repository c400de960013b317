// The checks every world's options share; their messages name the field as
// a JSON path under "world options" ("world options: vent.flange_count = -1:
// must be in [0, 20]").
#pragma once

#include <string>

namespace uw::sim {

// "world options: <section>.<name>".
std::string OptionName(const std::string& section, const char* name);

void CheckPositive(double value, const std::string& section, const char* name);
void CheckNonNegative(double value, const std::string& section,
                      const char* name);
void CheckRange(double value, double low, double high,
                const std::string& section, const char* name);
// Beyond kMaxWorldTriangles a world needs gigabytes once the ray caster
// holds a copy; a configuration asking for it is almost certainly a unit
// mistake. `spacing_name` is the field to increase.
void CheckTriangles(double triangles, const std::string& section,
                    const char* spacing_name);
constexpr double kMaxWorldTriangles = 2e7;

}  // namespace uw::sim
