#include "colmap_plugins/nav/nav_plausibility.h"
#include "common/util/median.h"

#include <algorithm>
#include <cmath>
#include <map>

#include <fmt/format.h>

namespace uw {

std::optional<std::string> DegreesLikePositionsWarning(
    const std::vector<NavRecord>& nav, const std::string& nav_name) {
  if (nav.size() < 2) return std::nullopt;
  Eigen::Vector2d lowest = nav.front().position.head<2>();
  Eigen::Vector2d highest = lowest;
  for (const NavRecord& row : nav) {
    lowest = lowest.cwiseMin(row.position.head<2>());
    highest = highest.cwiseMax(row.position.head<2>());
  }
  const Eigen::Vector2d largest =
      lowest.cwiseAbs().cwiseMax(highest.cwiseAbs());
  const bool angles = (largest.x() <= 180.0 && largest.y() <= 90.0) ||
                      (largest.x() <= 90.0 && largest.y() <= 180.0);
  const Eigen::Vector2d extent = highest - lowest;
  const double nearest = (0.5 * (lowest + highest)).cwiseAbs().maxCoeff();
  if (!angles || extent.maxCoeff() >= 0.01 || nearest < 0.5) {
    return std::nullopt;
  }
  return fmt::format(
      "{}: x and y span only {:.3g} x {:.3g} around ({:.6f}, {:.6f}): "
      "longitude and latitude in degrees? nav.csv's x, y, z are metres in a "
      "local frame (docs/formats.md), and read as metres this survey is "
      "{:.3g} m across",
      nav_name, extent.x(), extent.y(), 0.5 * (lowest.x() + highest.x()),
      0.5 * (lowest.y() + highest.y()), extent.maxCoeff());
}

std::optional<std::string> SpeedWarning(const std::vector<NavRecord>& nav,
                                        const std::string& nav_name,
                                        double min_speed_mps,
                                        double max_speed_mps) {
  std::map<int, const NavRecord*> last_of_dive;
  std::vector<double> speeds;
  for (const NavRecord& row : nav) {
    const auto last = last_of_dive.find(row.dive);
    if (last != last_of_dive.end() && row.time_s > last->second->time_s) {
      speeds.push_back((row.position - last->second->position).norm() /
                       (row.time_s - last->second->time_s));
    }
    last_of_dive[row.dive] = &row;
  }
  if (speeds.empty()) return std::nullopt;
  const double speed = Median(speeds);
  if (speed > max_speed_mps) {
    return fmt::format(
        "{}: the vehicle moves at {:.3g} m/s (median over {} steps), faster "
        "than any survey vehicle ({:g} m/s): positions in centimetres or "
        "millimetres read as metres, or times in another unit than seconds?",
        nav_name, speed, speeds.size(), max_speed_mps);
  }
  if (speed < min_speed_mps) {
    return fmt::format(
        "{}: the vehicle moves at {:.3g} m/s (median over {} steps): a "
        "stationary platform, or positions in another unit than metres?",
        nav_name, speed, speeds.size());
  }
  return std::nullopt;
}

}  // namespace uw
