#include "colmap_plugins/align/mesh_distance.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <random>

#include "common/util/error.h"

namespace uw {
namespace {

struct Mesh {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<Eigen::Vector3i> triangles;
};

// n x n quads over [0, size]², heights from `height`; counter-clockwise seen
// from +z.
template <typename Height>
Mesh Grid(int n, double size, const Height& height) {
  Mesh mesh;
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      const double x = size * i / n;
      const double y = size * j / n;
      mesh.vertices.emplace_back(x, y, height(x, y));
    }
  }
  const auto index = [&](int i, int j) { return j * (n + 1) + i; };
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      mesh.triangles.emplace_back(index(i, j), index(i + 1, j),
                                  index(i + 1, j + 1));
      mesh.triangles.emplace_back(index(i, j), index(i + 1, j + 1),
                                  index(i, j + 1));
    }
  }
  return mesh;
}

TEST(MeshDistance, KnownDistancesToATriangle) {
  const MeshDistance mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}});
  // Face, edge and vertex regions.
  EXPECT_NEAR(mesh.Query({0.2, 0.3, 0.5}).distance, 0.5, 1e-15);
  EXPECT_NEAR(
      (mesh.Query({0.2, 0.3, 0.5}).point - Eigen::Vector3d(0.2, 0.3, 0)).norm(),
      0.0, 1e-15);
  EXPECT_NEAR(mesh.Query({0.5, -2.0, 0.0}).distance, 2.0, 1e-15);
  EXPECT_NEAR(mesh.Query({1.0, 1.0, 0.0}).distance, std::sqrt(0.5), 1e-15);
  EXPECT_NEAR(mesh.Query({-3.0, -4.0, 0.0}).distance, 5.0, 1e-15);
  EXPECT_NEAR(mesh.Query({3.0, 0.0, 4.0}).distance, std::sqrt(4.0 + 16.0),
              1e-14);
  EXPECT_NEAR(mesh.Query({0.2, 0.3, 0.5}).triangle_normal.z(), 1.0, 1e-15);
  // Signed by the viewpoint's side, whatever the winding.
  EXPECT_NEAR(mesh.SignedDistance({0.2, 0.3, 0.5}, {0, 0, 10}), 0.5, 1e-15);
  EXPECT_NEAR(mesh.SignedDistance({0.2, 0.3, -0.5}, {0, 0, 10}), -0.5, 1e-15);
  const MeshDistance flipped({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 2, 1}});
  EXPECT_NEAR(flipped.SignedDistance({0.2, 0.3, -0.5}, {0, 0, 10}), -0.5,
              1e-15);
  EXPECT_NEAR(flipped.SignedDistance({0.2, 0.3, -0.5}, {0, 0, -10}), 0.5,
              1e-15);
}

// The tree must find what a search over every triangle finds.
TEST(MeshDistance, AgreesWithExhaustiveSearch) {
  const Mesh mesh = Grid(20, 4.0, [](double x, double y) {
    return 0.5 * std::sin(2 * x) * std::cos(3 * y);
  });
  const MeshDistance tree(mesh.vertices, mesh.triangles);
  std::vector<MeshDistance> single;
  for (const Eigen::Vector3i& triangle : mesh.triangles) {
    single.emplace_back(
        std::vector<Eigen::Vector3d>{mesh.vertices[triangle(0)],
                                     mesh.vertices[triangle(1)],
                                     mesh.vertices[triangle(2)]},
        std::vector<Eigen::Vector3i>{{0, 1, 2}});
  }
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> uniform(-1.0, 5.0);
  double max_difference = 0.0;
  for (int k = 0; k < 300; ++k) {
    const Eigen::Vector3d point(uniform(random), uniform(random),
                                uniform(random) - 2.0);
    double exhaustive = std::numeric_limits<double>::infinity();
    for (const MeshDistance& triangle : single) {
      exhaustive = std::min(exhaustive, triangle.Query(point).distance);
    }
    max_difference = std::max(
        max_difference, std::abs(tree.Query(point).distance - exhaustive));
  }
  EXPECT_LT(max_difference, 1e-14);
}

TEST(MeshDistance, MillionTrianglesHundredThousandPointsInSeconds) {
  const auto height = [](double x, double y) {
    return 0.3 * std::sin(x) * std::cos(0.7 * y);
  };
  const Mesh mesh = Grid(708, 24.0, height);  // ~1.0 M triangles, 3.4 cm
  const auto start = std::chrono::steady_clock::now();
  const MeshDistance tree(mesh.vertices, mesh.triangles);
  const auto built = std::chrono::steady_clock::now();
  std::mt19937_64 random(8);
  std::uniform_real_distribution<double> uniform(1.0, 23.0);
  std::normal_distribution<double> offset(0.0, 0.01);
  double max_error = 0.0;
  const int num_points = 100000;
  for (int k = 0; k < num_points; ++k) {
    const double x = uniform(random);
    const double y = uniform(random);
    // Points a few mm off a nearly flat surface: the distance is the
    // vertical offset to within the surface's tilt and facet error.
    const double dz = offset(random);
    const double distance =
        tree.SignedDistance({x, y, height(x, y) + dz}, {x, y, 10.0});
    max_error = std::max(max_error, std::abs(distance - dz));
  }
  const auto done = std::chrono::steady_clock::now();
  const double build_s = std::chrono::duration<double>(built - start).count();
  const double query_s = std::chrono::duration<double>(done - built).count();
  std::cout << "[ figures ] " << mesh.triangles.size() << " triangles: BVH in "
            << build_s << " s, " << num_points << " signed distances in "
            << query_s << " s, max |error| vs true offset " << max_error
            << " m\n";
  // Slope up to 0.3: the normal distance is the offset times cos(tilt),
  // plus facet error ~ curvature * h² / 8.
  EXPECT_LT(max_error, 0.003);
  EXPECT_LT(build_s + query_s, 10.0);
}

TEST(MeshDistance, RejectsBadMeshes) {
  EXPECT_THROW(MeshDistance({{0, 0, 0}, {1, 0, 0}}, {{0, 1, 2}}), Error);
  EXPECT_THROW(MeshDistance({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}}, {{0, 1, 2}}),
               Error);
  EXPECT_THROW(MeshDistance({{0, 0, NAN}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}}),
               Error);
  EXPECT_THROW(MeshDistance({}, {}), Error);
}

}  // namespace
}  // namespace uw
