#include "colmap_plugins/nav/nav_plausibility.h"

#include <gtest/gtest.h>

#include <cmath>

namespace uw {
namespace {

// A 40 m x 30 m lawnmower, as positions in metres from `origin`.
std::vector<NavRecord> Lawnmower(const Eigen::Vector2d& origin,
                                 double metres_per_unit_x = 1.0,
                                 double metres_per_unit_y = 1.0) {
  std::vector<NavRecord> nav;
  for (int k = 0; k < 40; ++k) {
    NavRecord row;
    row.time_s = k;
    row.position = Eigen::Vector3d(
        origin.x() + (k % 2 == 0 ? 0.0 : 40.0) / metres_per_unit_x,
        origin.y() + 30.0 * k / 39.0 / metres_per_unit_y, -12.0);
    nav.push_back(row);
  }
  return nav;
}

TEST(DegreesLikePositions, LongitudeAndLatitudeAreWarned) {
  const double metres_per_degree = 111320.0;
  const std::vector<NavRecord> nav =
      Lawnmower({5.4, 43.1}, metres_per_degree * std::cos(43.1 * M_PI / 180),
                metres_per_degree);
  const auto warning = DegreesLikePositionsWarning(nav, "nav.csv");
  ASSERT_TRUE(warning.has_value());
  EXPECT_EQ(warning->rfind("nav.csv: x and y span only 0.000492 x 0.000269 "
                           "around (5.400246, 43.100135): longitude and "
                           "latitude in degrees?",
                           0),
            0u)
      << *warning;
  // Latitude first, and the southern and western hemispheres.
  EXPECT_TRUE(DegreesLikePositionsWarning(
      Lawnmower({-33.9, -151.2}, metres_per_degree, metres_per_degree),
      "nav.csv"));
}

TEST(DegreesLikePositions, MetricLogsAreNot) {
  // Near the origin, far from it, in UTM, or a camera that stayed put at
  // the origin: none is warned.
  EXPECT_FALSE(DegreesLikePositionsWarning(Lawnmower({-20, -15}), "n"));
  EXPECT_FALSE(DegreesLikePositionsWarning(Lawnmower({43, 5}), "n"));
  EXPECT_FALSE(DegreesLikePositionsWarning(Lawnmower({4.5e5, 5.2e6}), "n"));
  EXPECT_FALSE(
      DegreesLikePositionsWarning(Lawnmower({0.01, 0}, 1e4, 1e4), "n"));
  // A single row has no extent to judge.
  EXPECT_FALSE(DegreesLikePositionsWarning(
      {Lawnmower({5.4, 43.1}, 1e5, 1e5).front()}, "n"));
}

// The lawnmower's rows are 1 s apart and 40 m across: 40 m/s.
TEST(Speed, UnitsFarOffAreWarned) {
  // In centimetres read as metres: 100 times a 0.4 m/s survey.
  std::vector<NavRecord> nav = Lawnmower({0, 0}, 0.01, 0.01);
  for (size_t k = 0; k < nav.size(); ++k) nav[k].time_s = 100.0 * k;
  const auto fast = SpeedWarning(nav, "nav.csv");
  ASSERT_TRUE(fast.has_value());
  EXPECT_EQ(fast->rfind("nav.csv: the vehicle moves at 40 m/s (median over 39 "
                        "steps), faster than any survey vehicle (10 m/s)",
                        0),
            0u)
      << *fast;
  // In metres it is 0.4 m/s: nothing to say.
  nav = Lawnmower({0, 0});
  for (size_t k = 0; k < nav.size(); ++k) nav[k].time_s = 100.0 * k;
  EXPECT_FALSE(SpeedWarning(nav, "nav.csv"));
  // A lander: it stays put, which is said, not refused.
  for (NavRecord& row : nav) row.position = Eigen::Vector3d(3, 4, -20);
  const auto still = SpeedWarning(nav, "nav.csv");
  ASSERT_TRUE(still.has_value());
  EXPECT_NE(still->find("moves at 0 m/s (median over 39 steps): a stationary "
                        "platform"),
            std::string::npos)
      << *still;
  // Steps are taken within a dive only: two dives at one place each.
  nav[1].dive = 2;
  nav[1].position = Eigen::Vector3d(1000, 0, 0);
  EXPECT_NE(SpeedWarning(nav, "nav.csv")->find("median over 38 steps"),
            std::string::npos);
}

}  // namespace
}  // namespace uw
