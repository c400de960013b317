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

// Each laser image has a time, as its file's time stamp would give a user,
// so that the navigation places it before matching: the truth's, within the
// survey's span.
TEST(Generate, TimesEveryLaserImage) {
  SimConfig config = SmallSimConfig();
  config.survey_options.max_images = 6;
  const fs::path dir = fs::temp_directory_path() /
                       ("uw_generate_times_" + std::to_string(getpid()));
  fs::remove_all(dir);
  const GenerateSummary summary = Generate(config, dir, {}, false);
  ASSERT_GT(summary.num_laser_images, 0u);
  const nlohmann::json truth =
      nlohmann::json::parse(FileBytes(dir / "truth" / "laser_images.json"));
  std::istringstream times(FileBytes(dir / "laser_image_times.csv"));
  std::string line;
  std::getline(times, line);
  EXPECT_EQ(line[0], '#');
  std::getline(times, line);
  EXPECT_EQ(line, "image_name,time");
  size_t k = 0;
  while (std::getline(times, line)) {
    ASSERT_LT(k, truth["images"].size()) << line;
    const nlohmann::json& image = truth["images"][k++];
    const size_t comma = line.find(',');
    EXPECT_EQ(line.substr(0, comma), image["name"].get<std::string>());
    EXPECT_EQ(std::stod(line.substr(comma + 1)), image["time"].get<double>());
  }
  EXPECT_EQ(k, summary.num_laser_images);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace uw::sim
