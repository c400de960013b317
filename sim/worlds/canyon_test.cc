#include "sim/worlds/canyon.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "sim/world.h"
#include "sim/world_testing.h"

namespace uw::sim {
namespace {

TEST(WorldTest, DefaultCanyonIsANarrowWindingFloorBetweenHighSteepWalls) {
  const WorldOptions options;
  const World world = MakeWorld(WorldKind::kCanyon, options, 1);
  EXPECT_EQ(world.name, "canyon");
  EXPECT_LE(world.mesh.triangles.size(), 1500000u);
  EXPECT_NEAR(world.bounds.min().x(), -30.0, 1e-9);
  EXPECT_NEAR(world.bounds.max().x(), 30.0, 1e-9);
  EXPECT_NEAR(world.bounds.min().y(), -18.0, 1e-9);
  EXPECT_NEAR(world.bounds.max().y(), 18.0, 1e-9);
  ExpectNormalsUp(world);
  ExpectUnitSurveyFrame(world);
  EXPECT_EQ(world.survey_normal, Eigen::Vector3d::UnitZ());
  EXPECT_EQ(world.survey_along, Eigen::Vector3d::UnitX());
  EXPECT_EQ(world.survey_length, 60.0);
  // 8 m of floor less the walls' wander (2 x 0.8 m) and the axis' range in
  // y (at most 2 x 2.5 m).
  EXPECT_GE(world.survey_width, 8.0 - 1.6 - 5.0);
  EXPECT_LE(world.survey_width, 8.0 - 1.6);
  EXPECT_NEAR(world.survey_origin.z(), 0.0, 0.3);

  // Cross-sections every 5 m: a floor (below 2 m, around the survey
  // strip) between two walls rising 8-15 m at more than 45 deg on average;
  // the floor's middle wanders in y; the survey strip lies on the floor.
  const double y0 = world.survey_origin.y();
  double lowest_middle = std::numeric_limits<double>::infinity();
  double highest_middle = -lowest_middle;
  for (double x = -27.5; x <= 27.5; x += 5.0) {
    SCOPED_TRACE("x = " + std::to_string(x));
    const auto section = CrossSection(world, x, 0.03);
    ASSERT_GT(section.size(), 500u);
    const auto middle = std::lower_bound(section.begin(), section.end(),
                                         std::make_pair(y0, 0.0));
    ASSERT_TRUE(middle != section.end());
    ASSERT_LT(middle->second, 2.0);
    auto first = middle, last = middle;
    while (first != section.begin() && std::prev(first)->second < 2.0) --first;
    while (std::next(last) != section.end() && std::next(last)->second < 2.0) {
      ++last;
    }
    // Oblique to the axis and up to 2 m up the rounded foot, a section
    // crosses more than the 8 m floor.
    const double floor_width = last->first - first->first;
    EXPECT_GT(floor_width, 6.5);
    EXPECT_LT(floor_width, 13.0);
    EXPECT_LE(first->first, y0 - 0.5 * world.survey_width);
    EXPECT_GE(last->first, y0 + 0.5 * world.survey_width);
    lowest_middle = std::min(lowest_middle, 0.5 * (first->first + last->first));
    highest_middle =
        std::max(highest_middle, 0.5 * (first->first + last->first));
    for (const bool plus_y : {false, true}) {
      double rim = -std::numeric_limits<double>::infinity();
      for (const auto& [y, z] : section) {
        if (plus_y ? y > last->first : y < first->first) rim = std::max(rim, z);
      }
      EXPECT_GT(rim, 8.0) << (plus_y ? "+y" : "-y");
      EXPECT_LT(rim, 15.0) << (plus_y ? "+y" : "-y");
      // Horizontal distance from the floor's edge to 2 m below the rim.
      double wall_run = std::numeric_limits<double>::infinity();
      for (const auto& [y, z] : section) {
        if (z <= rim - 2.0) continue;
        if (plus_y && y > last->first) {
          wall_run = std::min(wall_run, y - last->first);
        } else if (!plus_y && y < first->first) {
          wall_run = first->first - y;
        }
      }
      EXPECT_LT(wall_run, rim - 2.0 - 2.0) << (plus_y ? "+y" : "-y");
    }
  }
  EXPECT_GT(highest_middle - lowest_middle, 2.0);
}

}  // namespace
}  // namespace uw::sim
