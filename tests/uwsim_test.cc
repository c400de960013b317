// uwsim end to end: determinism of `uwsim generate`, and stock colmap on its
// default survey (fixture uwsim_survey, scripts/reconstruct_uwsim_survey.sh).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <fstream>
#include <map>

#include "colmap_plugins/scene/model_io.h"
#include "common/util/file.h"
#include "common/util/subprocess.h"
#include "tests/support/process.h"

namespace uw {
namespace {

namespace fs = std::filesystem;
using testing::FreshTestDir;
using testing::Quoted;

const fs::path kSurveyDir = UW_SURVEY_DIR;
const fs::path kUwsim = fs::path(UW_BIN_DIR) / "uwsim";

// Every regular file below `dir`, by relative path, with its bytes.
std::map<std::string, std::string> Files(const fs::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    if (entry.is_regular_file()) {
      files[entry.path().lexically_relative(dir).string()] =
          ReadFileToString(entry.path());
    }
  }
  return files;
}

void Generate(const fs::path& out, const std::string& flags) {
  const auto result = RunProcess(
      kUwsim.string() + " generate --out " + Quoted(out) + " " + flags, true);
  ASSERT_EQ(result.exit_code, 0) << result.output;
}

TEST(Uwsim, SameSeedGivesTheSameBytesWhateverTheThreadCount) {
  const fs::path dir = FreshTestDir("uw_uwsim_test");
  Generate(dir / "one", "--seed 5 --max_images 3 --num_threads 1");
  Generate(dir / "two", "--seed 5 --max_images 3 --num_threads 2");
  Generate(dir / "other", "--seed 6 --max_images 3 --num_threads 2");
  const auto one = Files(dir / "one");
  const auto two = Files(dir / "two");
  const auto other = Files(dir / "other");
  // 3 images, a laser image and its auxiliary, nav.csv, image_times.csv,
  // laser_image_times.csv, lasers.json and truth/: cameras, images,
  // points3D, ref_images, nav.csv, mesh.ply, sim.json, lasers.json,
  // laser_images.json.
  ASSERT_EQ(one.size(), 18u);
  EXPECT_TRUE(one.count("laser_image_times.csv"));
  EXPECT_TRUE(one.count("laser_images/L00002_aux.png"));
  for (const auto& [name, bytes] : one) {
    ASSERT_TRUE(two.count(name)) << name;
    EXPECT_TRUE(two.at(name) == bytes) << name << " differs";
  }
  EXPECT_FALSE(other.at("images/00000.png") == one.at("images/00000.png"));
  EXPECT_FALSE(other.at("nav.csv") == one.at("nav.csv"));
  EXPECT_FALSE(other.at("laser_images/L00002.png") ==
               one.at("laser_images/L00002.png"));
  EXPECT_FALSE(other.at("lasers.json") == one.at("lasers.json"));
}

TEST(Uwsim, RefusesToWriteIntoAFolderInUse) {
  const fs::path dir = FreshTestDir("uw_uwsim_test");
  std::ofstream(dir / "notes.txt") << "mine";
  const auto result = RunProcess(
      kUwsim.string() + " generate --max_images 1 --out " + Quoted(dir), true);
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.output.find("not empty"), std::string::npos)
      << result.output;
  EXPECT_EQ(ReadFileToString(dir / "notes.txt"), "mine");
}

// The default seafloor/lawnmower survey through stock colmap (with the true
// calibration, as a user with a calibrated camera runs it): nearly every
// image registers and, after a similarity to the truth, the cameras are
// where uwsim put them.
TEST(Uwsim, StockColmapReconstructsTheDefaultSurvey) {
  const Reconstruction truth = ReadModel(kSurveyDir / "sim" / "truth");
  const Reconstruction model = ReadModel(kSurveyDir / "sparse" / "0");
  const double registered =
      static_cast<double>(model.Images().size()) / truth.Images().size();
  EXPECT_GE(registered, 0.95);

  std::map<std::string, Eigen::Vector3d> true_centres;
  Eigen::AlignedBox3d extent;
  for (const Image& image : truth.Images()) {
    true_centres[image.name] = image.ProjectionCenter();
    extent.extend(image.ProjectionCenter());
  }
  Eigen::Matrix3Xd source(3, model.Images().size());
  Eigen::Matrix3Xd target(3, model.Images().size());
  for (size_t i = 0; i < model.Images().size(); ++i) {
    source.col(i) = model.Images()[i].ProjectionCenter();
    target.col(i) = true_centres.at(model.Images()[i].name);
  }
  const Eigen::Matrix4d world_from_model = Eigen::umeyama(source, target);
  const Eigen::Matrix3Xd aligned =
      (world_from_model.topLeftCorner<3, 3>() * source).colwise() +
      world_from_model.topRightCorner<3, 1>();
  const double rmse =
      std::sqrt((aligned - target).colwise().squaredNorm().mean());
  const double survey_extent = extent.sizes().maxCoeff();
  std::printf(
      "[ figures ] default survey: %zu/%zu images registered "
      "(%.1f %%), camera RMSE after similarity %.4f m = %.3f %% of "
      "the %.2f m survey extent\n",
      model.Images().size(), truth.Images().size(), 100 * registered, rmse,
      100 * rmse / survey_extent, survey_extent);
  EXPECT_LT(rmse, 0.01 * survey_extent);
}

}  // namespace
}  // namespace uw
