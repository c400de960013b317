#include "sim/generate.h"

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "sim/test_sim_config.h"

namespace uw::sim {
namespace {

namespace fs = std::filesystem;

std::string FileBytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

// Without images the folder holds every other file a rendered run writes,
// each the same bytes (sim.json but for "rendered"): a plan's truth is the
// truth of the survey one would render.
TEST(Generate, WithoutImagesWritesTheRenderedRunsTruth) {
  SimConfig config = SmallSimConfig();
  config.survey_options.max_images = 6;
  const fs::path dir =
      fs::temp_directory_path() / ("uw_generate_" + std::to_string(getpid()));
  fs::remove_all(dir);
  const GenerateSummary rendered = Generate(config, dir / "rendered");
  size_t planned_frames = 0;
  const GenerateSummary planned = Generate(
      config, dir / "planned", [&](size_t, size_t) { ++planned_frames; },
      false);
  EXPECT_EQ(planned_frames, 0u);
  EXPECT_EQ(planned.num_images, rendered.num_images);
  EXPECT_EQ(planned.num_laser_images, rendered.num_laser_images);
  ASSERT_GT(rendered.num_laser_images, 0u);
  EXPECT_TRUE(fs::is_directory(dir / "rendered" / "images"));
  EXPECT_TRUE(fs::is_directory(dir / "rendered" / "laser_images"));
  EXPECT_FALSE(fs::exists(dir / "planned" / "images"));
  EXPECT_FALSE(fs::exists(dir / "planned" / "laser_images"));

  size_t compared = 0;
  for (const fs::directory_entry& entry :
       fs::recursive_directory_iterator(dir / "rendered")) {
    const fs::path relative = entry.path().lexically_relative(dir / "rendered");
    const std::string top = relative.begin()->string();
    if (!entry.is_regular_file() || top == "images" || top == "laser_images" ||
        relative == fs::path("truth") / "sim.json") {
      continue;
    }
    ASSERT_TRUE(fs::exists(dir / "planned" / relative)) << relative;
    EXPECT_EQ(FileBytes(dir / "planned" / relative), FileBytes(entry.path()))
        << relative;
    ++compared;
  }
  EXPECT_GE(compared, 10u);  // nav, lasers, truth/{model, mesh, ...}

  nlohmann::json rendered_sim =
      nlohmann::json::parse(FileBytes(dir / "rendered" / "truth" / "sim.json"));
  nlohmann::json planned_sim =
      nlohmann::json::parse(FileBytes(dir / "planned" / "truth" / "sim.json"));
  EXPECT_EQ(rendered_sim["truth"]["rendered"], true);
  EXPECT_EQ(planned_sim["truth"]["rendered"], false);
  planned_sim["truth"]["rendered"] = true;
  EXPECT_EQ(planned_sim, rendered_sim);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace uw::sim
