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
#include "sim/world_testing.h"

namespace uw::sim {
namespace {

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
