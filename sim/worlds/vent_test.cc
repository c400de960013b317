#include "sim/worlds/vent.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "sim/world.h"
#include "sim/world_testing.h"

namespace uw::sim {
namespace {

TEST(WorldTest, DefaultVentHasATallChimneyWithOverhangs) {
  const WorldOptions options;
  const World world = MakeWorld(WorldKind::kVent, options, 1);
  EXPECT_EQ(world.name, "vent");
  EXPECT_LE(world.mesh.triangles.size(), 2000000u);
  EXPECT_NEAR(world.bounds.min().x(), -15.0, 1e-12);
  EXPECT_NEAR(world.bounds.max().y(), 15.0, 1e-12);
  ExpectUnitSurveyFrame(world);
  EXPECT_EQ(world.survey_normal, Eigen::Vector3d::UnitZ());
  EXPECT_NEAR(world.survey_origin.z(), world.bounds.max().z(), 1e-12);
  // The survey area covers the chimney (>= 2 x 2.8 m) plus margins.
  EXPECT_GT(world.survey_length, 2 * 2.8 + 6.0);
  EXPECT_LT(world.survey_length, 20.0);

  // The ground far from the mound is near z = 0; the chimney rises ~10 m
  // above the mound (1.5 m) to a shallow cap.
  const auto ground_hit = FirstHit(world.mesh, Eigen::Vector3d(13, 13, 20),
                                   -Eigen::Vector3d::UnitZ());
  ASSERT_TRUE(ground_hit);
  EXPECT_NEAR(20.0 - ground_hit->second, 0.0, 1.5);
  EXPECT_GT(world.bounds.max().z(), 10.5);
  EXPECT_LT(world.bounds.max().z(), 13.5);

  // Overhangs: triangles high on the chimney facing down, with open water
  // beneath them (a ray straight down travels a while before the next hit).
  double downward_area = 0.0;
  std::vector<size_t> undersides;
  for (size_t t = 0; t < world.mesh.triangles.size(); ++t) {
    const Eigen::Vector3d normal = world.mesh.TriangleNormal(t);
    if (normal.z() < -0.7 && Centroid(world.mesh, t).z() > 4.0) {
      downward_area += TriangleArea(world.mesh, t);
      undersides.push_back(t);
    }
  }
  EXPECT_GT(downward_area, 1.0);
  ASSERT_FALSE(undersides.empty());
  int open_below = 0;
  for (size_t k = 0; k < undersides.size(); k += undersides.size() / 5 + 1) {
    const Eigen::Vector3d start =
        Centroid(world.mesh, undersides[k]) - 0.01 * Eigen::Vector3d::UnitZ();
    const auto below = FirstHit(world.mesh, start, -Eigen::Vector3d::UnitZ());
    open_below += below && below->second > 0.3;
  }
  EXPECT_GT(open_below, 0);
}

}  // namespace
}  // namespace uw::sim
