// Numbers from text that must be all number: "12.5" but not "12.5x", "",
// "nan" or "1e999" (std::stod would take the first and give up on none).
#pragma once

#include <optional>
#include <string_view>

namespace uw {

// All of `text` as a finite double (from_chars: no padding, no '+'), or
// nullopt.
std::optional<double> FiniteDouble(std::string_view text);

}  // namespace uw
