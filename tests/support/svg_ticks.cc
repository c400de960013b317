#include "tests/support/svg_ticks.h"

#include <cmath>
#include <cstdlib>

#include <fmt/format.h>

namespace uw {
namespace {

std::string Replaced(std::string text, const std::string& from,
                     const std::string& to) {
  for (size_t at = text.find(from); at != std::string::npos;
       at = text.find(from, at + to.size())) {
    text.replace(at, from.size(), to);
  }
  return text;
}

std::string Quoted(const std::vector<std::string>& labels) {
  std::string text;
  for (const std::string& label : labels) {
    text += (text.empty() ? "'" : ", '") + label + "'";
  }
  return "[" + text + "]";
}

int DecimalsOf(const std::string& label) {
  const size_t point = label.find('.');
  return point == std::string::npos
             ? 0
             : static_cast<int>(label.size() - point - 1);
}

bool IsOneTwoFive(double step) {
  const double mantissa = step / std::pow(10.0, std::floor(std::log10(step)));
  for (const double nice : {1.0, 2.0, 5.0, 10.0}) {
    if (std::abs(mantissa - nice) < 1e-6) return true;
  }
  return false;
}

}  // namespace

std::vector<std::string> SvgTickLabels(const std::string& svg, char axis) {
  const std::string opening = std::string("<g id=\"") + axis + "tick_";
  std::vector<std::string> labels;
  for (size_t start = svg.find(opening); start != std::string::npos;
       start = svg.find(opening, start + 1)) {
    // The tick's group ends where its nesting does.
    int depth = 0;
    size_t end = start;
    while (end < svg.size()) {
      const size_t open = svg.find("<g", end);
      const size_t close = svg.find("</g>", end);
      if (close == std::string::npos) break;
      if (open != std::string::npos && open < close) {
        ++depth;
        end = open + 2;
      } else {
        --depth;
        end = close + 4;
        if (depth == 0) break;
      }
    }
    const size_t text = svg.find("<text", start);
    if (text == std::string::npos || text > end) continue;
    const size_t content = svg.find('>', text) + 1;
    const size_t stop = svg.find("</text>", content);
    std::string label = svg.substr(content, stop - content);
    label = Replaced(label, "\u2212", "-");
    for (const auto& [entity, character] :
         {std::pair<const char*, const char*>{"&lt;", "<"},
          {"&gt;", ">"},
          {"&quot;", "\""},
          {"&#39;", "'"},
          {"&apos;", "'"},
          {"&amp;", "&"}}) {
      label = Replaced(label, entity, character);
    }
    labels.push_back(label);
  }
  return labels;
}

std::string TickProblem(const std::vector<std::string>& labels) {
  if (labels.size() < 2) {
    return "fewer than 2 tick labels: " + Quoted(labels);
  }
  std::vector<double> values;
  for (const std::string& label : labels) {
    char* end = nullptr;
    const double value = std::strtod(label.c_str(), &end);
    if (label.empty() || *end != '\0' ||
        label.find_first_of("eE") != std::string::npos) {
      return "'" + label + "' is not a plain number in " + Quoted(labels);
    }
    values.push_back(value);
  }
  // A log axis: increasing values of 1, 2 or 5 x 10^k.
  bool log_axis = true;
  for (size_t i = 0; log_axis && i < values.size(); ++i) {
    log_axis = values[i] > 0.0 && IsOneTwoFive(values[i]) &&
               (i == 0 || values[i] > values[i - 1]);
  }
  const double step = values[1] - values[0];
  bool even = step > 0.0;
  for (size_t i = 1; even && i < values.size(); ++i) {
    even = std::abs(values[i] - values[i - 1] - step) <= 1e-6 * step;
  }
  if (even && !IsOneTwoFive(step) && !log_axis) {
    return fmt::format("step {} is not 1, 2 or 5 x 10^k in {}", step,
                       Quoted(labels));
  }
  if (even && IsOneTwoFive(step)) {
    const int needed =
        std::max(0, -static_cast<int>(std::floor(std::log10(step) + 1e-9)));
    for (const std::string& label : labels) {
      if (DecimalsOf(label) > needed) {
        return "'" + label + "' has more decimals than the step " +
               fmt::format("{}", step) + " needs in " + Quoted(labels);
      }
    }
    return "";
  }
  return log_axis
             ? ""
             : "neither evenly spaced nor 1, 2, 5 x 10^k: " + Quoted(labels);
}

}  // namespace uw
