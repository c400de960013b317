// uwcolmap dense_mesher on the default uwsim survey reconstructed by stock
// colmap (fixture uwsim_survey), measured against uwsim's true surface by
// uwcolmap model_comparer --dense_mesh_path (issue 7, acceptance 1).
#include <gtest/gtest.h>

#include <cstdio>

#include <nlohmann/json.hpp>

#include "common/util/file.h"
#include "common/util/subprocess.h"
#include "tests/support/process.h"

namespace uw {
namespace {

namespace fs = std::filesystem;
using testing::FreshTestDir;
using testing::Quoted;

const fs::path kSurveyDir = UW_SURVEY_DIR;
const fs::path kSimDir = kSurveyDir / "sim";
const fs::path kSparseDir = kSurveyDir / "sparse" / "0";
const fs::path kUwcolmap = fs::path(UW_BIN_DIR) / "uwcolmap";

// Made by the fixture uwsim_survey_dense (tests/CMakeLists.txt) at half the
// survey's 1024 px.
const fs::path kMesh = kSurveyDir / "dense" / "mesh.ply";
const char kMesherFlags[] = " --DenseMesher.max_image_size 512";

TEST(DenseMesher, DefaultSurveyMeshIsAccurateAndComplete) {
  const fs::path dir = FreshTestDir("uw_dense_mesher_test");
  const fs::path& mesh = kMesh;
  const std::string log =
      ReadFileToString(kSurveyDir / "dense" / "dense_mesher.log");
  // Progress per image, and every image of the survey got a depth map.
  EXPECT_NE(log.find("depth maps 33/33"), std::string::npos) << log;
  EXPECT_NE(log.find("33 of 33 images with a depth map"), std::string::npos)
      << log;
  // The header says the mesh is in the model's frame and units: only the
  // model knows whether they are metres.
  const std::string header = ReadFileToString(mesh).substr(0, 400);
  EXPECT_NE(header.find("comment uwcolmap dense_mesher of the model "),
            std::string::npos)
      << header;
  EXPECT_NE(header.find("that model's frame and units (metres only if it is "
                        "metric)"),
            std::string::npos);

  const fs::path json = dir / "compare.json";
  const auto comparer =
      RunProcess(kUwcolmap.string() + " model_comparer --input_path " +
                     Quoted(kSparseDir) + " --truth_dir " + Quoted(kSimDir) +
                     " --dense_mesh_path " + Quoted(mesh) + " --output_path " +
                     Quoted(json),
                 true);
  ASSERT_EQ(comparer.exit_code, 0) << comparer.output;
  const nlohmann::json dense =
      nlohmann::json::parse(ReadFileToString(json)).at("dense_surface");
  const double distance = dense.at("camera_scene_distance").get<double>();
  const double median = dense.at("median_distance").get<double>();
  const double coverage = dense.at("coverage").get<double>();
  std::printf(
      "[ figures ] camera-scene distance %.4f m; median distance to the true "
      "surface %.5f m = %.4f %% of it (90 %% %.5f m, RMS %.5f m, signed mean "
      "%+.5f m); coverage %.2f %% of %.2f m^2\n",
      distance, median, 100.0 * median / distance,
      dense.at("p90_distance").get<double>(),
      dense.at("rms_distance").get<double>(),
      dense.at("mean_signed_distance").get<double>(), 100.0 * coverage,
      dense.at("observed_area").get<double>());
  // The survey flies 2.5 m over a floor with rocks.
  EXPECT_GT(distance, 2.0);
  EXPECT_LT(distance, 3.0);
  // Issue 7: median < 0.5 % of the camera-scene distance, >= 90 % covered.
  EXPECT_LT(median, 0.005 * distance);
  EXPECT_GE(coverage, 0.90);
}

TEST(DenseMesher, MissingImageIsAnErrorNamingItAndWritesNothing) {
  const fs::path dir = FreshTestDir("uw_dense_mesher_missing_test");
  const fs::path images = dir / "images";
  fs::create_directories(images);
  const fs::path mesh = dir / "mesh.ply";
  const auto result =
      RunProcess(kUwcolmap.string() + " dense_mesher --input_path " +
                     Quoted(kSparseDir) + " --image_path " + Quoted(images) +
                     " --output_path " + Quoted(mesh) + kMesherFlags,
                 true);
  EXPECT_EQ(result.exit_code, 1) << result.output;
  EXPECT_NE(result.output.find("missing or unreadable image"),
            std::string::npos)
      << result.output;
  EXPECT_NE(result.output.find(".png"), std::string::npos) << result.output;
  EXPECT_FALSE(fs::exists(mesh));
}

}  // namespace
}  // namespace uw
