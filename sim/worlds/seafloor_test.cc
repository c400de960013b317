#include "sim/worlds/seafloor.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "sim/world.h"
#include "sim/world_testing.h"

namespace uw::sim {
namespace {

TEST(WorldTest, DefaultSeafloor) {
  const WorldOptions options;
  const World world = MakeWorld(WorldKind::kSeafloor, options, 1);
  EXPECT_EQ(world.name, "seafloor");
  EXPECT_LE(world.mesh.triangles.size(), 2000000u);
  EXPECT_NEAR(world.bounds.min().x(), -12.0, 1e-12);
  EXPECT_NEAR(world.bounds.max().x(), 12.0, 1e-12);
  EXPECT_NEAR(world.bounds.min().y(), -8.0, 1e-12);
  EXPECT_NEAR(world.bounds.max().y(), 8.0, 1e-12);
  // A heightfield seen from above: every normal points up.
  for (size_t t = 0; t < world.mesh.triangles.size(); ++t) {
    ASSERT_GT(world.mesh.TriangleNormal(t).z(), 0.0) << "triangle " << t;
  }
  ExpectUnitSurveyFrame(world);
  EXPECT_EQ(world.survey_normal, Eigen::Vector3d::UnitZ());
  EXPECT_EQ(world.survey_along, Eigen::Vector3d::UnitX());
  EXPECT_EQ(world.survey_length, 24.0);
  EXPECT_EQ(world.survey_width, 16.0);
  // Relief of the configured size: metres of undulation, not cm or 10 m.
  const double relief = world.bounds.max().z() - world.bounds.min().z();
  EXPECT_GT(relief, 0.5);
  EXPECT_LT(relief, 5.0);
}

}  // namespace
}  // namespace uw::sim
