#include "sim/worlds/breakwater.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "sim/world.h"
#include "sim/world_testing.h"

namespace uw::sim {
namespace {

TEST(WorldTest, DefaultBreakwaterIsAnArmouredMoundFacingMinusY) {
  const WorldOptions options;
  const World world = MakeWorld(WorldKind::kBreakwater, options, 1);
  EXPECT_EQ(world.name, "breakwater");
  EXPECT_LE(world.mesh.triangles.size(), 1500000u);
  const double slope = 33.0 * M_PI / 180.0;
  const double run = 5.0 / std::tan(slope);  // toe to crest, horizontally
  // Crest 40 m x 4 m, slopes, 6 m of seafloor beyond the toe.
  EXPECT_NEAR(world.bounds.max().x(), 20.0 + run + 6.0, 1e-9);
  EXPECT_NEAR(world.bounds.min().x(), -(20.0 + run + 6.0), 1e-9);
  EXPECT_NEAR(world.bounds.max().y(), 2.0 + run + 6.0, 1e-9);
  EXPECT_NEAR(world.bounds.min().y(), -(2.0 + run + 6.0), 1e-9);
  // The armour's tops stand a little above the 5 m design crest.
  EXPECT_GT(world.bounds.max().z(), 5.0);
  EXPECT_LT(world.bounds.max().z(), 6.6);
  ExpectNormalsUp(world);
  ExpectUnitSurveyFrame(world);
  EXPECT_TRUE(world.survey_normal.isApprox(
      Eigen::Vector3d(0.0, -std::sin(slope), std::cos(slope))));
  EXPECT_EQ(world.survey_along, Eigen::Vector3d::UnitX());
  EXPECT_EQ(world.survey_length, 40.0);
  EXPECT_NEAR(world.survey_width, 5.0 / std::sin(slope), 1e-12);
  EXPECT_TRUE(world.survey_origin.isApprox(
      Eigen::Vector3d(0.0, -2.0 - 0.5 * run, 2.5)));

  // A trapezoid: high on the crest, half-way up on the lee side and on the
  // roundheads, seafloor beyond the toe.
  EXPECT_NEAR(MaxHeightIn(world, -0.5, 0.5, -0.5, 0.5), 5.0, 0.8);
  EXPECT_NEAR(MaxHeightIn(world, -0.5, 0.5, 1.5 + 0.5 * run, 2.5 + 0.5 * run),
              2.5, 1.2);
  for (const double end : {-1.0, 1.0}) {
    EXPECT_NEAR(MaxHeightIn(world, end * (20.0 + 0.5 * run) - 0.5,
                            end * (20.0 + 0.5 * run) + 0.5, -0.5, 0.5),
                2.5, 1.2);
  }
  const std::vector<double> floor =
      HeightsIn(world, -20.0, 20.0, -10.0 - run, -3.5 - run);
  ASSERT_FALSE(floor.empty());
  double mean_abs = 0.0;
  for (const double z : floor) mean_abs += std::abs(z) / floor.size();
  EXPECT_LT(mean_abs, 0.3);
  EXPECT_LT(*std::max_element(floor.begin(), floor.end()), 1.2);

  // The seaward face (middle half of its slant height, |x| < 15 m):
  // vertices scatter about the survey plane by blocks' sizes, and much of
  // the area is steep block sides; a plain slope would have neither.
  const Eigen::Vector3d across = world.survey_normal.cross(world.survey_along);
  const auto on_face = [&](const Eigen::Vector3d& point) {
    const Eigen::Vector3d offset = point - world.survey_origin;
    return std::abs(offset.dot(world.survey_along)) < 15.0 &&
           std::abs(offset.dot(across)) < 0.25 * world.survey_width;
  };
  double sum = 0.0, sum_squares = 0.0;
  int count = 0;
  for (const Eigen::Vector3d& vertex : world.mesh.vertices) {
    if (!on_face(vertex)) continue;
    const double height =
        (vertex - world.survey_origin).dot(world.survey_normal);
    sum += height;
    sum_squares += height * height;
    ++count;
  }
  ASSERT_GT(count, 1000);
  EXPECT_NEAR(sum / count, 0.0, 0.3);
  const double rms = std::sqrt(sum_squares / count);
  EXPECT_GT(rms, 0.15);
  EXPECT_LT(rms, 1.0);
  Eigen::Vector3d mean_normal = Eigen::Vector3d::Zero();
  double steep = 0.0, total = 0.0;
  for (size_t t = 0; t < world.mesh.triangles.size(); ++t) {
    if (!on_face(Centroid(world.mesh, t))) continue;
    const double area = TriangleArea(world.mesh, t);
    const Eigen::Vector3d normal = world.mesh.TriangleNormal(t);
    mean_normal += area * normal;
    total += area;
    steep += std::abs(normal.z()) < 0.5 ? area : 0.0;  // steeper than 60 deg
  }
  EXPECT_GT(mean_normal.normalized().dot(world.survey_normal), 0.97);
  EXPECT_GT(steep / total, 0.25);
}

}  // namespace
}  // namespace uw::sim
