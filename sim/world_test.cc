#include "sim/world.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <optional>
#include <random>
#include <utility>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "common/util/error.h"

namespace uw::sim {
namespace {

constexpr WorldKind kKinds[] = {WorldKind::kSeafloor, WorldKind::kVent,
                                WorldKind::kScarp, WorldKind::kBreakwater,
                                WorldKind::kCanyon};

// Worlds small enough to build in a few milliseconds; the default worlds
// are built once each, in the tests named after them.
WorldOptions SmallOptions() {
  WorldOptions options;
  options.seafloor.length_m = 4.0;
  options.seafloor.width_m = 3.0;
  options.seafloor.vertex_spacing_m = 0.05;
  options.seafloor.rocks.count = 4;
  options.vent.ground_size_m = 16.0;
  options.vent.ground_vertex_spacing_m = 0.2;
  options.vent.chimney_vertex_spacing_m = 0.1;
  options.vent.ground_rocks.count = 5;
  options.scarp.length_m = 20.0;
  options.scarp.vertex_spacing_m = 0.25;
  options.breakwater.length_m = 6.0;
  options.breakwater.height_m = 3.0;
  options.breakwater.crest_width_m = 2.0;
  options.breakwater.apron_width_m = 2.0;
  options.breakwater.vertex_spacing_m = 0.1;
  options.breakwater.block_size_m = 0.8;
  options.breakwater.rocks = {5, 0.3, 1.0};
  options.canyon.length_m = 12.0;
  options.canyon.width_m = 18.0;
  options.canyon.floor_width_m = 5.0;
  options.canyon.wall_height_m = 4.0;
  options.canyon.wall_height_variation_m = 1.0;
  options.canyon.wall_slope_deg = 60.0;
  options.canyon.meander_amplitude_m = 1.0;
  options.canyon.meander_wavelength_m = 12.0;
  options.canyon.wall_relief_m = 0.3;
  options.canyon.wall_relief_wavelength_m = 2.0;
  options.canyon.vertex_spacing_m = 0.15;
  options.canyon.rocks = {4, 0.3, 1.0};
  return options;
}

std::string ErrorOf(const std::function<void()>& run) {
  try {
    run();
  } catch (const Error& error) {
    return error.what();
  }
  return "(no uw::Error)";
}

double TriangleArea(const TriangleMesh& mesh, size_t t) {
  const Eigen::Vector3i& f = mesh.triangles[t];
  return 0.5 * (mesh.vertices[f[1]] - mesh.vertices[f[0]])
                   .cross(mesh.vertices[f[2]] - mesh.vertices[f[0]])
                   .norm();
}

Eigen::Vector3d Centroid(const TriangleMesh& mesh, size_t t) {
  const Eigen::Vector3i& f = mesh.triangles[t];
  return (mesh.vertices[f[0]] + mesh.vertices[f[1]] + mesh.vertices[f[2]]) /
         3.0;
}

// Brute-force first hit (Moller-Trumbore) of the ray origin + t * direction,
// t > 0: the triangle index and distance.
std::optional<std::pair<size_t, double>> FirstHit(
    const TriangleMesh& mesh, const Eigen::Vector3d& origin,
    const Eigen::Vector3d& direction) {
  std::optional<std::pair<size_t, double>> best;
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Eigen::Vector3i& f = mesh.triangles[t];
    const Eigen::Vector3d& a = mesh.vertices[f[0]];
    const Eigen::Vector3d e1 = mesh.vertices[f[1]] - a;
    const Eigen::Vector3d e2 = mesh.vertices[f[2]] - a;
    const Eigen::Vector3d p = direction.cross(e2);
    const double det = e1.dot(p);
    if (std::abs(det) < 1e-15) continue;
    const Eigen::Vector3d s = origin - a;
    const double u = s.dot(p) / det;
    if (u < 0.0 || u > 1.0) continue;
    const Eigen::Vector3d q = s.cross(e1);
    const double v = direction.dot(q) / det;
    if (v < 0.0 || u + v > 1.0) continue;
    const double distance = e2.dot(q) / det;
    if (distance > 1e-9 && (!best || distance < best->second)) {
      best = std::make_pair(t, distance);
    }
  }
  return best;
}

// Rays from the water towards the surface must first meet a triangle
// whose normal faces them: the normals point into the water.
void ExpectRaysMeetFrontFaces(const World& world,
                              const std::vector<Eigen::Vector3d>& origins,
                              const std::vector<Eigen::Vector3d>& directions) {
  for (size_t r = 0; r < origins.size(); ++r) {
    const auto hit = FirstHit(world.mesh, origins[r], directions[r]);
    ASSERT_TRUE(hit) << world.name << " ray " << r;
    EXPECT_LT(world.mesh.TriangleNormal(hit->first).dot(directions[r]), 0.0)
        << world.name << " ray " << r << " from " << origins[r].transpose();
  }
}

// A consistently oriented surface uses each directed edge at most once
// (a flipped neighbour would repeat it).
void ExpectConsistentOrientation(const TriangleMesh& mesh) {
  std::vector<std::pair<int64_t, int>> edges;
  edges.reserve(3 * mesh.triangles.size());
  for (const Eigen::Vector3i& f : mesh.triangles) {
    for (int k = 0; k < 3; ++k) {
      edges.emplace_back(static_cast<int64_t>(f[k]) << 32 | f[(k + 1) % 3], 0);
    }
  }
  std::sort(edges.begin(), edges.end());
  const auto repeated = std::adjacent_find(
      edges.begin(), edges.end(),
      [](const auto& a, const auto& b) { return a.first == b.first; });
  EXPECT_TRUE(repeated == edges.end())
      << "directed edge " << (repeated->first >> 32) << " -> "
      << (repeated->first & 0xffffffff) << " used twice";
}

// Heights of the vertices in a box of the plane: the worlds built as
// heightfields have one vertex per grid point.
std::vector<double> HeightsIn(const World& world, double x0, double x1,
                              double y0, double y1) {
  std::vector<double> heights;
  for (const Eigen::Vector3d& vertex : world.mesh.vertices) {
    if (vertex.x() >= x0 && vertex.x() <= x1 && vertex.y() >= y0 &&
        vertex.y() <= y1) {
      heights.push_back(vertex.z());
    }
  }
  return heights;
}

double MaxHeightIn(const World& world, double x0, double x1, double y0,
                   double y1) {
  const std::vector<double> heights = HeightsIn(world, x0, x1, y0, y1);
  EXPECT_FALSE(heights.empty()) << "no vertex in [" << x0 << ", " << x1
                                << "] x [" << y0 << ", " << y1 << "]";
  return heights.empty() ? std::numeric_limits<double>::quiet_NaN()
                         : *std::max_element(heights.begin(), heights.end());
}

// The (y, z) of a heightfield's vertices within `tolerance` of x = x0,
// sorted by y.
std::vector<std::pair<double, double>> CrossSection(const World& world,
                                                    double x0,
                                                    double tolerance) {
  std::vector<std::pair<double, double>> section;
  for (const Eigen::Vector3d& vertex : world.mesh.vertices) {
    if (std::abs(vertex.x() - x0) <= tolerance) {
      section.emplace_back(vertex.y(), vertex.z());
    }
  }
  std::sort(section.begin(), section.end());
  return section;
}

void ExpectNormalsUp(const World& world) {
  for (size_t t = 0; t < world.mesh.triangles.size(); ++t) {
    ASSERT_GT(world.mesh.TriangleNormal(t).z(), 0.0) << "triangle " << t;
  }
}

void ExpectUnitSurveyFrame(const World& world) {
  EXPECT_NEAR(world.survey_normal.norm(), 1.0, 1e-12);
  EXPECT_NEAR(world.survey_along.norm(), 1.0, 1e-12);
  EXPECT_NEAR(world.survey_normal.dot(world.survey_along), 0.0, 1e-12);
  EXPECT_GT(world.survey_length, 0.0);
  EXPECT_GT(world.survey_width, 0.0);
  EXPECT_TRUE(world.bounds.contains(world.survey_origin))
      << world.survey_origin.transpose();
}

TEST(WorldTest, KindNamesRoundTrip) {
  for (const WorldKind kind : kKinds) {
    EXPECT_EQ(WorldKindFromName(WorldKindName(kind)), kind);
  }
  const std::string message = ErrorOf([] { WorldKindFromName("reef"); });
  EXPECT_NE(message.find("\"reef\""), std::string::npos) << message;
  EXPECT_NE(message.find("seafloor, vent, scarp, breakwater, canyon"),
            std::string::npos)
      << message;
}

TEST(WorldTest, SameSeedSameBitsDifferentSeedDifferent) {
  const WorldOptions options = SmallOptions();
  for (const WorldKind kind : kKinds) {
    const World a = MakeWorld(kind, options, 5);
    const World b = MakeWorld(kind, options, 5);
    const World c = MakeWorld(kind, options, 6);
    ASSERT_EQ(a.mesh.vertices.size(), b.mesh.vertices.size());
    EXPECT_EQ(std::memcmp(a.mesh.vertices.data(), b.mesh.vertices.data(),
                          a.mesh.vertices.size() * sizeof(Eigen::Vector3d)),
              0)
        << a.name;
    EXPECT_TRUE(a.mesh.triangles == b.mesh.triangles) << a.name;
    EXPECT_EQ(a.survey_origin, b.survey_origin);
    const Eigen::Vector3d point = a.survey_origin + Eigen::Vector3d(0.1, 0, 0);
    const Eigen::Vector3f albedo_a = a.texture->Albedo(point, a.survey_normal);
    const Eigen::Vector3f albedo_b = b.texture->Albedo(point, b.survey_normal);
    EXPECT_EQ(std::memcmp(albedo_a.data(), albedo_b.data(), sizeof(albedo_a)),
              0);
    const bool same_size = a.mesh.vertices.size() == c.mesh.vertices.size();
    EXPECT_TRUE(!same_size ||
                std::memcmp(a.mesh.vertices.data(), c.mesh.vertices.data(),
                            a.mesh.vertices.size() * sizeof(Eigen::Vector3d)) !=
                    0)
        << a.name;
    EXPECT_FALSE(albedo_a.isApprox(c.texture->Albedo(point, c.survey_normal)));
  }
}

TEST(WorldTest, SmallWorldsAreOrientedTowardsTheWater) {
  const WorldOptions options = SmallOptions();
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (const WorldKind kind : kKinds) {
    const World world = MakeWorld(kind, options, 8);
    ExpectConsistentOrientation(world.mesh);
    ExpectUnitSurveyFrame(world);
    const Eigen::Vector3d across =
        world.survey_normal.cross(world.survey_along);
    std::vector<Eigen::Vector3d> origins, directions;
    for (int r = 0; r < 12; ++r) {
      // From 2 m off the survey plane (above the chimney's top for the
      // vent), over the middle of the survey area, slanted up to ~16 deg.
      origins.push_back(world.survey_origin +
                        0.25 * world.survey_length * uniform(rng) *
                            world.survey_along +
                        0.25 * world.survey_width * uniform(rng) * across +
                        2.0 * world.survey_normal);
      directions.push_back((-world.survey_normal +
                            0.2 * uniform(rng) * world.survey_along +
                            0.2 * uniform(rng) * across)
                               .normalized());
    }
    if (kind == WorldKind::kVent) {
      // Horizontal rays at the chimney from all sides.
      for (int r = 0; r < 8; ++r) {
        const double theta = 2.0 * M_PI * r / 8;
        const Eigen::Vector3d towards(std::cos(theta), std::sin(theta), 0.0);
        origins.push_back(Eigen::Vector3d(0, 0, 3.0 + 0.8 * r) - 6.9 * towards);
        directions.push_back(towards);
      }
    }
    if (kind == WorldKind::kBreakwater) {
      // Horizontal rays at the mound's mid-height from all sides (1.5 m of
      // the 3 m mound; its crest is 6 m x 2 m).
      for (int r = 0; r < 8; ++r) {
        const double theta = 2.0 * M_PI * r / 8;
        const Eigen::Vector3d towards(std::cos(theta), std::sin(theta), 0.0);
        origins.push_back(Eigen::Vector3d(0, 0, 1.5) - 9.0 * towards);
        directions.push_back(towards);
      }
    }
    if (kind == WorldKind::kCanyon) {
      // Horizontal rays from above the floor strip at both walls, 2 m up
      // the 4 m walls.
      for (int r = 0; r < 8; ++r) {
        const Eigen::Vector3d towards(0.0, r % 2 == 0 ? 1.0 : -1.0, 0.0);
        origins.push_back(world.survey_origin +
                          Eigen::Vector3d(-4.5 + 1.3 * r, 0.0, 2.0));
        directions.push_back(towards);
      }
    }
    ExpectRaysMeetFrontFaces(world, origins, directions);
  }
}

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

TEST(WorldTest, RocksOnlyRaiseTheFloor) {
  WorldOptions options = SmallOptions();
  options.seafloor.length_m = 8.0;
  options.seafloor.width_m = 6.0;
  options.seafloor.rocks.count = 0;
  const World bare = MakeWorld(WorldKind::kSeafloor, options, 3);
  options.seafloor.rocks.count = 12;
  const World rocky = MakeWorld(WorldKind::kSeafloor, options, 3);
  ASSERT_EQ(bare.mesh.vertices.size(), rocky.mesh.vertices.size());
  int raised = 0;
  double highest = 0.0;
  for (size_t i = 0; i < bare.mesh.vertices.size(); ++i) {
    const double rise = rocky.mesh.vertices[i].z() - bare.mesh.vertices[i].z();
    ASSERT_GE(rise, 0.0);
    raised += rise > 0.0;
    highest = std::max(highest, rise);
  }
  EXPECT_GT(raised, 100);
  EXPECT_GT(highest, 0.1);  // the smallest rock is 0.2 m across
  EXPECT_LT(highest, 1.0);  // and the largest 1 m
}

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

// The breakwater's rocks lie on the seafloor around the mound and the
// canyon's on its floor: every vertex a rock raises was low before.
TEST(WorldTest, BreakwaterAndCanyonRocksLieOnTheFloor) {
  for (const WorldKind kind : {WorldKind::kBreakwater, WorldKind::kCanyon}) {
    WorldOptions options = SmallOptions();
    RockOptions& rocks = kind == WorldKind::kBreakwater
                             ? options.breakwater.rocks
                             : options.canyon.rocks;
    rocks.count = 0;
    const World bare = MakeWorld(kind, options, 3);
    rocks.count = 12;
    const World rocky = MakeWorld(kind, options, 3);
    ASSERT_EQ(bare.mesh.vertices.size(), rocky.mesh.vertices.size());
    int raised = 0;
    double highest_ground = -std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < bare.mesh.vertices.size(); ++i) {
      const double rise =
          rocky.mesh.vertices[i].z() - bare.mesh.vertices[i].z();
      ASSERT_GE(rise, 0.0) << bare.name;
      if (rise > 0.0) {
        ++raised;
        highest_ground = std::max(highest_ground, bare.mesh.vertices[i].z());
      }
    }
    EXPECT_GT(raised, 50) << bare.name;
    // The mound is 3 m high and the canyon's walls ~4 m; the floors' relief
    // is a few dm.
    EXPECT_LT(highest_ground, 1.0) << bare.name;
  }
}

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

TEST(WorldTest, CheckRejectsNonsense) {
  EXPECT_NO_THROW(WorldOptions().Check());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const auto rejects = [](const std::function<void(WorldOptions&)>& modify,
                          const std::string& expected) {
    WorldOptions options;
    modify(options);
    const std::string message = ErrorOf([&] { options.Check(); });
    EXPECT_NE(message.find(expected), std::string::npos)
        << "expected \"" << expected << "\" in: " << message;
    EXPECT_THROW(MakeWorld(WorldKind::kSeafloor, options, 1), Error);
  };
  rejects([](auto& o) { o.seafloor.length_m = -24.0; }, "seafloor.length_m");
  rejects([&](auto& o) { o.seafloor.vertex_spacing_m = nan; },
          "seafloor.vertex_spacing_m = nan");
  rejects([](auto& o) { o.seafloor.vertex_spacing_m = 0.001; },
          "triangles exceed the limit");
  rejects([](auto& o) { o.seafloor.relief.roughness_amplitude_m = -1.0; },
          "seafloor.relief.roughness_amplitude_m");
  rejects([](auto& o) { o.seafloor.rocks.min_diameter_m = 2.0; },
          "seafloor.rocks.min_diameter_m = 2: exceeds max_diameter_m");
  rejects([](auto& o) { o.seafloor.rocks.count = -1; }, "seafloor.rocks.count");
  rejects([](auto& o) { o.vent.flange_count = -1; }, "vent.flange_count");
  rejects([](auto& o) { o.vent.ground_size_m = 8.0; },
          "vent.ground_size_m = 8: the ground must extend");
  rejects([&](auto& o) { o.vent.chimney_height_m = nan; },
          "vent.chimney_height_m");
  rejects([](auto& o) { o.vent.flange_max_width_m = 0.1; },
          "vent.flange_min_width_m");
  rejects([](auto& o) { o.scarp.dip_deg = 30.0; }, "scarp.dip_deg = 30");
  rejects([](auto& o) { o.scarp.dip_deg = 95.0; }, "scarp.dip_deg = 95");
  rejects([](auto& o) { o.scarp.height_m = 1.0; }, "scarp.height_m = 1");
  rejects([](auto& o) { o.scarp.foot_width_m = 0.5; }, "scarp.foot_width_m");
  rejects([&](auto& o) { o.scarp.meander_wavelength_m = nan; },
          "scarp.meander_wavelength_m");
  rejects([](auto& o) { o.breakwater.slope_deg = 70.0; },
          "breakwater.slope_deg = 70");
  rejects([](auto& o) { o.breakwater.crest_width_m = -1.0; },
          "breakwater.crest_width_m");
  rejects([](auto& o) { o.breakwater.block_size_m = 0.1; },
          "breakwater.block_size_m = 0.1: must span at least 4 vertex");
  rejects([](auto& o) { o.breakwater.height_m = 2.0; },
          "breakwater.height_m = 2: must exceed the armour's thickness");
  rejects([](auto& o) { o.breakwater.block_layers = 0; },
          "breakwater.block_layers = 0");
  rejects([](auto& o) { o.breakwater.rocks.max_diameter_m = 7.0; },
          "breakwater.rocks.max_diameter_m = 7: rocks must fit on the apron");
  rejects([](auto& o) { o.breakwater.vertex_spacing_m = 0.005; },
          "breakwater: about");
  rejects([&](auto& o) { o.breakwater.block_tilt_deg = nan; },
          "breakwater.block_tilt_deg = nan");
  rejects([](auto& o) { o.canyon.floor_width_m = 7.0; },
          "canyon.floor_width_m = 7: leaves a straight strip of 0.4 m along "
          "the floor; must be at least 7.6 m");
  rejects([](auto& o) { o.canyon.width_m = 25.0; },
          "canyon.width_m = 25: too narrow");
  rejects([](auto& o) { o.canyon.wall_slope_deg = 85.0; },
          "canyon.wall_slope_deg = 85");
  rejects([](auto& o) { o.canyon.wall_height_variation_m = 6.0; },
          "canyon.wall_height_variation_m = 6");
  rejects([](auto& o) { o.canyon.rocks.max_diameter_m = 9.0; },
          "canyon.rocks.max_diameter_m = 9: rocks must fit on the floor");
  rejects([&](auto& o) { o.canyon.meander_wavelength_m = nan; },
          "canyon.meander_wavelength_m");
  rejects([](auto& o) { o.canyon.vertex_spacing_m = 0.001; }, "canyon: about");
  rejects([](auto& o) { o.texture.grain_octaves = 9; }, "grain_octaves");
}

TEST(WorldTest, OptionsJsonRoundTrip) {
  WorldOptions options;
  options.seafloor.length_m = 30.5;
  options.seafloor.rocks.count = 7;
  options.vent.ground_relief.roughness_wavelength_m = 0.33;
  options.vent.flange_count = 5;
  options.scarp.dip_deg = 75.25;
  options.breakwater.slope_deg = 26.5;
  options.breakwater.block_layers = 3;
  options.breakwater.rocks.count = 11;
  options.canyon.wall_height_variation_m = 1.25;
  options.canyon.relief.undulation_amplitude_m = 0.45;
  options.texture.grain_octaves = 3;
  options.texture.rock_albedo = {0.1, 0.2, 0.3};
  const nlohmann::json json = options;
  WorldOptions read;
  json.get_to(read);
  EXPECT_EQ(nlohmann::json(read), json);
  EXPECT_EQ(read.seafloor.length_m, 30.5);
  EXPECT_EQ(read.seafloor.rocks.count, 7);
  EXPECT_EQ(read.vent.ground_relief.roughness_wavelength_m, 0.33);
  EXPECT_EQ(read.vent.flange_count, 5);
  EXPECT_EQ(read.scarp.dip_deg, 75.25);
  EXPECT_EQ(read.breakwater.slope_deg, 26.5);
  EXPECT_EQ(read.breakwater.block_layers, 3);
  EXPECT_EQ(read.breakwater.rocks.count, 11);
  EXPECT_EQ(read.canyon.wall_height_variation_m, 1.25);
  EXPECT_EQ(read.canyon.relief.undulation_amplitude_m, 0.45);
  EXPECT_EQ(read.texture.grain_octaves, 3);
  EXPECT_EQ(read.texture.rock_albedo[2], 0.3);
  // Every field is written: a reader with other defaults gets them all.
  EXPECT_EQ(json["vent"]["chimney_height_m"], 10.0);
  EXPECT_EQ(json["seafloor"]["relief"]["undulation_wavelength_m"], 8.0);
  EXPECT_EQ(json["breakwater"]["block_size_m"], 1.6);
  EXPECT_EQ(json["canyon"]["floor_width_m"], 8.0);
  EXPECT_EQ(json["canyon"]["rocks"]["max_diameter_m"], 1.6);
}

TEST(WorldTest, OptionsJsonKeepsDefaultsAndRejectsBadKeys) {
  WorldOptions options;
  nlohmann::json::parse(R"({"scarp": {"length_m": 120, "relief": {}}})")
      .get_to(options);
  EXPECT_EQ(options.scarp.length_m, 120.0);
  EXPECT_EQ(options.scarp.height_m, WorldOptions().scarp.height_m);
  EXPECT_EQ(options.seafloor.length_m, WorldOptions().seafloor.length_m);

  const auto error = [](const std::string& text) {
    return ErrorOf([&] {
      WorldOptions ignored;
      nlohmann::json::parse(text).get_to(ignored);
    });
  };
  std::string message = error(R"({"seafloor": {"lenght_m": 3}})");
  EXPECT_NE(message.find("seafloor: unknown key \"lenght_m\""),
            std::string::npos)
      << message;
  EXPECT_NE(message.find("length_m, width_m"), std::string::npos) << message;
  message = error(R"({"volcano": {}})");
  EXPECT_NE(message.find("unknown key \"volcano\""), std::string::npos)
      << message;
  message = error(R"({"vent": {"flange_count": 2.5}})");
  EXPECT_NE(message.find("vent.flange_count: expected an integer, got 2.5"),
            std::string::npos)
      << message;
  message = error(R"({"seafloor": {"rocks": {"max_diameter_m": "big"}}})");
  EXPECT_NE(message.find("seafloor.rocks.max_diameter_m: expected a number"),
            std::string::npos)
      << message;
  message = error(R"({"texture": {"rock_albedo": [0.1, 0.2]}})");
  EXPECT_NE(message.find("texture.rock_albedo: expected an array of 3"),
            std::string::npos)
      << message;
  message = error(R"({"canyon": {"wall_slope": 70}})");
  EXPECT_NE(message.find("canyon: unknown key \"wall_slope\""),
            std::string::npos)
      << message;
  message = error(R"({"breakwater": {"block_layers": 1.5}})");
  EXPECT_NE(
      message.find("breakwater.block_layers: expected an integer, got 1.5"),
      std::string::npos)
      << message;
  message = error(R"({"scarp": 3})");
  EXPECT_NE(message.find("scarp: expected a JSON object"), std::string::npos)
      << message;
}

}  // namespace
}  // namespace uw::sim
