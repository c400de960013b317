// Our reading and writing of COLMAP's database against stock colmap 3.8, on
// the database colmap wrote for the rendered test scene (fixture
// colmap_scene). database_test.cc beside the library covers every schema.
#include <gtest/gtest.h>

#include <fstream>
#include <map>

#include "colmap_plugins/scene/database.h"
#include "colmap_plugins/scene/model_io.h"
#include "common/util/file.h"
#include "common/util/subprocess.h"
#include "tests/support/process.h"

namespace uw {
namespace {

namespace fs = std::filesystem;
using testing::FreshTestDir;
using testing::Quoted;

const fs::path kSceneDir = UW_SCENE_DIR;
const fs::path kUwcolmap = fs::path(UW_BIN_DIR) / "uwcolmap";

std::string Shell(const fs::path& database, const std::string& sql) {
  const auto result =
      RunProcess("sqlite3 " + Quoted(database) + " '" + sql + "'", true);
  EXPECT_EQ(result.exit_code, 0) << result.output;
  return result.output.substr(0, result.output.find('\n'));
}

std::map<std::string, Eigen::Vector3d> TrueCentres() {
  std::map<std::string, Eigen::Vector3d> centres;
  std::ifstream file(kSceneDir / "scene" / "truth" / "ref_images.txt");
  std::string name;
  Eigen::Vector3d centre;
  while (file >> name >> centre.x() >> centre.y() >> centre.z()) {
    centres[name] = centre;
  }
  return centres;
}

// colmap's mapper turns an image's keypoints into its 2D points one for one,
// so the database and the model must agree to the bit.
TEST(ColmapDatabase, KeypointsAreTheModelsPoints2D) {
  const Database database =
      Database::Open(kSceneDir / "database.db", Database::Mode::kReadOnly);
  EXPECT_EQ(database.Schema(), DatabaseSchema::kColmap38);
  const Reconstruction model = ReadModel(kSceneDir / "sparse" / "0");
  ASSERT_EQ(database.ReadAllImages().size(), model.Images().size());
  size_t num_keypoints = 0;
  for (const Image& image : model.Images()) {
    const auto db_image = database.ReadImageWithName(image.name);
    ASSERT_TRUE(db_image.has_value()) << image.name;
    EXPECT_EQ(db_image->image_id, image.image_id);
    const FeatureKeypointsBlob keypoints =
        database.ReadKeypoints(image.image_id);
    ASSERT_EQ(static_cast<size_t>(keypoints.rows()), image.points2D.size());
    for (Eigen::Index i = 0; i < keypoints.rows(); ++i) {
      ASSERT_EQ(static_cast<double>(keypoints(i, 0)), image.points2D[i].xy.x());
      ASSERT_EQ(static_cast<double>(keypoints(i, 1)), image.points2D[i].xy.y());
    }
    EXPECT_EQ(database.ReadDescriptors(image.image_id).data.rows(),
              keypoints.rows());
    num_keypoints += keypoints.rows();
  }
  // Exhaustive matching stores a geometry for all 66 pairs; those that
  // failed verification (config 0, UNDEFINED) have no inliers, the others
  // index existing keypoints of both images. The sqlite3 shell counts the
  // verified pairs independently of our reader.
  const auto geometries = database.ReadTwoViewGeometries();
  EXPECT_EQ(geometries.size(), 66u);
  size_t num_verified = 0;
  for (const auto& [pair_id, geometry] : geometries) {
    const auto [image_id1, image_id2] = PairIdToImagePair(pair_id);
    EXPECT_EQ(geometry.config == 0, geometry.inlier_matches.rows() == 0);
    if (geometry.inlier_matches.rows() == 0) continue;
    ++num_verified;
    EXPECT_LT(geometry.inlier_matches.col(0).maxCoeff(),
              database.ReadKeypoints(image_id1).rows());
    EXPECT_LT(geometry.inlier_matches.col(1).maxCoeff(),
              database.ReadKeypoints(image_id2).rows());
  }
  EXPECT_EQ(std::to_string(num_verified),
            Shell(kSceneDir / "database.db",
                  "SELECT count(*) FROM two_view_geometries WHERE rows > 0"));
  EXPECT_GE(num_verified, 40u);
  std::printf(
      "[ figures ] %zu keypoints in %zu images, %zu of %zu pairs "
      "verified\n",
      num_keypoints, model.Images().size(), num_verified, geometries.size());
}

// Priors we write into colmap's 3.8 database are what colmap's own
// model_aligner aligns to: with the true camera centres as priors, the
// aligned model lands on the truth.
TEST(ColmapDatabase, PosePriorsWeWriteAreUsedByColmapModelAligner) {
  const fs::path dir = FreshTestDir("uw_colmap_database_test");
  fs::copy_file(kSceneDir / "database.db", dir / "database.db");
  const auto centres = TrueCentres();
  ASSERT_EQ(centres.size(), 12u);
  {
    Database database =
        Database::Open(dir / "database.db", Database::Mode::kReadWrite);
    std::vector<PosePrior> priors;
    for (const DatabaseImage& image : database.ReadAllImages()) {
      PosePrior prior;
      prior.image_id = image.image_id;
      prior.position = centres.at(image.name);
      priors.push_back(prior);
    }
    EXPECT_EQ(database.WritePosePriors(priors).num_written, 12u);
  }
  const Reconstruction before = ReadModel(kSceneDir / "sparse" / "0");
  fs::create_directories(dir / "aligned");
  const auto aligned =
      RunProcess("colmap model_aligner --input_path " +
                     Quoted(kSceneDir / "sparse" / "0") + " --output_path " +
                     Quoted(dir / "aligned") + " --database_path " +
                     Quoted(dir / "database.db") +
                     " --ref_is_gps 0 --robust_alignment_max_error 0.05",
                 true);
  ASSERT_EQ(aligned.exit_code, 0) << aligned.output;
  const Reconstruction after = ReadModel(dir / "aligned");
  double error_before = 0.0;
  double error_after = 0.0;
  for (const Image& image : after.Images()) {
    const Eigen::Vector3d truth = centres.at(image.name);
    error_after += (image.ProjectionCenter() - truth).norm();
    error_before +=
        (before.FindImage(image.image_id)->ProjectionCenter() - truth).norm();
  }
  error_before /= after.Images().size();
  error_after /= after.Images().size();
  std::printf(
      "[ figures ] mean camera centre error vs truth: %.4f m before, "
      "%.5f m after colmap model_aligner with our priors\n",
      error_before, error_after);
  EXPECT_GT(error_before, 0.5);
  EXPECT_LT(error_after, 0.01);
}

TEST(ColmapDatabase, DatabaseAnalyzerCountsWhatTheSqliteShellCounts) {
  const fs::path db = kSceneDir / "database.db";
  const auto result = RunProcess(
      kUwcolmap.string() + " database_analyzer --database_path " + Quoted(db),
      true);
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const std::string expected =
      "Schema: COLMAP 3.8/3.9\n"
      "Cameras: " +
      Shell(db, "SELECT count(*) FROM cameras") + "\n" +
      "Images: " + Shell(db, "SELECT count(*) FROM images") + "\n" +
      "Images with keypoints: " +
      Shell(db, "SELECT count(*) FROM keypoints WHERE rows > 0") + "\n" +
      "Keypoints: " + Shell(db, "SELECT sum(rows) FROM keypoints") + "\n" +
      "Matched pairs: " +
      Shell(db, "SELECT count(*) FROM matches WHERE rows > 0") + "\n" +
      "Verified pairs: " +
      Shell(db, "SELECT count(*) FROM two_view_geometries WHERE rows > 0") +
      "\n" + "Inlier matches: " +
      Shell(db, "SELECT sum(rows) FROM two_view_geometries") + "\n" +
      "Pose priors: 0 (0 with position covariance)\n";
  EXPECT_EQ(result.output, expected);
}

// A database that lacks a table is refused with the file and table named, a
// non-zero exit, and neither the file nor its folder changed.
TEST(ColmapDatabase, DatabaseAnalyzerRejectsMissingTable) {
  const fs::path dir = FreshTestDir("uw_colmap_database_test");
  const fs::path db = dir / "database.db";
  fs::copy_file(kSceneDir / "database.db", db);
  Shell(db, "DROP TABLE two_view_geometries");
  const std::string before = ReadFileToString(db);
  const auto result = RunProcess(
      kUwcolmap.string() + " database_analyzer --database_path " + Quoted(db),
      true);
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.output.find(db.string() + ": "), std::string::npos)
      << result.output;
  EXPECT_NE(result.output.find("'two_view_geometries' is missing"),
            std::string::npos)
      << result.output;
  EXPECT_TRUE(ReadFileToString(db) == before);
  // colmap keeps its database in WAL mode, where SQLite itself adds the
  // -shm/-wal companions for any reader; nothing else may appear.
  for (const auto& entry : fs::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    EXPECT_TRUE(name == "database.db" || name == "database.db-shm" ||
                name == "database.db-wal")
        << name;
  }
}

}  // namespace
}  // namespace uw
