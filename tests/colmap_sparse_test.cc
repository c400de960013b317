// scripts/colmap_sparse.sh with a user's own colmap flags (issue 17, "own
// images in one step"): EXTRACTOR_FLAGS, MATCHER_FLAGS and MAPPER_FLAGS
// reach their steps, and replace the script's defaults of the same name,
// which colmap would refuse twice.
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "colmap_plugins/scene/database.h"
#include "colmap_plugins/scene/model_io.h"
#include "common/util/file.h"
#include "common/util/subprocess.h"
#include "tests/support/process.h"

namespace uw {
namespace {

namespace fs = std::filesystem;
using testing::Quoted;

const fs::path kSurveyDir = UW_SURVEY_DIR;
const fs::path kScript =
    fs::path(UW_SOURCE_DIR) / "scripts" / "colmap_sparse.sh";

TEST(ColmapSparse, UserFlagsReachTheirStepsAndReplaceTheDefaults) {
  const fs::path dir = testing::FreshTestDir("uw_colmap_sparse_test");
  const fs::path images = dir / "images";
  fs::create_directories(images);
  // Six images along the survey's first line: enough for a model.
  for (int i = 0; i < 6; ++i) {
    const std::string name = "0000" + std::to_string(i) + ".png";
    fs::copy_file(kSurveyDir / "sim" / "images" / name, images / name);
  }
  const fs::path out = dir / "out";
  // The script's default is 2000 features (about 2500 keypoints on these
  // images, some features taking two orientations); colmap refuses a flag
  // given twice. 300 features give at most 600 keypoints. The matcher's
  // flags come as NAME=VALUE and tab-separated, and one of them is a
  // default of the script's (use_gpu), which colmap would refuse twice.
  const auto result = RunProcess(
      "EXTRACTOR_FLAGS='--SiftExtraction.max_num_features 300' "
      "MATCHER_FLAGS='--SiftMatching.use_gpu=0\t--SiftMatching.max_ratio "
      "0.75' "
      "MAPPER_FLAGS='--Mapper.ba_global_max_num_iterations 20' bash " +
          Quoted(kScript) + " " + Quoted(images) + " " + Quoted(out),
      true);
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const Database database =
      Database::Open(out / "database.db", Database::Mode::kReadOnly);
  size_t num_images = 0;
  for (const DatabaseImage& image : database.ReadAllImages()) {
    const long num_keypoints = database.ReadKeypoints(image.image_id).rows();
    EXPECT_GT(num_keypoints, 100) << image.name;
    EXPECT_LE(num_keypoints, 600) << image.name;
    ++num_images;
  }
  EXPECT_EQ(num_images, 6u);
  EXPECT_EQ(database.ReadAllCameras().size(), 1u);
  EXPECT_GE(ReadModel(out / "sparse" / "0").Images().size(), 3u);

  // A camera per image (SINGLE_CAMERA=0); a flag colmap does not know
  // stops the step that got it, and says so.
  const auto bad = RunProcess(
      "SINGLE_CAMERA=0 MAPPER_FLAGS='--Mapper.no_such_flag 1' bash " +
          Quoted(kScript) + " " + Quoted(images) + " " + Quoted(dir / "bad"),
      true);
  EXPECT_EQ(bad.exit_code, 1) << bad.output;
  EXPECT_NE(bad.output.find("step 'mapper' failed"), std::string::npos)
      << bad.output;
  EXPECT_EQ(
      Database::Open(dir / "bad" / "database.db", Database::Mode::kReadOnly)
          .ReadAllCameras()
          .size(),
      6u);
}

}  // namespace
}  // namespace uw
