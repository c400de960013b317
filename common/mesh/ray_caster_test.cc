#include "common/mesh/ray_caster.h"

#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <tbb/parallel_for.h>
#include <Eigen/Geometry>

#include "common/mesh/test_meshes.h"
#include "common/util/error.h"

namespace uw {
namespace {

// The plane z = 0 over [-5, 5]^2, facing +z.
TriangleMesh FloorMesh() {
  TriangleMesh mesh;
  AddGrid({-5, -5, 0}, {10, 0, 0}, {0, 10, 0}, 10, 10, &mesh);
  return mesh;
}

// The unit cube [0, 1]^3 with outward normals, 2 x 2 quads a face.
TriangleMesh CubeMesh() {
  TriangleMesh mesh;
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX();
  const Eigen::Vector3d y = Eigen::Vector3d::UnitY();
  const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
  AddGrid({0, 0, 0}, y, x, 2, 2, &mesh);  // z = 0, facing -z
  AddGrid({0, 0, 1}, x, y, 2, 2, &mesh);  // z = 1, facing +z
  AddGrid({0, 0, 0}, x, z, 2, 2, &mesh);  // y = 0, facing -y
  AddGrid({0, 1, 0}, z, x, 2, 2, &mesh);  // y = 1, facing +y
  AddGrid({0, 0, 0}, z, y, 2, 2, &mesh);  // x = 0, facing -x
  AddGrid({1, 0, 0}, y, z, 2, 2, &mesh);  // x = 1, facing +x
  return mesh;
}

Eigen::Vector3d RandomUnit(std::mt19937_64* rng) {
  std::normal_distribution<double> normal;
  return Eigen::Vector3d(normal(*rng), normal(*rng), normal(*rng)).normalized();
}

TEST(RayCaster, HitsPlaneExactly) {
  const RayCaster caster(FloorMesh());
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (int k = 0; k < 1000; ++k) {
    const Eigen::Vector3d origin(3 * uniform(rng), 3 * uniform(rng),
                                 2.0 + uniform(rng));
    const Eigen::Vector3d target(4 * uniform(rng), 4 * uniform(rng), 0.0);
    const Eigen::Vector3d direction = (target - origin).normalized();
    const std::optional<RayCaster::Hit> hit =
        caster.Intersect(origin, direction);
    ASSERT_TRUE(hit.has_value()) << k;
    const double expected = -origin.z() / direction.z();
    EXPECT_NEAR(hit->distance, expected, 1e-12);
    EXPECT_NEAR(hit->point_in_world.z(), 0.0, 1e-14);
    EXPECT_LT((hit->point_in_world - target).norm(), 1e-12);
    EXPECT_EQ(hit->point_in_world, origin + hit->distance * direction);
    EXPECT_LT((hit->normal_in_world - Eigen::Vector3d::UnitZ()).norm(), 1e-15);
    EXPECT_LT(hit->triangle_id, 200u);
  }
}

TEST(RayCaster, BackFaceKeepsTheMeshNormal) {
  const RayCaster caster(FloorMesh());
  const std::optional<RayCaster::Hit> hit =
      caster.Intersect({0.3, 0.2, -1.5}, Eigen::Vector3d::UnitZ());
  ASSERT_TRUE(hit.has_value());
  EXPECT_NEAR(hit->distance, 1.5, 1e-15);
  EXPECT_EQ(hit->normal_in_world, Eigen::Vector3d::UnitZ());
}

TEST(RayCaster, MissesParallelBehindAndOutside) {
  const RayCaster caster(FloorMesh());
  EXPECT_FALSE(caster.Intersect({0, 0, 1}, Eigen::Vector3d::UnitX()));
  EXPECT_FALSE(caster.Intersect({0, 0, 1}, Eigen::Vector3d::UnitZ()));
  EXPECT_FALSE(caster.Intersect({0, 0, -1}, -Eigen::Vector3d::UnitZ()));
  EXPECT_FALSE(caster.Intersect({6, 0, 1}, -Eigen::Vector3d::UnitZ()));
  // In the plane itself.
  EXPECT_FALSE(caster.Intersect({-7, 0.25, 0}, Eigen::Vector3d::UnitX()));
  EXPECT_FALSE(caster.Occluded({0, 0, 1}, Eigen::Vector3d::UnitX(), 100));
  EXPECT_FALSE(caster.Occluded({0, 0, 1}, Eigen::Vector3d::UnitZ(), 100));
}

TEST(RayCaster, RespectsMaxDistance) {
  const RayCaster caster(FloorMesh());
  const Eigen::Vector3d origin(0.1, 0.2, 2.0);
  const Eigen::Vector3d down = -Eigen::Vector3d::UnitZ();
  EXPECT_FALSE(caster.Intersect(origin, down, 1.999));
  EXPECT_FALSE(caster.Intersect(origin, down, 2.0 - 1e-9));
  ASSERT_TRUE(caster.Intersect(origin, down, 2.001));
  ASSERT_TRUE(caster.Intersect(origin, down, 2.0));
  EXPECT_EQ(caster.Intersect(origin, down, 2.0)->distance, 2.0);
  EXPECT_FALSE(caster.Occluded(origin, down, 1.999));
  EXPECT_TRUE(caster.Occluded(origin, down, 2.001));
}

// Distance to the cube [0, 1]^3 from outside by the slab method, with the
// normal of the face entered.
std::optional<std::pair<double, Eigen::Vector3d>> CubeEntry(
    const Eigen::Vector3d& origin, const Eigen::Vector3d& direction) {
  double entry = 0.0;
  double exit = std::numeric_limits<double>::infinity();
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  for (int axis = 0; axis < 3; ++axis) {
    if (direction(axis) == 0.0) {
      if (origin(axis) < 0.0 || origin(axis) > 1.0) return std::nullopt;
      continue;
    }
    double near = (0.0 - origin(axis)) / direction(axis);
    double far = (1.0 - origin(axis)) / direction(axis);
    Eigen::Vector3d near_normal = -Eigen::Vector3d::Unit(axis);
    if (near > far) {
      std::swap(near, far);
      near_normal = -near_normal;
    }
    if (near > entry) {
      entry = near;
      normal = near_normal;
    }
    exit = std::min(exit, far);
  }
  if (entry > exit) return std::nullopt;
  return std::make_pair(entry, normal);
}

TEST(RayCaster, HitsCubeFacesWithOutwardNormals) {
  const RayCaster caster(CubeMesh());
  std::mt19937_64 rng(2);
  std::uniform_real_distribution<double> unit(0.05, 0.95);
  int hits = 0;
  for (int k = 0; k < 2000; ++k) {
    const Eigen::Vector3d origin =
        Eigen::Vector3d::Constant(0.5) + 3.0 * RandomUnit(&rng);
    const Eigen::Vector3d target(unit(rng), unit(rng), unit(rng));
    // Half the rays aim at the cube, half anywhere.
    const Eigen::Vector3d direction =
        k % 2 == 0 ? Eigen::Vector3d((target - origin).normalized())
                   : RandomUnit(&rng);
    const auto expected = CubeEntry(origin, direction);
    const std::optional<RayCaster::Hit> hit =
        caster.Intersect(origin, direction);
    ASSERT_EQ(hit.has_value(), expected.has_value()) << k;
    if (!hit) continue;
    ++hits;
    EXPECT_NEAR(hit->distance, expected->first, 1e-12) << k;
    EXPECT_LT((hit->normal_in_world - expected->second).norm(), 1e-15) << k;
    EXPECT_TRUE(caster.Occluded(origin, direction, hit->distance + 1e-4));
    EXPECT_FALSE(caster.Occluded(origin, direction, hit->distance - 1e-4));
  }
  EXPECT_GT(hits, 1000);
  // From inside, the far face is hit from behind.
  const std::optional<RayCaster::Hit> inside =
      caster.Intersect({0.5, 0.5, 0.5}, Eigen::Vector3d::UnitZ());
  ASSERT_TRUE(inside.has_value());
  EXPECT_NEAR(inside->distance, 0.5, 1e-15);
  EXPECT_EQ(inside->normal_in_world, Eigen::Vector3d::UnitZ());
}

// A 300 m long, 30 m high wall leaning back by 0.1 m per metre, far from the
// world origin as a real survey in projected coordinates would be.
TEST(RayCaster, FarFromOriginStaysExact) {
  const Eigen::Vector3d offset(1e5, 2e5, -1000);
  const Eigen::Vector3d along(0, 300, 0);
  const Eigen::Vector3d up(-3, 0, 30);  // leans back 0.1 m per metre
  TriangleMesh mesh;
  AddGrid(offset, along, up, 300, 30, &mesh);
  const RayCaster caster(mesh);
  const Eigen::Vector3d normal = along.cross(up).normalized();
  ASSERT_GT(normal.x(), 0.0);  // faces +x, the water
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  double max_relative_error = 0.0;
  double max_plane_error = 0.0;
  for (int k = 0; k < 2000; ++k) {
    const Eigen::Vector3d on_wall = offset +
                                    (0.02 + 0.96 * uniform(rng)) * along +
                                    (0.1 + 0.8 * uniform(rng)) * up;
    const Eigen::Vector3d origin =
        on_wall + 3.0 * normal +
        Eigen::Vector3d(0, 2 * uniform(rng) - 1, 2 * uniform(rng) - 1);
    const Eigen::Vector3d direction = (on_wall - origin).normalized();
    const double expected = normal.dot(offset - origin) / normal.dot(direction);
    const std::optional<RayCaster::Hit> hit =
        caster.Intersect(origin, direction);
    ASSERT_TRUE(hit.has_value()) << k;
    max_relative_error = std::max(
        max_relative_error, std::abs(hit->distance - expected) / expected);
    max_plane_error = std::max(
        max_plane_error, std::abs(normal.dot(hit->point_in_world - offset)));
    // The grid vertices themselves are rounded at 2e5 m (3e-11 m).
    EXPECT_LT((hit->normal_in_world - normal).norm(), 1e-10);
    EXPECT_TRUE(caster.Occluded(origin, direction, expected + 1e-3));
    EXPECT_FALSE(caster.Occluded(origin, direction, expected - 1e-3));
  }
  // Float coordinates this far out would be off by ~1 cm, centred float
  // ones by ~1e-5 m, at ranges of ~3 m.
  EXPECT_LT(max_relative_error, 1e-9);
  EXPECT_LT(max_plane_error, 1e-9);
  std::printf(
      "[ figures ] 300 m wall at 1e5 m: max relative distance error "
      "%.2e, max off-plane %.2e m\n",
      max_relative_error, max_plane_error);
}

// A cylinder of radius 1 about the z axis, from z = -2 to 2, with
// triangles wound outwards. By symmetry its vertex normals are exactly
// radial, so interpolating them must give the true normal at any hit.
TriangleMesh CylinderMesh(int segments) {
  TriangleMesh mesh;
  for (int level = 0; level < 2; ++level) {
    for (int s = 0; s < segments; ++s) {
      const double phi = 2 * M_PI * s / segments;
      mesh.vertices.emplace_back(std::cos(phi), std::sin(phi),
                                 level == 0 ? -2.0 : 2.0);
    }
  }
  for (int s = 0; s < segments; ++s) {
    const int a = s;
    const int b = (s + 1) % segments;
    mesh.triangles.emplace_back(a, b, b + segments);
    mesh.triangles.emplace_back(a, b + segments, a + segments);
  }
  return mesh;
}

// Shading normals interpolate vertex normals: on a coarse cylinder they are
// the true normal where the flat facets are off by up to half a facet
// angle, and on a plane they are the plane's normal.
TEST(RayCaster, ShadingNormalsAreSmooth) {
  const RayCaster cylinder(CylinderMesh(16));
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> uniform(-0.9, 0.9);
  double max_geometric_error = 0.0;
  double max_shading_error = 0.0;
  for (int i = 0; i < 500; ++i) {
    const Eigen::Vector3d origin(3.0, uniform(rng), uniform(rng));
    const auto hit = cylinder.Intersect(origin, -Eigen::Vector3d::UnitX());
    ASSERT_TRUE(hit.has_value());
    const Eigen::Vector3d truth =
        Eigen::Vector3d(hit->point_in_world.x(), hit->point_in_world.y(), 0)
            .normalized();
    EXPECT_NEAR(hit->shading_normal_in_world.norm(), 1.0, 1e-12);
    max_geometric_error =
        std::max(max_geometric_error,
                 std::acos(std::min(1.0, hit->normal_in_world.dot(truth))));
    max_shading_error = std::max(
        max_shading_error,
        std::acos(std::min(1.0, hit->shading_normal_in_world.dot(truth))));
  }
  std::printf(
      "[ figures ] 16-sided cylinder: max normal error flat %.4f "
      "rad, smooth %.2e rad\n",
      max_geometric_error, max_shading_error);
  EXPECT_GT(max_geometric_error, 0.15);  // facets span 22.5 deg
  EXPECT_LT(max_shading_error, 1e-5);    // Embree's float barycentrics

  const RayCaster floor(FloorMesh());
  const auto hit = floor.Intersect(Eigen::Vector3d(0.3, -0.2, 2.0),
                                   -Eigen::Vector3d::UnitZ());
  ASSERT_TRUE(hit.has_value());
  EXPECT_LT((hit->shading_normal_in_world - hit->normal_in_world).norm(),
            1e-12);
}

TEST(RayCaster, ShadowRaysLeaveTheirSurface) {
  // A bumpy floor: ray back from any hit toward the origin must be clear.
  TriangleMesh mesh;
  AddGrid({-4, -4, 0}, {8, 0, 0}, {0, 8, 0}, 80, 80, &mesh);
  for (Eigen::Vector3d& vertex : mesh.vertices) {
    vertex.z() = 0.2 * std::sin(3 * vertex.x()) * std::cos(2 * vertex.y());
  }
  const RayCaster caster(mesh);
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> uniform(-3.0, 3.0);
  for (int k = 0; k < 2000; ++k) {
    const Eigen::Vector3d origin(uniform(rng), uniform(rng), 2.0);
    const Eigen::Vector3d direction =
        (Eigen::Vector3d(uniform(rng), uniform(rng), 0.0) - origin)
            .normalized();
    const std::optional<RayCaster::Hit> hit =
        caster.Intersect(origin, direction);
    ASSERT_TRUE(hit.has_value());
    const Eigen::Vector3d facing = hit->normal_in_world.dot(direction) < 0
                                       ? hit->normal_in_world
                                       : Eigen::Vector3d(-hit->normal_in_world);
    const double epsilon = caster.SurfaceEpsilon();
    EXPECT_FALSE(caster.Occluded(hit->point_in_world + epsilon * facing,
                                 -direction, hit->distance - 2 * epsilon))
        << k;
    EXPECT_FALSE(caster.Intersect(hit->point_in_world + epsilon * facing,
                                  -direction, hit->distance - 2 * epsilon))
        << k;
  }
}

TEST(RayCaster, ConcurrentQueriesMatchSerial) {
  const RayCaster caster(CubeMesh());
  std::mt19937_64 rng(5);
  std::vector<Eigen::Vector3d> origins;
  std::vector<Eigen::Vector3d> directions;
  for (int k = 0; k < 20000; ++k) {
    origins.push_back(Eigen::Vector3d::Constant(0.5) + 2.0 * RandomUnit(&rng));
    directions.push_back((Eigen::Vector3d::Constant(0.5) +
                          0.4 * RandomUnit(&rng) - origins.back())
                             .normalized());
  }
  std::vector<double> serial(origins.size());
  for (size_t k = 0; k < origins.size(); ++k) {
    serial[k] = caster.Intersect(origins[k], directions[k])->distance;
  }
  std::vector<double> parallel(origins.size());
  tbb::parallel_for(size_t{0}, origins.size(), [&](size_t k) {
    parallel[k] = caster.Intersect(origins[k], directions[k])->distance;
  });
  EXPECT_EQ(serial, parallel);
}

TEST(RayCaster, MovesAndKeepsZeroAreaTrianglesUnhittable) {
  TriangleMesh mesh = FloorMesh();
  // A zero-area triangle across the floor's centre.
  const int first = static_cast<int>(mesh.vertices.size());
  mesh.vertices.push_back({-1, 0, 0.5});
  mesh.vertices.push_back({0, 0, 0.5});
  mesh.vertices.push_back({1, 0, 0.5});
  mesh.triangles.emplace_back(first, first + 1, first + 2);
  RayCaster original(mesh);
  RayCaster moved(std::move(original));
  const std::optional<RayCaster::Hit> hit =
      moved.Intersect({0.0, 0.0, 1.0}, -Eigen::Vector3d::UnitZ());
  ASSERT_TRUE(hit.has_value());
  EXPECT_EQ(hit->distance, 1.0);
  RayCaster assigned(CubeMesh());
  assigned = std::move(moved);
  EXPECT_TRUE(assigned.Intersect({0.0, 0.0, 1.0}, -Eigen::Vector3d::UnitZ()));
}

TEST(RayCaster, RejectsBadMeshes) {
  EXPECT_THROW(RayCaster{TriangleMesh{}}, Error);
  TriangleMesh bad_index = FloorMesh();
  bad_index.triangles.back()(2) = static_cast<int>(bad_index.vertices.size());
  EXPECT_THROW(RayCaster{bad_index}, Error);
  TriangleMesh negative_index = FloorMesh();
  negative_index.triangles.front()(0) = -1;
  EXPECT_THROW(RayCaster{negative_index}, Error);
  TriangleMesh not_finite = FloorMesh();
  not_finite.vertices[3].y() = std::nan("");
  EXPECT_THROW(RayCaster{not_finite}, Error);
  TriangleMesh flat;
  flat.vertices = {{0, 0, 0}, {1, 1, 1}, {2, 2, 2}};
  flat.triangles = {{0, 1, 2}, {0, 0, 1}};
  try {
    RayCaster caster(flat);
    FAIL() << "expected uw::Error";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("zero area"), std::string::npos)
        << error.what();
  }
}

}  // namespace
}  // namespace uw
