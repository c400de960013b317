#include "sim/exe/generate_command.h"

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

namespace uw::sim {
namespace {

namespace fs = std::filesystem;

TEST(GenerateConfig, FlagsGivenOverrideTheConfigurationFile) {
  const fs::path dir = fs::temp_directory_path() / "uw_generate_command_test";
  fs::create_directories(dir);
  const fs::path path = dir / "sim.json";
  std::ofstream(path) << R"({"world": "scarp", "survey": "single_pass",
      "seed": 4, "survey_options": {"max_images": 9}})";
  GenerateCommandOptions options;
  options.config_path = path.string();
  SimConfig config = GenerateConfig(options);
  EXPECT_EQ(config.world, WorldKind::kScarp);
  EXPECT_EQ(config.survey, SurveyKind::kSinglePass);
  EXPECT_EQ(config.seed, 4u);
  EXPECT_EQ(config.survey_options.max_images, 9);

  options.world = WorldKind::kVent;
  options.seed = 11;
  options.max_images = 3;
  config = GenerateConfig(options);
  EXPECT_EQ(config.world, WorldKind::kVent);
  EXPECT_EQ(config.survey, SurveyKind::kSinglePass);
  EXPECT_EQ(config.seed, 11u);
  EXPECT_EQ(config.survey_options.max_images, 3);
  // A negative --max_images is as if it were not given.
  options.max_images = -1;
  EXPECT_EQ(GenerateConfig(options).survey_options.max_images, 9);
  fs::remove_all(dir);
}

TEST(GenerateConfig, WithoutAFileTheDefaultsAndTheFlags) {
  GenerateCommandOptions options;
  EXPECT_EQ(nlohmann::json(GenerateConfig(options)),
            nlohmann::json(SimConfig()));
  options.survey = SurveyKind::kVideo;
  EXPECT_EQ(GenerateConfig(options).survey, SurveyKind::kVideo);
}

}  // namespace
}  // namespace uw::sim
