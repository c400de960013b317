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

#include "colmap_plugins/util/error.h"

namespace uw::sim {
namespace {

constexpr WorldKind kKinds[] = {WorldKind::kSeafloor, WorldKind::kVent,
                                WorldKind::kScarp};

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
  EXPECT_NE(message.find("seafloor, vent, scarp"), std::string::npos)
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
  rejects([](auto& o) { o.texture.grain_octaves = 9; }, "grain_octaves");
}

TEST(WorldTest, OptionsJsonRoundTrip) {
  WorldOptions options;
  options.seafloor.length_m = 30.5;
  options.seafloor.rocks.count = 7;
  options.vent.ground_relief.roughness_wavelength_m = 0.33;
  options.vent.flange_count = 5;
  options.scarp.dip_deg = 75.25;
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
  EXPECT_EQ(read.texture.grain_octaves, 3);
  EXPECT_EQ(read.texture.rock_albedo[2], 0.3);
  // Every field is written: a reader with other defaults gets them all.
  EXPECT_EQ(json["vent"]["chimney_height_m"], 10.0);
  EXPECT_EQ(json["seafloor"]["relief"]["undulation_wavelength_m"], 8.0);
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
  message = error(R"({"scarp": 3})");
  EXPECT_NE(message.find("scarp: expected a JSON object"), std::string::npos)
      << message;
}

}  // namespace
}  // namespace uw::sim
