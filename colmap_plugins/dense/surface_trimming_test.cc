#include "colmap_plugins/dense/surface_trimming.h"

#include <gtest/gtest.h>

#include <functional>
#include <limits>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "common/mesh/test_meshes.h"
#include "common/util/error.h"
#include "common/util/error_testing.h"

namespace uw {
namespace {

Eigen::Vector3d Centroid(const TriangleMesh& mesh, size_t t) {
  const Eigen::Vector3i& triangle = mesh.triangles[t];
  return (mesh.vertices[triangle[0]] + mesh.vertices[triangle[1]] +
          mesh.vertices[triangle[2]]) /
         3.0;
}

// 20 x 20 quads of 0.5 m over [0, 10]^2 at z = 0: edges of 0.5 m and
// diagonals of 0.71 m, so the median edge is 0.5 m. The centroids of the two
// triangles of a quad are 0.24 m apart.
TriangleMesh Grid() {
  TriangleMesh mesh;
  AddGrid(Eigen::Vector3d::Zero(), Eigen::Vector3d(10, 0, 0),
          Eigen::Vector3d(0, 10, 0), 20, 20, &mesh);
  return mesh;
}

// Support 5 cm above the centroid of every triangle that `supported`
// accepts.
std::vector<Eigen::Vector3d> SupportAt(
    const TriangleMesh& mesh, const std::function<bool(size_t)>& supported) {
  std::vector<Eigen::Vector3d> points;
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (supported(t)) {
      points.push_back(Centroid(mesh, t) + Eigen::Vector3d(0, 0, 0.05));
    }
  }
  return points;
}

TrimmingOptions Options() {
  TrimmingOptions options;
  options.max_distance = 0.1;
  return options;
}

// The triangles of `trimmed`, as vertex positions, must be those of `mesh`
// listed in `kept`, in that order; every vertex used, none twice.
void ExpectSubset(const TriangleMesh& mesh, const std::vector<size_t>& kept,
                  const TriangleMesh& trimmed) {
  ASSERT_EQ(trimmed.triangles.size(), kept.size());
  std::set<int> used;
  for (size_t k = 0; k < kept.size(); ++k) {
    for (int corner = 0; corner < 3; ++corner) {
      const int index = trimmed.triangles[k][corner];
      ASSERT_GE(index, 0);
      ASSERT_LT(index, static_cast<int>(trimmed.vertices.size()));
      used.insert(index);
      ASSERT_EQ(trimmed.vertices[index],
                mesh.vertices[mesh.triangles[kept[k]][corner]])
          << "triangle " << k << " corner " << corner;
    }
  }
  EXPECT_EQ(used.size(), trimmed.vertices.size()) << "unreferenced vertices";
  std::set<std::tuple<double, double, double>> positions;
  for (const Eigen::Vector3d& vertex : trimmed.vertices) {
    positions.insert({vertex.x(), vertex.y(), vertex.z()});
  }
  EXPECT_EQ(positions.size(), trimmed.vertices.size()) << "duplicated vertices";
}

TEST(TrimUnsupported, KeepsExactlyTheSupportedTriangles) {
  const TriangleMesh mesh = Grid();
  // The left half (x < 5) and one triangle of each quad of the top right
  // corner (x > 7.5, y > 7.5): a second component of 25 triangles.
  auto left = [&](size_t t) { return Centroid(mesh, t).x() < 5.0; };
  auto corner = [&](size_t t) {
    const Eigen::Vector3d c = Centroid(mesh, t);
    return c.x() > 7.5 && c.y() > 7.5 && t % 2 == 0;
  };
  const TriangleMesh trimmed = TrimUnsupported(
      mesh, SupportAt(mesh, [&](size_t t) { return left(t) || corner(t); }),
      Options());
  std::vector<size_t> expected;
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (left(t) || corner(t)) {
      expected.push_back(t);
    }
  }
  ASSERT_EQ(expected.size(), 400u + 25u);
  ExpectSubset(mesh, expected, trimmed);
  // 11 x 21 vertices on the left; 25 triangles (i, j), (i+1, j),
  // (i+1, j+1) in a 5 x 5 block of quads use 6 x 6 vertices but for one
  // corner.
  EXPECT_EQ(trimmed.vertices.size(), 11u * 21u + 35u);
}

TEST(TrimUnsupported, NoSupportLeavesNothing) {
  const TriangleMesh mesh = Grid();
  const TriangleMesh trimmed = TrimUnsupported(mesh, {}, Options());
  EXPECT_TRUE(trimmed.triangles.empty());
  EXPECT_TRUE(trimmed.vertices.empty());
  // Support farther than max_distance from every centroid counts for
  // nothing either.
  const TriangleMesh far =
      TrimUnsupported(mesh, {Eigen::Vector3d(5.1, 5.1, 0.5)}, Options());
  EXPECT_TRUE(far.triangles.empty());
  EXPECT_TRUE(
      TrimUnsupported(TriangleMesh(), {Eigen::Vector3d::Zero()}, Options())
          .triangles.empty());
}

TEST(TrimUnsupported, LongEdgedTrianglesGo) {
  TriangleMesh mesh = Grid();
  // A sliver bridging the grid's right edge to a point 3 m away (edges of
  // 3 m and more, over 4 x the 0.5 m median), and a moderately stretched
  // one (longest edge 1.39 m) that stays.
  const int first = static_cast<int>(mesh.vertices.size());
  mesh.vertices.emplace_back(13.0, 5.0, 0.0);
  mesh.vertices.emplace_back(11.3, 5.0, 0.0);
  const int right_middle = 10 * 21 + 20;  // (10, 5)
  const int right_above = 11 * 21 + 20;   // (10, 5.5)
  ASSERT_EQ(mesh.vertices[right_middle], Eigen::Vector3d(10, 5, 0));
  mesh.triangles.emplace_back(right_middle, first, right_above);
  mesh.triangles.emplace_back(right_middle, first + 1, right_above);
  const TriangleMesh trimmed = TrimUnsupported(
      mesh, SupportAt(mesh, [](size_t) { return true; }), Options());
  std::vector<size_t> expected;
  for (size_t t = 0; t < 800; ++t) {
    expected.push_back(t);
  }
  expected.push_back(801);
  ExpectSubset(mesh, expected, trimmed);

  // A looser factor keeps the sliver too.
  TrimmingOptions loose = Options();
  loose.max_edge_factor = 7.0;
  EXPECT_EQ(
      TrimUnsupported(mesh, SupportAt(mesh, [](size_t) { return true; }), loose)
          .triangles.size(),
      802u);
}

TEST(TrimUnsupported, SmallComponentsGo) {
  TriangleMesh mesh = Grid();  // 800 triangles
  // An island of 2 x 2 quads (8 triangles) and one of 1 quad (2 triangles)
  // beside the grid, and 2 triangles that touch the grid at a vertex only,
  // so belong to its component.
  AddGrid(Eigen::Vector3d(20, 0, 0), Eigen::Vector3d(1, 0, 0),
          Eigen::Vector3d(0, 1, 0), 2, 2, &mesh);
  AddGrid(Eigen::Vector3d(30, 0, 0), Eigen::Vector3d(0.5, 0, 0),
          Eigen::Vector3d(0, 0.5, 0), 1, 1, &mesh);
  const int first = static_cast<int>(mesh.vertices.size());
  const int grid_corner = 20;  // (10, 0)
  ASSERT_EQ(mesh.vertices[grid_corner], Eigen::Vector3d(10, 0, 0));
  mesh.vertices.emplace_back(10.5, -0.5, 0.0);
  mesh.vertices.emplace_back(10.5, 0.0, 0.0);
  mesh.vertices.emplace_back(11.0, -0.5, 0.0);
  mesh.triangles.emplace_back(grid_corner, first, first + 1);
  mesh.triangles.emplace_back(first, first + 2, first + 1);
  ASSERT_EQ(mesh.triangles.size(), 800u + 8u + 2u + 2u);
  const std::vector<Eigen::Vector3d> support =
      SupportAt(mesh, [](size_t) { return true; });
  auto all_but = [&](size_t begin, size_t end) {
    std::vector<size_t> kept;
    for (size_t t = 0; t < mesh.triangles.size(); ++t) {
      if (t < begin || t >= end) {
        kept.push_back(t);
      }
    }
    return kept;
  };

  // The largest component has 802 triangles: at 1.5 % (12.03) both
  // islands go.
  TrimmingOptions options = Options();
  options.min_component_fraction = 0.015;
  ExpectSubset(mesh, all_but(800, 810),
               TrimUnsupported(mesh, support, options));

  // At 0.5 % (4.01) the 8-triangle island stays.
  options.min_component_fraction = 0.005;
  ExpectSubset(mesh, all_but(808, 810),
               TrimUnsupported(mesh, support, options));

  options.min_component_fraction = 0.0;
  EXPECT_EQ(TrimUnsupported(mesh, support, options).triangles.size(),
            mesh.triangles.size());
}

TEST(TrimUnsupported, ComponentsAreCountedAfterTrimming) {
  // Two grids joined by one unsupported strip of quads: without the strip
  // the smaller one is an island of its own.
  TriangleMesh mesh;
  AddGrid(Eigen::Vector3d::Zero(), Eigen::Vector3d(11, 0, 0),
          Eigen::Vector3d(0, 10, 0), 22, 20, &mesh);
  // Support for x < 10 (the main part) and x > 10.5 (a strip of 20 x 2
  // triangles, 5 % of the main part's 800).
  const std::vector<Eigen::Vector3d> support = SupportAt(mesh, [&](size_t t) {
    const double x = Centroid(mesh, t).x();
    return x < 10.0 || x > 10.5;
  });
  TrimmingOptions options = Options();
  options.min_component_fraction = 0.04;
  EXPECT_EQ(TrimUnsupported(mesh, support, options).triangles.size(), 840u);
  options.min_component_fraction = 0.06;
  EXPECT_EQ(TrimUnsupported(mesh, support, options).triangles.size(), 800u);
}

TEST(TrimmingOptions, CheckRejectsBadFields) {
  EXPECT_NO_THROW(Options().Check());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const std::vector<
      std::pair<std::function<void(TrimmingOptions*)>, std::string>>
      cases = {
          {[](TrimmingOptions* o) { o->max_distance = 0.0; }, "max_distance"},
          {[nan](TrimmingOptions* o) { o->max_distance = nan; },
           "max_distance"},
          {[inf](TrimmingOptions* o) { o->max_distance = inf; },
           "max_distance"},
          {[](TrimmingOptions* o) { o->max_edge_factor = 1.0; },
           "max_edge_factor"},
          {[](TrimmingOptions* o) { o->min_component_fraction = -0.1; },
           "min_component_fraction"},
          {[](TrimmingOptions* o) { o->min_component_fraction = 1.5; },
           "min_component_fraction"},
      };
  const TriangleMesh mesh = Grid();
  for (const auto& [spoil, field] : cases) {
    TrimmingOptions options = Options();
    spoil(&options);
    ExpectErrorContaining([&] { options.Check(); }, field);
    ExpectErrorContaining([&] { TrimUnsupported(mesh, {}, options); }, field);
  }
  // The default max_distance is unset.
  ExpectErrorContaining([&] { TrimUnsupported(mesh, {}, TrimmingOptions()); },
                        "max_distance");
}

}  // namespace
}  // namespace uw
