#include "sim/worlds/scarp.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "sim/world.h"
#include "sim/world_testing.h"

namespace uw::sim {
namespace {

TEST(WorldTest, DefaultScarpIsALongSteepWallFacingMinusY) {
  const WorldOptions options;
  const World world = MakeWorld(WorldKind::kScarp, options, 1);
  EXPECT_EQ(world.name, "scarp");
  EXPECT_LE(world.mesh.triangles.size(), 2000000u);
  EXPECT_NEAR(world.bounds.min().x(), -150.0, 1e-9);
  EXPECT_NEAR(world.bounds.max().x(), 150.0, 1e-9);
  const double height = world.bounds.max().z() - world.bounds.min().z();
  EXPECT_GT(height, 9.0);
  EXPECT_LT(height, 13.5);  // 10 m plus relief at the ends
  ExpectUnitSurveyFrame(world);
  const double dip = 82.0 * M_PI / 180.0;
  EXPECT_TRUE(world.survey_normal.isApprox(
      Eigen::Vector3d(0.0, -std::sin(dip), std::cos(dip))));
  EXPECT_EQ(world.survey_along, Eigen::Vector3d::UnitX());
  EXPECT_EQ(world.survey_length, 300.0);
  EXPECT_NEAR(world.survey_width, 10.0 / std::sin(dip), 1e-12);
  // The wall (its middle heights): area-weighted mean normal close to the
  // survey normal, and most of it facing the water.
  Eigen::Vector3d mean_normal = Eigen::Vector3d::Zero();
  double facing = 0.0, total = 0.0;
  for (size_t t = 0; t < world.mesh.triangles.size(); ++t) {
    const double z = Centroid(world.mesh, t).z();
    if (z < 3.0 || z > 7.0) continue;
    const double area = TriangleArea(world.mesh, t);
    const Eigen::Vector3d normal = world.mesh.TriangleNormal(t);
    mean_normal += area * normal;
    total += area;
    facing += normal.dot(world.survey_normal) > 0.0 ? area : 0.0;
  }
  EXPECT_GT(mean_normal.normalized().dot(world.survey_normal), 0.97);
  EXPECT_GT(facing / total, 0.97);
}

}  // namespace
}  // namespace uw::sim
