#include "sim/worlds/height_grid.h"

#include <cmath>

#include <gtest/gtest.h>

#include "sim/world_testing.h"

namespace uw::sim {
namespace {

TEST(HeightGrid, CoversItsRectangleWithAtLeastTheSpacing) {
  const HeightGrid grid(-2.0, 1.0, 4.0, 1.0, 0.3);
  EXPECT_EQ(grid.nx, 15);  // ceil(4 / 0.3) + 1
  EXPECT_EQ(grid.ny, 5);
  EXPECT_DOUBLE_EQ(grid.x(0), -2.0);
  EXPECT_DOUBLE_EQ(grid.x(grid.nx - 1), 2.0);
  EXPECT_DOUBLE_EQ(grid.y(grid.ny - 1), 2.0);
  EXPECT_LE(grid.dx, 0.3);
  EXPECT_LE(grid.dy, 0.3);
  const HeightGrid tiny(0.0, 0.0, 0.01, 0.01, 1.0);
  EXPECT_EQ(tiny.nx, 2);
  EXPECT_EQ(tiny.ny, 2);
}

TEST(HeightGrid, TrianglesFaceUpAndAreConsistentlyOriented) {
  HeightGrid grid(0.0, 0.0, 2.0, 1.0, 0.25);
  for (int j = 0; j < grid.ny; ++j) {
    for (int i = 0; i < grid.nx; ++i) {
      grid.at(i, j) = 0.1 * std::sin(3.0 * grid.x(i)) * grid.y(j);
    }
  }
  TriangleMesh mesh;
  AppendHeightGrid(grid, &mesh);
  EXPECT_EQ(mesh.vertices.size(), grid.z.size());
  EXPECT_EQ(mesh.triangles.size(),
            2u * static_cast<size_t>(grid.nx - 1) * (grid.ny - 1));
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    EXPECT_GT(mesh.TriangleNormal(t).z(), 0.0) << t;
  }
  ExpectConsistentOrientation(mesh);
}

TEST(AppendGridTriangles, AWrappedGridIsAClosedTubeFacingOut) {
  TriangleMesh mesh;
  constexpr int kAround = 12, kUp = 4;
  for (int j = 0; j < kUp; ++j) {
    for (int i = 0; i < kAround; ++i) {
      const double theta = 2.0 * M_PI * i / kAround;
      mesh.vertices.emplace_back(std::cos(theta), std::sin(theta), j);
    }
  }
  AppendGridTriangles(0, kAround, kUp, /*wrap_u=*/true, &mesh);
  EXPECT_EQ(mesh.triangles.size(), 2u * kAround * (kUp - 1));
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Eigen::Vector3i& f = mesh.triangles[t];
    const Eigen::Vector3d centre =
        (mesh.vertices[f[0]] + mesh.vertices[f[1]] + mesh.vertices[f[2]]) / 3;
    EXPECT_GT(mesh.TriangleNormal(t).dot(
                  Eigen::Vector3d(centre.x(), centre.y(), 0.0)),
              0.0)
        << t;
  }
  ExpectConsistentOrientation(mesh);
}

TEST(LimitSlope, OnlyRaisesAndCapsTheSlope) {
  HeightGrid grid(0.0, 0.0, 2.0, 2.0, 0.1);
  // A 1 m tall one-cell pillar in the middle.
  grid.at(10, 10) = 1.0;
  const std::vector<double> before = grid.z;
  LimitSlope(2.0, &grid);
  for (size_t k = 0; k < grid.z.size(); ++k) ASSERT_GE(grid.z[k], before[k]);
  EXPECT_EQ(grid.at(10, 10), 1.0);
  // Neighbours along the axes hang 2 x 0.1 m below, and further ones on the
  // cone; the far corner is untouched.
  EXPECT_DOUBLE_EQ(grid.at(11, 10), 0.8);
  EXPECT_DOUBLE_EQ(grid.at(10, 13), 0.4);
  EXPECT_EQ(grid.at(0, 0), 0.0);
  for (int j = 0; j < grid.ny; ++j) {
    for (int i = 0; i + 1 < grid.nx; ++i) {
      EXPECT_LE(std::abs(grid.at(i + 1, j) - grid.at(i, j)),
                2.0 * grid.dx + 1e-12);
    }
  }
}

}  // namespace
}  // namespace uw::sim
