#include "sim/sim_config.h"

#include <fstream>

#include <gtest/gtest.h>

#include "common/util/error_testing.h"
#include "common/util/file.h"

namespace uw::sim {
namespace {

namespace fs = std::filesystem;

TEST(SimConfig, JsonRoundTripsEverySection) {
  SimConfig config;
  config.world = WorldKind::kCanyon;
  config.survey = SurveyKind::kViews;
  config.seed = 12345678901234ull;
  config.camera.width = 640;
  config.world_options.canyon.floor_width_m = 9.0;
  config.survey_options.max_images = 7;
  config.navigation.dive_biases_m = {{1, 2, 0}};
  config.render.sensor.jpeg_quality = 80;
  config.lasers.every_nth_image = 2;
  config.logs.clock_start = "2024-10-08T12:00:00+02:00";
  config.logs.nav_formats = {"nmea", "utm"};
  config.logs.geodetic_origin = "43.25,5.375";
  const nlohmann::json json = config;
  SimConfig read;
  json.get_to(read);
  EXPECT_EQ(nlohmann::json(read), json);
  EXPECT_EQ(read.world, WorldKind::kCanyon);
  EXPECT_EQ(read.survey, SurveyKind::kViews);
  EXPECT_EQ(read.seed, 12345678901234ull);
  EXPECT_EQ(read.camera.width, 640u);
  EXPECT_EQ(read.camera.camera_id, 1u);
  EXPECT_EQ(read.logs.nav_formats, config.logs.nav_formats);
}

TEST(SimConfig, SectionsLeftOutKeepTheirDefaults) {
  SimConfig read;
  nlohmann::json::parse(
      R"({"world": "vent", "lasers": {"every_nth_image": 0}})")
      .get_to(read);
  EXPECT_EQ(read.world, WorldKind::kVent);
  EXPECT_EQ(read.survey, SimConfig().survey);
  EXPECT_EQ(read.seed, SimConfig().seed);
  EXPECT_EQ(read.lasers.every_nth_image, 0);
  EXPECT_EQ(nlohmann::json(read.world_options), nlohmann::json(WorldOptions()));
}

TEST(SimConfig, ReadingAFileNamesItInEveryError) {
  const fs::path dir = fs::temp_directory_path() / "uw_sim_config_test";
  fs::create_directories(dir);
  const fs::path path = dir / "my_sim.json";
  const auto error_of = [&](const std::string& text) {
    std::ofstream(path) << text;
    try {
      ReadSimConfig(path);
    } catch (const Error& error) {
      return std::string(error.what());
    }
    return std::string("(no uw::Error)");
  };
  const std::string file = path.string() + ": ";
  const auto starts = [](const std::string& message, const std::string& start) {
    EXPECT_EQ(message.substr(0, start.size()), start);
  };
  starts(error_of(R"({"volcano": 1})"),
         file + "configuration: unknown key \"volcano\" (valid");
  EXPECT_EQ(error_of(R"({"seed": "x"})"),
            file + "configuration.seed: expected an integer, got \"x\"");
  starts(error_of(R"({"world": "reef"})"), file + "unknown world \"reef\"");
  EXPECT_EQ(error_of("3"),
            file + "configuration: expected a JSON object, got 3");
  starts(error_of(R"({"navigation": {"speed": 1}})"),
         file + "navigation: unknown key \"speed\"");
  starts(error_of("[1"), file + "[json.exception");
  std::ofstream(path) << R"({"survey": "video", "seed": 3})";
  const SimConfig read = ReadSimConfig(path);
  EXPECT_EQ(read.survey, SurveyKind::kVideo);
  EXPECT_EQ(read.seed, 3u);
  ExpectErrorContaining([&] { ReadSimConfig(dir / "missing.json"); },
                        "missing.json");
  fs::remove_all(dir);
}

}  // namespace
}  // namespace uw::sim
