// Numbers from text that must be all number: "12.5" but not "12.5x", "",
// "nan" or "1e999" (std::stod would take the first and give up on none).
#pragma once

#include <optional>
#include <string_view>
#include <vector>

namespace uw {

// All of `text` as a finite double (from_chars: no padding, no '+'), or
// nullopt.
std::optional<double> FiniteDouble(std::string_view text);

// Comma-separated FiniteDoubles ("43.1, 5.4,-100": spaces and tabs around
// each allowed, as a value typed in quotes has them), or nullopt when any
// is not one.
std::optional<std::vector<double>> FiniteDoubles(std::string_view text);

}  // namespace uw
