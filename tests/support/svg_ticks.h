// What a reader sees on a figure's axes: the tick labels of an SVG written
// by matplotlib (common/util/figure.h), and whether they are readable.
#pragma once

#include <string>
#include <vector>

namespace uw {

// The labels of one axis ('x' or 'y') in order, matplotlib's minus sign
// read as "-". matplotlib groups each tick as <g id="xtick_N"> with its
// label's <text> inside (svg.fonttype none keeps it as text).
std::vector<std::string> SvgTickLabels(const std::string& svg, char axis);

// Empty when the labels are numbers evenly spaced by 1, 2 or 5 x 10^k,
// written with no more decimals than that step needs, or (a log axis)
// increasing values of 1, 2 or 5 x 10^k; otherwise what is wrong, quoting
// the labels.
std::string TickProblem(const std::vector<std::string>& labels);

}  // namespace uw
