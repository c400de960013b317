// Tests of the COLMAP database reader/writer against stock COLMAP 3.8 (the
// `colmap` program writes and consumes the 3.8 database) and against
// databases created from COLMAP's own CREATE TABLE statements of later tags.
// Expected values come from the sqlite3 command-line shell, never from the
// code under test.
#include "colmap_plugins/scene/database.h"
#include "colmap_plugins/scene/database_stats.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/util/error.h"

namespace uw {
namespace {

namespace fs = std::filesystem;

// ---------------------------------------------------------------------------
// CREATE TABLE statements of COLMAP, as its Create*Table() functions build
// them (string pieces concatenated, %d = kMaxNumImages = 2147483647).

// COLMAP 3.8 src/base/database.cc CreateCameraTable; same text at every tag up
// to HEAD 5d968cf.
constexpr char kCamerasSql[] =
    "CREATE TABLE IF NOT EXISTS cameras"
    "   (camera_id            INTEGER  PRIMARY KEY AUTOINCREMENT  NOT NULL,"
    "    model                INTEGER                             NOT NULL,"
    "    width                INTEGER                             NOT NULL,"
    "    height               INTEGER                             NOT NULL,"
    "    params               BLOB,"
    "    prior_focal_length   INTEGER                             NOT NULL);";

// COLMAP 3.8 src/base/database.cc CreateImageTable.
constexpr char kImages38Sql[] =
    "CREATE TABLE IF NOT EXISTS images"
    "   (image_id   INTEGER  PRIMARY KEY AUTOINCREMENT  NOT NULL,"
    "    name       TEXT                                NOT NULL UNIQUE,"
    "    camera_id  INTEGER                             NOT NULL,"
    "    prior_qw   REAL,"
    "    prior_qx   REAL,"
    "    prior_qy   REAL,"
    "    prior_qz   REAL,"
    "    prior_tx   REAL,"
    "    prior_ty   REAL,"
    "    prior_tz   REAL,"
    "CONSTRAINT image_id_check CHECK(image_id >= 0 and image_id < 2147483647),"
    "FOREIGN KEY(camera_id) REFERENCES cameras(camera_id));"
    "CREATE UNIQUE INDEX IF NOT EXISTS index_name ON images(name);";

// COLMAP 3.10 src/colmap/scene/database.cc CreateImageTable; same at 3.11.0.
constexpr char kImages310Sql[] =
    "CREATE TABLE IF NOT EXISTS images"
    "   (image_id   INTEGER  PRIMARY KEY AUTOINCREMENT  NOT NULL,"
    "    name       TEXT                                NOT NULL UNIQUE,"
    "    camera_id  INTEGER                             NOT NULL,"
    "CONSTRAINT image_id_check CHECK(image_id >= 0 and image_id < 2147483647),"
    "FOREIGN KEY(camera_id) REFERENCES cameras(camera_id));"
    "CREATE UNIQUE INDEX IF NOT EXISTS index_name ON images(name);";

// COLMAP 3.12.0 src/colmap/scene/database.cc CreateImageTable; same at 3.13.0,
// 4.0.0, 4.1.1 and HEAD (src/colmap/scene/database_sqlite.cc).
constexpr char kImages312Sql[] =
    "CREATE TABLE IF NOT EXISTS images"
    "   (image_id   INTEGER  PRIMARY KEY AUTOINCREMENT  NOT NULL,"
    "    name       TEXT                                NOT NULL UNIQUE,"
    "    camera_id  INTEGER                             NOT NULL,"
    "    CONSTRAINT image_id_check CHECK(image_id >= 0 and image_id < "
    "2147483647),"
    "    FOREIGN KEY(camera_id) REFERENCES cameras(camera_id));"
    "CREATE UNIQUE INDEX IF NOT EXISTS index_name ON images(name);";

// COLMAP 3.10 src/colmap/scene/database.cc CreatePosePriorTable.
constexpr char kPosePriors310Sql[] =
    "CREATE TABLE IF NOT EXISTS pose_priors"
    "   (image_id          INTEGER  PRIMARY KEY  NOT NULL,"
    "    position          BLOB,"
    "    coordinate_system INTEGER               NOT NULL,"
    "FOREIGN KEY(image_id) REFERENCES images(image_id) ON DELETE CASCADE);";

// COLMAP 3.11.0 src/colmap/scene/database.cc CreatePosePriorTable.
constexpr char kPosePriors311Sql[] =
    "CREATE TABLE IF NOT EXISTS pose_priors"
    "   (image_id                   INTEGER  PRIMARY KEY  NOT NULL,"
    "    position                   BLOB,"
    "    coordinate_system          INTEGER               NOT NULL,"
    "    position_covariance        BLOB,"
    "FOREIGN KEY(image_id) REFERENCES images(image_id) ON DELETE CASCADE);";

// COLMAP 3.12.0 src/colmap/scene/database.cc CreatePosePriorTable; same at
// 3.13.0 (src/colmap/scene/database_sqlite.cc).
constexpr char kPosePriors312Sql[] =
    "CREATE TABLE IF NOT EXISTS pose_priors"
    "   (image_id                   INTEGER  PRIMARY KEY  NOT NULL,"
    "    position                   BLOB,"
    "    coordinate_system          INTEGER               NOT NULL,"
    "    position_covariance        BLOB,"
    "    FOREIGN KEY(image_id) REFERENCES images(image_id) ON DELETE CASCADE);";

// COLMAP 4.0.0 src/colmap/scene/database_sqlite.cc CreatePosePriorTable; same
// at 4.1.1 and HEAD.
constexpr char kPosePriors4Sql[] =
    "CREATE TABLE IF NOT EXISTS pose_priors"
    "   (pose_prior_id              INTEGER  PRIMARY KEY  NOT NULL,"
    "    corr_data_id               INTEGER               NOT NULL,"
    "    corr_sensor_id             INTEGER               NOT NULL,"
    "    corr_sensor_type           INTEGER               NOT NULL,"
    "    position                   BLOB,"
    "    position_covariance        BLOB,"
    "    gravity                    BLOB,"
    "    coordinate_system          INTEGER               NOT NULL);"
    "CREATE UNIQUE INDEX IF NOT EXISTS pose_prior_data_assignment ON "
    "   pose_priors(corr_data_id, corr_sensor_id, corr_sensor_type);";

// COLMAP 3.8 src/base/database.cc CreateKeypointsTable; same at 3.10
// and 3.11.0.
constexpr char kKeypoints38Sql[] =
    "CREATE TABLE IF NOT EXISTS keypoints"
    "   (image_id  INTEGER  PRIMARY KEY  NOT NULL,"
    "    rows      INTEGER               NOT NULL,"
    "    cols      INTEGER               NOT NULL,"
    "    data      BLOB,"
    "FOREIGN KEY(image_id) REFERENCES images(image_id) ON DELETE CASCADE);";

// COLMAP 3.12.0 src/colmap/scene/database.cc CreateKeypointsTable; same up to
// HEAD.
constexpr char kKeypoints312Sql[] =
    "CREATE TABLE IF NOT EXISTS keypoints"
    "   (image_id  INTEGER  PRIMARY KEY  NOT NULL,"
    "    rows      INTEGER               NOT NULL,"
    "    cols      INTEGER               NOT NULL,"
    "    data      BLOB,"
    "    FOREIGN KEY(image_id) REFERENCES images(image_id) ON DELETE CASCADE);";

// COLMAP 3.8 src/base/database.cc CreateDescriptorsTable; same at 3.10 and
// 3.11.0.
constexpr char kDescriptors38Sql[] =
    "CREATE TABLE IF NOT EXISTS descriptors"
    "   (image_id  INTEGER  PRIMARY KEY  NOT NULL,"
    "    rows      INTEGER               NOT NULL,"
    "    cols      INTEGER               NOT NULL,"
    "    data      BLOB,"
    "FOREIGN KEY(image_id) REFERENCES images(image_id) ON DELETE CASCADE);";

// COLMAP 3.12.0 src/colmap/scene/database.cc CreateDescriptorsTable; same at
// 3.13.0.
constexpr char kDescriptors312Sql[] =
    "CREATE TABLE IF NOT EXISTS descriptors"
    "   (image_id  INTEGER  PRIMARY KEY  NOT NULL,"
    "    rows      INTEGER               NOT NULL,"
    "    cols      INTEGER               NOT NULL,"
    "    data      BLOB,"
    "    FOREIGN KEY(image_id) REFERENCES images(image_id) ON DELETE CASCADE);";

// COLMAP 4.0.0 src/colmap/scene/database_sqlite.cc CreateDescriptorsTable; same
// at 4.1.1 and HEAD.
constexpr char kDescriptors4Sql[] =
    "CREATE TABLE IF NOT EXISTS descriptors"
    "   (image_id      INTEGER  PRIMARY KEY  NOT NULL,"
    "    type          INTEGER               NOT NULL,"
    "    rows          INTEGER               NOT NULL,"
    "    cols          INTEGER               NOT NULL,"
    "    data          BLOB,"
    "    FOREIGN KEY(image_id) REFERENCES images(image_id) ON DELETE CASCADE);";

// COLMAP 3.8 src/base/database.cc CreateMatchesTable; same at every tag up to
// HEAD.
constexpr char kMatchesSql[] =
    "CREATE TABLE IF NOT EXISTS matches"
    "   (pair_id  INTEGER  PRIMARY KEY  NOT NULL,"
    "    rows     INTEGER               NOT NULL,"
    "    cols     INTEGER               NOT NULL,"
    "    data     BLOB);";

// COLMAP 3.13.0 src/colmap/scene/database_sqlite.cc
// CreateTwoViewGeometriesTable; same text from 3.8 to 4.1.1.
constexpr char kTwoViewGeometriesSql[] =
    "CREATE TABLE IF NOT EXISTS two_view_geometries"
    "   (pair_id  INTEGER  PRIMARY KEY  NOT NULL,"
    "    rows     INTEGER               NOT NULL,"
    "    cols     INTEGER               NOT NULL,"
    "    data     BLOB,"
    "    config   INTEGER               NOT NULL,"
    "    F        BLOB,"
    "    E        BLOB,"
    "    H        BLOB,"
    "    qvec     BLOB,"
    "    tvec     BLOB);";

// COLMAP HEAD 5d968cf src/colmap/scene/database_sqlite.cc
// CreateTwoViewGeometriesTable (camera1/camera2 are not in any release yet).
constexpr char kTwoViewGeometriesHeadSql[] =
    "CREATE TABLE IF NOT EXISTS two_view_geometries"
    "   (pair_id  INTEGER  PRIMARY KEY  NOT NULL,"
    "    rows     INTEGER               NOT NULL,"
    "    cols     INTEGER               NOT NULL,"
    "    data     BLOB,"
    "    config   INTEGER               NOT NULL,"
    "    F        BLOB,"
    "    E        BLOB,"
    "    H        BLOB,"
    "    qvec     BLOB,"
    "    tvec     BLOB,"
    "    camera1  BLOB,"
    "    camera2  BLOB);";

// COLMAP 3.12.0 src/colmap/scene/database.cc CreateRigTable; same up to HEAD.
constexpr char kRigsSql[] =
    "CREATE TABLE IF NOT EXISTS rigs"
    "   (rig_id               INTEGER  PRIMARY KEY AUTOINCREMENT  NOT NULL,"
    "    ref_sensor_id        INTEGER                             NOT NULL,"
    "    ref_sensor_type      INTEGER                             NOT NULL);"
    "CREATE UNIQUE INDEX IF NOT EXISTS rig_ref_sensor_assignment ON "
    "   rigs(ref_sensor_id, ref_sensor_type);";

// COLMAP 3.12.0 src/colmap/scene/database.cc CreateRigSensorsTable; same up to
// HEAD.
constexpr char kRigSensorsSql[] =
    "CREATE TABLE IF NOT EXISTS rig_sensors"
    "   (rig_id               INTEGER                             NOT NULL,"
    "    sensor_id            INTEGER                             NOT NULL,"
    "    sensor_type          INTEGER                             NOT NULL,"
    "    sensor_from_rig      BLOB,"
    "FOREIGN KEY(rig_id) REFERENCES rigs(rig_id) ON DELETE CASCADE);"
    "CREATE UNIQUE INDEX IF NOT EXISTS rig_sensor_assignment ON "
    "   rig_sensors(sensor_id, sensor_type);";

// COLMAP 3.12.0 src/colmap/scene/database.cc CreateFrameTable; same up to HEAD.
constexpr char kFramesSql[] =
    "CREATE TABLE IF NOT EXISTS frames"
    "   (frame_id             INTEGER  PRIMARY KEY AUTOINCREMENT  NOT NULL,"
    "    rig_id               INTEGER                             NOT NULL,"
    "    FOREIGN KEY(rig_id) REFERENCES rigs(rig_id) ON DELETE CASCADE);";

// COLMAP 3.12.0 src/colmap/scene/database.cc CreateFrameDataTable; same up to
// HEAD.
constexpr char kFrameDataSql[] =
    "CREATE TABLE IF NOT EXISTS frame_data"
    "   (frame_id             INTEGER                             NOT NULL,"
    "    data_id              INTEGER                             NOT NULL,"
    "    sensor_id            INTEGER                             NOT NULL,"
    "    sensor_type          INTEGER                             NOT NULL,"
    "    FOREIGN KEY(frame_id) REFERENCES frames(frame_id) ON DELETE CASCADE);"
    "CREATE UNIQUE INDEX IF NOT EXISTS frame_sensor_assignment ON "
    "   frame_data(data_id, sensor_type);";

// One database layout per tag, tables in the order COLMAP creates them.
struct Fixture {
  std::string tag;
  std::vector<const char*> statements;
  DatabaseSchema schema;
  bool has_rigs_and_frames;
};

// The 3.8 layout without stock colmap, for tests that need no features.
Fixture Colmap38Fixture() {
  return {"3.8",
          {kCamerasSql, kImages38Sql, kKeypoints38Sql, kDescriptors38Sql,
           kMatchesSql, kTwoViewGeometriesSql},
          DatabaseSchema::kColmap38,
          false};
}

std::vector<Fixture> LaterFixtures() {
  return {
      {"3.10",
       {kCamerasSql, kImages310Sql, kPosePriors310Sql, kKeypoints38Sql,
        kDescriptors38Sql, kMatchesSql, kTwoViewGeometriesSql},
       DatabaseSchema::kColmap310,
       false},
      {"3.11.0",
       {kCamerasSql, kImages310Sql, kPosePriors311Sql, kKeypoints38Sql,
        kDescriptors38Sql, kMatchesSql, kTwoViewGeometriesSql},
       DatabaseSchema::kColmap311,
       false},
      {"3.12.0",
       {kRigsSql, kRigSensorsSql, kCamerasSql, kFramesSql, kFrameDataSql,
        kImages312Sql, kPosePriors312Sql, kKeypoints312Sql, kDescriptors312Sql,
        kMatchesSql, kTwoViewGeometriesSql},
       DatabaseSchema::kColmap311,
       true},
      {"4.0.0",
       {kRigsSql, kRigSensorsSql, kCamerasSql, kFramesSql, kFrameDataSql,
        kImages312Sql, kPosePriors4Sql, kKeypoints312Sql, kDescriptors4Sql,
        kMatchesSql, kTwoViewGeometriesSql},
       DatabaseSchema::kColmap4,
       true},
      {"HEAD",
       {kRigsSql, kRigSensorsSql, kCamerasSql, kFramesSql, kFrameDataSql,
        kImages312Sql, kPosePriors4Sql, kKeypoints312Sql, kDescriptors4Sql,
        kMatchesSql, kTwoViewGeometriesHeadSql},
       DatabaseSchema::kColmap4,
       true},
  };
}

std::vector<Fixture> AllFixtures() {
  std::vector<Fixture> fixtures = {Colmap38Fixture()};
  for (Fixture& fixture : LaterFixtures()) fixtures.push_back(fixture);
  return fixtures;
}

// ---------------------------------------------------------------------------
// Helpers.

// Everything a test writes lives below one directory per process.
fs::path TestRoot() {
  static const fs::path root =
      fs::temp_directory_path() /
      ("uw_database_test_" + std::to_string(::getpid()));
  return root;
}

class TestRootCleanup : public ::testing::Environment {
 public:
  void TearDown() override { fs::remove_all(TestRoot()); }
};
[[maybe_unused]] ::testing::Environment* const kTestRootCleanup =
    ::testing::AddGlobalTestEnvironment(new TestRootCleanup);

// A fresh directory named after the running test.
fs::path TestDir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const fs::path dir =
      TestRoot() / (std::string(info->test_suite_name()) + "." + info->name());
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string ReadFile(const fs::path& path) {
  std::ifstream stream(path, std::ios::binary);
  std::ostringstream content;
  content << stream.rdbuf();
  return content.str();
}

void WriteFile(const fs::path& path, const std::string& content) {
  std::ofstream stream(path, std::ios::binary);
  stream << content;
  if (!stream) throw std::runtime_error("cannot write " + path.string());
}

// Runs a shell command, returns its stdout+stderr; throws on failure.
std::string Shell(const std::string& command) {
  FILE* pipe = ::popen((command + " 2>&1").c_str(), "r");
  if (pipe == nullptr) throw std::runtime_error("popen failed: " + command);
  std::string output;
  char buffer[4096];
  size_t n;
  while ((n = std::fread(buffer, 1, sizeof(buffer), pipe)) > 0) {
    output.append(buffer, n);
  }
  const int status = ::pclose(pipe);
  if (status != 0) {
    throw std::runtime_error("command failed (" + std::to_string(status) +
                             "): " + command + "\n" + output);
  }
  return output;
}

// The independent oracle: SQL run by the sqlite3 shell (list mode, '|').
std::string Sqlite3(const fs::path& db, const std::string& sql,
                    bool read_only = true) {
  const fs::path script = db.string() + ".query.sql";
  WriteFile(script, sql);
  const std::string output =
      Shell(std::string("sqlite3 -batch ") + (read_only ? "-readonly " : "") +
            "'" + db.string() + "' < '" + script.string() + "'");
  fs::remove(script);
  return output;
}

std::vector<std::vector<std::string>> Sqlite3Rows(const fs::path& db,
                                                  const std::string& sql) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream lines(Sqlite3(db, sql));
  std::string line;
  while (std::getline(lines, line)) {
    std::vector<std::string> fields;
    std::string field;
    std::istringstream parts(line);
    while (std::getline(parts, field, '|')) fields.push_back(field);
    if (!line.empty() && line.back() == '|') fields.emplace_back();
    rows.push_back(fields);
  }
  return rows;
}

int64_t Sqlite3Int(const fs::path& db, const std::string& sql) {
  return std::stoll(Sqlite3(db, sql));
}

std::string SchemaText(const fs::path& db) {
  return Sqlite3(db,
                 "SELECT type, name, tbl_name, sql FROM sqlite_master "
                 "ORDER BY type, name;");
}

void CreateDatabase(const fs::path& path,
                    const std::vector<const char*>& statements) {
  std::string sql;
  for (const char* statement : statements) sql += std::string(statement) + "\n";
  Sqlite3(path, sql, /*read_only=*/false);
}

// Bytes as SQLite's hex() prints them.
std::string Hex(const void* data, size_t num_bytes) {
  static const char kDigits[] = "0123456789ABCDEF";
  std::string hex;
  const auto* bytes = static_cast<const uint8_t*>(data);
  for (size_t i = 0; i < num_bytes; ++i) {
    hex += kDigits[bytes[i] >> 4];
    hex += kDigits[bytes[i] & 15];
  }
  return hex;
}

template <typename Matrix>
std::string HexOf(const Matrix& matrix) {
  return Hex(matrix.data(), matrix.size() * sizeof(typename Matrix::Scalar));
}

// The matrix's elements in COLMAP's blob order (row by row), whatever the
// matrix's own storage order, so a transposed read shows up.
template <typename Matrix>
std::string RowMajorHex(const Matrix& matrix) {
  std::string hex;
  for (Eigen::Index i = 0; i < matrix.rows(); ++i) {
    for (Eigen::Index j = 0; j < matrix.cols(); ++j) {
      hex += Hex(&matrix(i, j), sizeof(typename Matrix::Scalar));
    }
  }
  return hex;
}

template <typename Matrix>
bool BitIdentical(const Matrix& a, const Matrix& b) {
  return a.size() == b.size() &&
         std::memcmp(a.data(), b.data(),
                     a.size() * sizeof(typename Matrix::Scalar)) == 0;
}

template <typename Matrix>
bool AllNaN(const Matrix& matrix) {
  return matrix.array().isNaN().all();
}

// The message of the uw::Error `action` throws; fails the test otherwise.
std::string ErrorMessage(const std::function<void()>& action) {
  try {
    action();
  } catch (const Error& error) {
    return error.what();
  }
  ADD_FAILURE() << "expected a uw::Error";
  return "";
}

// COLMAP's pair id, spelled out independently of the code under test.
uint64_t ExpectedPairId(uint64_t a, uint64_t b) {
  return 2147483647ull * std::min(a, b) + std::max(a, b);
}

// ---------------------------------------------------------------------------
// A real COLMAP 3.8 database: images and features written by stock colmap.

constexpr int kTextureWidth = 1000;
constexpr int kTextureHeight = 300;
constexpr int kImageWidth = 320;
constexpr int kImageHeight = 240;
constexpr int kNumImages = 6;
constexpr int kCropStep = 120;  // Neighbouring crops overlap by 200 px.

// Multi-scale value noise: blobs at several sizes give SIFT stable corners.
std::vector<double> Texture() {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::vector<double> texture(kTextureWidth * kTextureHeight, 0.0);
  for (const int scale : {4, 9, 23}) {
    const int grid_width = kTextureWidth / scale + 2;
    const int grid_height = kTextureHeight / scale + 2;
    std::vector<double> grid(grid_width * grid_height);
    for (double& value : grid) value = uniform(random);
    for (int y = 0; y < kTextureHeight; ++y) {
      for (int x = 0; x < kTextureWidth; ++x) {
        const double fx = static_cast<double>(x) / scale;
        const double fy = static_cast<double>(y) / scale;
        const int ix = static_cast<int>(fx);
        const int iy = static_cast<int>(fy);
        const double tx = fx - ix;
        const double ty = fy - iy;
        const auto at = [&](int gx, int gy) {
          return grid[gy * grid_width + gx];
        };
        const double top = at(ix, iy) * (1 - tx) + at(ix + 1, iy) * tx;
        const double bottom =
            at(ix, iy + 1) * (1 - tx) + at(ix + 1, iy + 1) * tx;
        texture[y * kTextureWidth + x] += (top * (1 - ty) + bottom * ty) / 3;
      }
    }
  }
  return texture;
}

// img<k>.pgm is the crop starting at column k * kCropStep.
void WriteImages(const fs::path& image_dir) {
  fs::create_directories(image_dir);
  const std::vector<double> texture = Texture();
  for (int k = 0; k < kNumImages; ++k) {
    std::string pgm = "P5\n" + std::to_string(kImageWidth) + " " +
                      std::to_string(kImageHeight) + "\n255\n";
    for (int y = 0; y < kImageHeight; ++y) {
      for (int x = 0; x < kImageWidth; ++x) {
        const double value =
            texture[(y + 20) * kTextureWidth + x + k * kCropStep];
        pgm += static_cast<char>(std::clamp((value - 0.2) * 400, 0.0, 255.0));
      }
    }
    WriteFile(image_dir / ("img" + std::to_string(k) + ".pgm"), pgm);
  }
}

void RunColmap(const std::string& arguments, const fs::path& log) {
  Shell("colmap " + arguments + " > '" + log.string() + "'");
}

// Features of the six crops, extracted once per test process.
const fs::path& ColmapFeaturesDatabase() {
  static const fs::path database = [] {
    const fs::path dir = TestRoot() / "colmap38";
    fs::create_directories(dir);
    WriteImages(dir / "images");
    const fs::path path = dir / "features.db";
    RunColmap("feature_extractor --database_path '" + path.string() +
                  "' --image_path '" + (dir / "images").string() +
                  "' --SiftExtraction.use_gpu 0"
                  " --SiftExtraction.max_num_features 500",
              dir / "feature_extractor.log");
    return path;
  }();
  return database;
}

fs::path CopyOfColmapFeatures(const fs::path& dir, const std::string& name) {
  const fs::path path = dir / name;
  fs::copy_file(ColmapFeaturesDatabase(), path);
  return path;
}

TEST(ColmapDatabase38, ReadsWhatStockColmapWrote) {
  const fs::path dir = TestDir();
  const fs::path db_path = CopyOfColmapFeatures(dir, "database.db");
  RunColmap("exhaustive_matcher --database_path '" + db_path.string() +
                "' --SiftMatching.use_gpu 0",
            dir / "exhaustive_matcher.log");
  const std::string file_before = ReadFile(db_path);

  const Database db = Database::Open(db_path, Database::Mode::kReadOnly);
  EXPECT_EQ(db.Schema(), DatabaseSchema::kColmap38);
  EXPECT_FALSE(db.HasRigsAndFrames());

  // Cameras: colmap makes one SIMPLE_RADIAL (model 2) camera per image with
  // f = 1.2 * max(width, height) and the principal point at the centre.
  const std::vector<DatabaseCamera> cameras = db.ReadAllCameras();
  ASSERT_EQ(static_cast<int64_t>(cameras.size()),
            Sqlite3Int(db_path, "SELECT COUNT(*) FROM cameras;"));
  for (const DatabaseCamera& camera : cameras) {
    EXPECT_EQ(camera.model_id, 2);
    EXPECT_EQ(camera.width, uint64_t{kImageWidth});
    EXPECT_EQ(camera.height, uint64_t{kImageHeight});
    EXPECT_EQ(camera.params,
              (std::vector<double>{1.2 * kImageWidth, kImageWidth / 2.0,
                                   kImageHeight / 2.0, 0.0}));
    EXPECT_FALSE(camera.prior_focal_length);
  }

  // Images: ids and names as the shell sees them.
  std::map<uint32_t, std::string> name_of;
  for (const auto& row :
       Sqlite3Rows(db_path, "SELECT image_id, name, camera_id FROM images;")) {
    name_of[std::stoul(row[0])] = row[1];
  }
  const std::vector<DatabaseImage> images = db.ReadAllImages();
  ASSERT_EQ(images.size(), size_t{kNumImages});
  ASSERT_EQ(name_of.size(), size_t{kNumImages});
  std::map<std::string, uint32_t> id_of;
  for (const DatabaseImage& image : images) {
    EXPECT_EQ(name_of.at(image.image_id), image.name);
    id_of[image.name] = image.image_id;
    const auto by_name = db.ReadImageWithName(image.name);
    ASSERT_TRUE(by_name.has_value());
    EXPECT_EQ(by_name->image_id, image.image_id);
    EXPECT_EQ(by_name->camera_id, image.camera_id);
  }
  EXPECT_FALSE(db.ReadImageWithName("no_such_image.png").has_value());
  // Stock colmap leaves the prior columns NULL for images without EXIF GPS.
  EXPECT_TRUE(db.ReadAllPosePriors().empty());

  // Keypoints and descriptors: shape, size, and every byte in row order.
  std::map<uint32_t, int64_t> num_keypoints;
  for (const auto& row : Sqlite3Rows(
           db_path,
           "SELECT image_id, rows, cols, length(data), hex(substr(data, 1, "
           "4)), hex(substr(data, -4, 4)), hex(data) FROM keypoints;")) {
    const uint32_t image_id = std::stoul(row[0]);
    const FeatureKeypointsBlob keypoints = db.ReadKeypoints(image_id);
    ASSERT_EQ(keypoints.rows(), std::stoll(row[1])) << image_id;
    ASSERT_EQ(keypoints.cols(), std::stoll(row[2]));
    EXPECT_EQ(keypoints.cols(), 6);
    EXPECT_GT(keypoints.rows(), 100);
    EXPECT_EQ(keypoints.size() * 4, std::stoll(row[3]));
    EXPECT_EQ(Hex(&keypoints(0, 0), 4), row[4]);
    EXPECT_EQ(Hex(&keypoints(keypoints.rows() - 1, 5), 4), row[5]);
    EXPECT_TRUE(RowMajorHex(keypoints) == row[6]) << image_id;
    num_keypoints[image_id] = keypoints.rows();
  }
  EXPECT_EQ(num_keypoints.size(), size_t{kNumImages});
  for (const auto& row :
       Sqlite3Rows(db_path,
                   "SELECT image_id, rows, cols, hex(substr(data, 1, 1)), "
                   "hex(substr(data, -1, 1)), hex(data) FROM descriptors;")) {
    const DatabaseDescriptors descriptors =
        db.ReadDescriptors(std::stoul(row[0]));
    EXPECT_EQ(descriptors.type, FeatureExtractorType::kSift);
    ASSERT_EQ(descriptors.data.rows(), std::stoll(row[1]));
    ASSERT_EQ(descriptors.data.cols(), std::stoll(row[2]));
    EXPECT_EQ(descriptors.data.cols(), 128);
    EXPECT_EQ(Hex(&descriptors.data(0, 0), 1), row[3]);
    EXPECT_EQ(Hex(&descriptors.data(descriptors.data.rows() - 1, 127), 1),
              row[4]);
    EXPECT_TRUE(RowMajorHex(descriptors.data) == row[5]) << row[0];
  }

  // Matches: every pair of six images, indices within the keypoints.
  const auto matches = db.ReadAllMatches();
  const auto match_rows =
      Sqlite3Rows(db_path,
                  "SELECT pair_id, rows, cols, hex(substr(data, 1, 4)), "
                  "hex(substr(data, -4, 4)) FROM matches ORDER BY pair_id;");
  ASSERT_EQ(matches.size(), match_rows.size());
  EXPECT_EQ(matches.size(), size_t{kNumImages * (kNumImages - 1) / 2});
  std::map<image_pair_t, std::set<std::pair<uint32_t, uint32_t>>> match_sets;
  for (size_t i = 0; i < matches.size(); ++i) {
    const auto& [pair_id, blob] = matches[i];
    const auto& row = match_rows[i];
    ASSERT_EQ(pair_id, std::stoull(row[0]));
    ASSERT_EQ(blob.rows(), std::stoll(row[1]));
    const auto [image_id1, image_id2] = PairIdToImagePair(pair_id);
    EXPECT_EQ(ExpectedPairId(image_id1, image_id2), pair_id);
    ASSERT_TRUE(name_of.count(image_id1) && name_of.count(image_id2));
    if (blob.rows() > 0) {
      EXPECT_EQ(std::stoll(row[2]), 2);
      EXPECT_EQ(Hex(&blob(0, 0), 4), row[3]);
      EXPECT_EQ(Hex(&blob(blob.rows() - 1, 1), 4), row[4]);
    }
    for (Eigen::Index m = 0; m < blob.rows(); ++m) {
      EXPECT_LT(blob(m, 0), num_keypoints.at(image_id1));
      EXPECT_LT(blob(m, 1), num_keypoints.at(image_id2));
      match_sets[pair_id].emplace(blob(m, 0), blob(m, 1));
    }
  }

  // Two-view geometries: inliers are a subset of the matches; F, E, H come
  // back in COLMAP's row-major byte order; neighbouring crops verify.
  const auto geometries = db.ReadTwoViewGeometries();
  const auto geometry_rows = Sqlite3Rows(
      db_path,
      "SELECT pair_id, rows, config, hex(F), hex(E), hex(H), hex(qvec), "
      "hex(tvec) FROM two_view_geometries ORDER BY pair_id;");
  ASSERT_EQ(geometries.size(), geometry_rows.size());
  ASSERT_EQ(geometries.size(), matches.size());
  for (size_t i = 0; i < geometries.size(); ++i) {
    const auto& [pair_id, geometry] = geometries[i];
    const auto& row = geometry_rows[i];
    ASSERT_EQ(pair_id, std::stoull(row[0]));
    ASSERT_EQ(geometry.inlier_matches.rows(), std::stoll(row[1]));
    EXPECT_EQ(geometry.config, std::stoi(row[2]));
    for (Eigen::Index m = 0; m < geometry.inlier_matches.rows(); ++m) {
      EXPECT_TRUE(match_sets[pair_id].count(
          {geometry.inlier_matches(m, 0), geometry.inlier_matches(m, 1)}));
    }
    const std::optional<Eigen::Matrix3d>* matrices[] = {
        &geometry.F, &geometry.E, &geometry.H};
    for (int k = 0; k < 3; ++k) {
      if (row[3 + k].empty()) {
        EXPECT_FALSE(matrices[k]->has_value());
      } else {
        ASSERT_TRUE(matrices[k]->has_value());
        const Eigen::Matrix<double, 3, 3, Eigen::RowMajor> row_major =
            **matrices[k];
        EXPECT_EQ(HexOf(row_major), row[3 + k]);
      }
    }
    if (row[6].empty()) {
      EXPECT_FALSE(geometry.cam2_from_cam1.has_value());
    } else {
      ASSERT_TRUE(geometry.cam2_from_cam1.has_value());
      EXPECT_EQ(HexOf(geometry.cam2_from_cam1->rotation_wxyz), row[6]);
      EXPECT_EQ(HexOf(geometry.cam2_from_cam1->translation), row[7]);
    }
  }
  for (int k = 0; k + 1 < kNumImages; ++k) {
    const image_pair_t pair_id =
        ExpectedPairId(id_of.at("img" + std::to_string(k) + ".pgm"),
                       id_of.at("img" + std::to_string(k + 1) + ".pgm"));
    const auto it =
        std::find_if(geometries.begin(), geometries.end(),
                     [&](const auto& entry) { return entry.first == pair_id; });
    ASSERT_NE(it, geometries.end());
    EXPECT_GE(it->second.inlier_matches.rows(), 50) << "crops " << k;
    EXPECT_TRUE(it->second.F.has_value());
  }

  // Reading never modifies the file.
  EXPECT_EQ(ReadFile(db_path), file_before);
}

TEST(ColmapDatabase38, SpatialMatcherUsesPriorsWeWrote) {
  const fs::path dir = TestDir();
  const fs::path db_path = CopyOfColmapFeatures(dir, "database.db");
  const std::string schema_before = SchemaText(db_path);

  // Positions on a line, out of image-id order; powers of two have no ties
  // in distance, so each image's nearest neighbours are unique.
  const double kX[kNumImages] = {8, 1, 32, 2, 16, 4};
  std::vector<PosePrior> priors;
  {
    Database db = Database::Open(db_path, Database::Mode::kReadWrite);
    const std::vector<DatabaseImage> images = db.ReadAllImages();
    ASSERT_EQ(images.size(), size_t{kNumImages});
    for (int i = 0; i < kNumImages; ++i) {
      PosePrior prior;
      prior.image_id = images[i].image_id;
      prior.position = Eigen::Vector3d(kX[i], 0.25, 100.0 + i);
      prior.coordinate_system = PosePriorCoordinateSystem::kCartesian;
      prior.position_covariance = Eigen::Matrix3d::Identity();
      if (i == 0) {
        prior.cam_from_world_rotation_wxyz =
            Eigen::Vector4d(0.5, -0.5, 0.5, 0.5);
      }
      priors.push_back(prior);
    }
    const PosePriorWriteSummary summary = db.WritePosePriors(priors);
    EXPECT_EQ(summary.num_written, size_t{kNumImages});
    EXPECT_EQ(summary.num_dropped_covariances, size_t{kNumImages});
    EXPECT_EQ(summary.num_dropped_coordinate_systems, size_t{kNumImages});
    EXPECT_EQ(summary.num_dropped_rotations, 0u);
  }
  EXPECT_EQ(SchemaText(db_path), schema_before);

  // What the images table holds now, read by the shell.
  for (const auto& row : Sqlite3Rows(
           db_path,
           "SELECT image_id, prior_qw, prior_qx, prior_tx, prior_ty, prior_tz "
           "FROM images ORDER BY image_id;")) {
    const auto it = std::find_if(priors.begin(), priors.end(), [&](auto& p) {
      return p.image_id == std::stoul(row[0]);
    });
    ASSERT_NE(it, priors.end());
    EXPECT_EQ(std::stod(row[3]), it->position.x());
    EXPECT_EQ(std::stod(row[4]), it->position.y());
    EXPECT_EQ(std::stod(row[5]), it->position.z());
    EXPECT_EQ(row[1].empty(), !it->cam_from_world_rotation_wxyz.has_value());
  }
  {
    const Database db = Database::Open(db_path, Database::Mode::kReadOnly);
    const std::vector<PosePrior> read = db.ReadAllPosePriors();
    ASSERT_EQ(read.size(), priors.size());
    for (size_t i = 0; i < read.size(); ++i) {
      EXPECT_EQ(read[i].image_id, priors[i].image_id);
      EXPECT_TRUE(BitIdentical(read[i].position, priors[i].position));
      EXPECT_TRUE(AllNaN(read[i].position_covariance));
      EXPECT_EQ(read[i].coordinate_system,
                PosePriorCoordinateSystem::kUndefined);
      EXPECT_EQ(read[i].cam_from_world_rotation_wxyz.has_value(), i == 0);
    }
    EXPECT_TRUE(BitIdentical(*read[0].cam_from_world_rotation_wxyz,
                             *priors[0].cam_from_world_rotation_wxyz));
  }

  // colmap matches each image with its max_num_neighbors - 1 nearest
  // neighbours (the query itself is the first hit) and writes a matches row
  // for every pair it tried, matched or not.
  constexpr int kNeighbors = 3;
  RunColmap("spatial_matcher --database_path '" + db_path.string() +
                "' --SiftMatching.use_gpu 0 --SpatialMatching.is_gps 0"
                " --SpatialMatching.max_distance 1000"
                " --SpatialMatching.max_num_neighbors " +
                std::to_string(kNeighbors),
            dir / "spatial_matcher.log");
  std::set<uint64_t> expected;
  for (int i = 0; i < kNumImages; ++i) {
    std::vector<int> others;
    for (int j = 0; j < kNumImages; ++j) {
      if (j != i) others.push_back(j);
    }
    std::sort(others.begin(), others.end(), [&](int a, int b) {
      return std::abs(kX[a] - kX[i]) < std::abs(kX[b] - kX[i]);
    });
    for (int n = 0; n < kNeighbors - 1; ++n) {
      expected.insert(
          ExpectedPairId(priors[i].image_id, priors[others[n]].image_id));
    }
  }
  std::set<uint64_t> actual;
  for (const auto& row : Sqlite3Rows(db_path, "SELECT pair_id FROM matches;")) {
    actual.insert(std::stoull(row[0]));
  }
  EXPECT_EQ(actual, expected);
  EXPECT_LT(expected.size(), size_t{kNumImages * (kNumImages - 1) / 2});
}

// ---------------------------------------------------------------------------
// Later schemas, built from COLMAP's CREATE TABLE statements.

struct FixtureDatabase {
  fs::path path;
  std::vector<DatabaseImage> images;
};

// Two cameras and three images (image 3 on camera 2), written by us.
FixtureDatabase MakeFixture(const fs::path& dir, const Fixture& fixture,
                            const std::string& suffix = "") {
  FixtureDatabase result;
  result.path = dir / ("colmap_" + fixture.tag + suffix + ".db");
  CreateDatabase(result.path, fixture.statements);
  Database db = Database::Open(result.path, Database::Mode::kReadWrite);
  for (const uint32_t camera_id : {1u, 2u}) {
    DatabaseCamera camera;
    camera.camera_id = camera_id;
    camera.model_id = 1;  // PINHOLE
    camera.width = 640;
    camera.height = 480;
    camera.params = {500.0 + camera_id, 501.0, 320.0, 240.0};
    camera.prior_focal_length = camera_id == 2;
    EXPECT_EQ(db.WriteCamera(camera), camera_id);
  }
  for (const uint32_t image_id : {1u, 2u, 3u}) {
    DatabaseImage image;
    image.name = "dive1/img" + std::to_string(image_id) + ".jpg";
    image.camera_id = image_id == 3 ? 2 : 1;
    image.image_id = db.WriteImage(image);
    EXPECT_EQ(image.image_id, image_id);
    result.images.push_back(image);
  }
  return result;
}

PosePrior RandomPrior(uint32_t image_id, std::mt19937_64* random) {
  std::uniform_real_distribution<double> uniform(-1000.0, 1000.0);
  PosePrior prior;
  prior.image_id = image_id;
  for (int i = 0; i < 3; ++i) prior.position(i) = uniform(*random);
  for (int i = 0; i < 9; ++i) prior.position_covariance(i) = uniform(*random);
  for (int i = 0; i < 3; ++i) prior.gravity_in_cam(i) = uniform(*random);
  prior.coordinate_system = static_cast<PosePriorCoordinateSystem>(
      static_cast<int>(image_id % 3) - 1);
  return prior;
}

// What a database of `schema` gives back for a written prior.
PosePrior Stored(PosePrior prior, DatabaseSchema schema) {
  if (schema == DatabaseSchema::kColmap38) {
    prior.coordinate_system = PosePriorCoordinateSystem::kUndefined;
    // SQLite stores an integral value of a REAL column as an integer, so
    // -0.0 comes back as +0.0 (stock COLMAP 3.8 sees the same).
    for (double& value : prior.position) {
      if (value == 0.0) value = 0.0;
    }
  }
  if (schema == DatabaseSchema::kColmap38 ||
      schema == DatabaseSchema::kColmap310) {
    prior.position_covariance.setConstant(PosePrior::kNaN);
  }
  if (schema != DatabaseSchema::kColmap4) {
    prior.gravity_in_cam.setConstant(PosePrior::kNaN);
  }
  if (schema != DatabaseSchema::kColmap38) {
    prior.cam_from_world_rotation_wxyz.reset();
  }
  return prior;
}

void ExpectSamePriors(const std::vector<PosePrior>& actual,
                      const std::vector<PosePrior>& expected) {
  ASSERT_EQ(actual.size(), expected.size());
  for (size_t i = 0; i < actual.size(); ++i) {
    SCOPED_TRACE("prior of image " + std::to_string(expected[i].image_id));
    EXPECT_EQ(actual[i].image_id, expected[i].image_id);
    EXPECT_TRUE(BitIdentical(actual[i].position, expected[i].position));
    EXPECT_TRUE(BitIdentical(actual[i].position_covariance,
                             expected[i].position_covariance) ||
                (AllNaN(actual[i].position_covariance) &&
                 AllNaN(expected[i].position_covariance)));
    EXPECT_TRUE(
        BitIdentical(actual[i].gravity_in_cam, expected[i].gravity_in_cam) ||
        (AllNaN(actual[i].gravity_in_cam) &&
         AllNaN(expected[i].gravity_in_cam)));
    EXPECT_EQ(actual[i].coordinate_system, expected[i].coordinate_system);
    ASSERT_EQ(actual[i].cam_from_world_rotation_wxyz.has_value(),
              expected[i].cam_from_world_rotation_wxyz.has_value());
    if (expected[i].cam_from_world_rotation_wxyz) {
      EXPECT_TRUE(BitIdentical(*actual[i].cam_from_world_rotation_wxyz,
                               *expected[i].cam_from_world_rotation_wxyz));
    }
  }
}

TEST(DatabaseSchemas, DetectsEveryTag) {
  const fs::path dir = TestDir();
  for (const Fixture& fixture : AllFixtures()) {
    SCOPED_TRACE("COLMAP " + fixture.tag);
    const FixtureDatabase made = MakeFixture(dir, fixture);
    const Database db = Database::Open(made.path, Database::Mode::kReadOnly);
    EXPECT_EQ(db.Schema(), fixture.schema) << DatabaseSchemaName(db.Schema());
    EXPECT_EQ(db.HasRigsAndFrames(), fixture.has_rigs_and_frames);
    EXPECT_EQ(db.ReadAllImages().size(), 3u);
    EXPECT_TRUE(db.ReadAllPosePriors().empty());
  }
  // A 3.8 database that COLMAP 3.10 opened keeps its prior_* columns and
  // gains pose_priors, which is what 3.10 and later read.
  Fixture upgraded = Colmap38Fixture();
  upgraded.tag = "3.8-opened-by-3.10";
  upgraded.statements.push_back(kPosePriors310Sql);
  const FixtureDatabase made = MakeFixture(dir, upgraded);
  EXPECT_EQ(Database::Open(made.path, Database::Mode::kReadOnly).Schema(),
            DatabaseSchema::kColmap310);
}

TEST(DatabaseSchemas, PosePriorsRoundTripInEverySchema) {
  const fs::path dir = TestDir();
  std::mt19937_64 random(42);
  for (const Fixture& fixture : AllFixtures()) {
    SCOPED_TRACE("COLMAP " + fixture.tag);
    const FixtureDatabase made = MakeFixture(dir, fixture);
    const std::string schema_before = SchemaText(made.path);

    std::vector<PosePrior> priors = {RandomPrior(1, &random),
                                     RandomPrior(3, &random)};
    priors[0].position(1) = -0.0;
    priors[0].position(2) = 5e-324;  // Subnormal: survives only as bits.
    priors[1].position_covariance.setConstant(PosePrior::kNaN);
    priors[1].cam_from_world_rotation_wxyz = Eigen::Vector4d(1, 0, 0, 0);
    {
      Database db = Database::Open(made.path, Database::Mode::kReadWrite);
      const PosePriorWriteSummary summary = db.WritePosePriors(priors);
      EXPECT_EQ(summary.num_written, 2u);
      const bool has_covariance =
          fixture.schema == DatabaseSchema::kColmap311 ||
          fixture.schema == DatabaseSchema::kColmap4;
      EXPECT_EQ(summary.num_dropped_covariances, has_covariance ? 0u : 1u);
      EXPECT_EQ(summary.num_dropped_gravities,
                fixture.schema == DatabaseSchema::kColmap4 ? 0u : 2u);
      EXPECT_EQ(summary.num_dropped_rotations,
                fixture.schema == DatabaseSchema::kColmap38 ? 0u : 1u);
    }
    std::vector<PosePrior> expected = {Stored(priors[0], fixture.schema),
                                       Stored(priors[1], fixture.schema)};
    ExpectSamePriors(Database::Open(made.path, Database::Mode::kReadOnly)
                         .ReadAllPosePriors(),
                     expected);

    // Replace image 1's prior and add image 2's: still one row per image.
    PosePrior replaced = RandomPrior(1, &random);
    PosePrior added = RandomPrior(2, &random);
    Database::Open(made.path, Database::Mode::kReadWrite)
        .WritePosePriors({added, replaced});
    expected = {Stored(replaced, fixture.schema), Stored(added, fixture.schema),
                expected[1]};
    ExpectSamePriors(Database::Open(made.path, Database::Mode::kReadOnly)
                         .ReadAllPosePriors(),
                     expected);
    EXPECT_EQ(SchemaText(made.path), schema_before);

    // The bytes COLMAP reads: covariance in Matrix3d::data() order, absent
    // values as NaN blobs (COLMAP would read NULL as zeros).
    if (fixture.schema == DatabaseSchema::kColmap311 ||
        fixture.schema == DatabaseSchema::kColmap4) {
      const std::string key = fixture.schema == DatabaseSchema::kColmap4
                                  ? "corr_data_id"
                                  : "image_id";
      const auto rows = Sqlite3Rows(
          made.path, "SELECT " + key +
                         ", hex(position), hex(position_covariance) FROM "
                         "pose_priors ORDER BY " +
                         key + ";");
      ASSERT_EQ(rows.size(), 3u);
      EXPECT_EQ(rows[0][1], HexOf(replaced.position));
      EXPECT_EQ(rows[0][2], HexOf(replaced.position_covariance));
      EXPECT_EQ(rows[2][2], HexOf(priors[1].position_covariance));
      EXPECT_EQ(rows[2][2].size(), 9u * 8u * 2u);
    }
    if (fixture.schema == DatabaseSchema::kColmap4) {
      // The image is the data id of its camera sensor (type CAMERA = 0), and
      // a replaced prior keeps its pose_prior_id.
      EXPECT_EQ(Sqlite3(made.path,
                        "SELECT pose_prior_id, corr_data_id, corr_sensor_id, "
                        "corr_sensor_type, hex(gravity) = '" +
                            HexOf(added.gravity_in_cam) +
                            "' FROM pose_priors ORDER BY corr_data_id;"),
                "1|1|1|0|0\n3|2|1|0|1\n2|3|2|0|0\n");
    }
  }
}

TEST(DatabaseSchemas, FeatureWritersRoundTrip) {
  const fs::path dir = TestDir();
  for (const Fixture& fixture : AllFixtures()) {
    SCOPED_TRACE("COLMAP " + fixture.tag);
    const FixtureDatabase made = MakeFixture(dir, fixture);
    FeatureKeypointsBlob keypoints(3, 4);
    keypoints << 1.5f, 2.5f, 3, 0.25f, 10, 20, 1, -1, 300.75f, 200.5f, 2, 3.5f;
    DatabaseDescriptors descriptors;
    descriptors.data.resize(3, 8);
    for (Eigen::Index i = 0; i < descriptors.data.size(); ++i) {
      descriptors.data.data()[i] = static_cast<uint8_t>(i * 7);
    }
    FeatureMatchesBlob matches(2, 2);
    matches << 0, 1, 2, 0;  // Columns index image 3's, then image 1's.
    {
      Database db = Database::Open(made.path, Database::Mode::kReadWrite);
      db.WriteKeypoints(1, keypoints);
      db.WriteDescriptors(1, descriptors);
      db.WriteMatches(3, 1, matches);
      DatabaseDescriptors aliked = descriptors;
      aliked.type = FeatureExtractorType::kAlikedN32;
      if (fixture.schema == DatabaseSchema::kColmap4) {
        db.WriteDescriptors(2, aliked);
      } else {
        EXPECT_NE(ErrorMessage([&] {
                    db.WriteDescriptors(2, aliked);
                  }).find("SIFT descriptors only"),
                  std::string::npos);
      }
      EXPECT_THROW(db.WriteKeypoints(1, keypoints), Error);  // Exists.
      EXPECT_THROW(db.WriteMatches(1, 99, matches), Error);
    }
    EXPECT_EQ(
        Sqlite3(made.path, "SELECT rows, cols, hex(data) FROM keypoints;"),
        "3|4|" + HexOf(keypoints) + "\n");
    // Stored from the smaller image id: columns swapped.
    FeatureMatchesBlob swapped(2, 2);
    swapped << 1, 0, 0, 2;
    EXPECT_EQ(
        Sqlite3(made.path,
                "SELECT pair_id, rows, cols, hex(data) "
                "FROM matches;"),
        std::to_string(ExpectedPairId(1, 3)) + "|2|2|" + HexOf(swapped) + "\n");

    const Database db = Database::Open(made.path, Database::Mode::kReadOnly);
    EXPECT_TRUE(BitIdentical(db.ReadKeypoints(1), keypoints));
    EXPECT_EQ(db.ReadKeypoints(2).size(), 0);
    EXPECT_TRUE(BitIdentical(db.ReadDescriptors(1).data, descriptors.data));
    if (fixture.schema == DatabaseSchema::kColmap4) {
      EXPECT_EQ(db.ReadDescriptors(2).type, FeatureExtractorType::kAlikedN32);
    }
    const auto all_matches = db.ReadAllMatches();
    ASSERT_EQ(all_matches.size(), 1u);
    EXPECT_EQ(all_matches[0].first, ExpectedPairId(1, 3));
    EXPECT_TRUE(BitIdentical(all_matches[0].second, swapped));
    EXPECT_TRUE(db.ReadTwoViewGeometries().empty());

    const auto cameras = db.ReadAllCameras();
    ASSERT_EQ(cameras.size(), 2u);
    EXPECT_EQ(cameras[1].params, (std::vector<double>{502, 501, 320, 240}));
    EXPECT_TRUE(cameras[1].prior_focal_length);
    EXPECT_EQ(Sqlite3(made.path,
                      "SELECT hex(params) FROM cameras WHERE camera_id=2;"),
              HexOf(Eigen::Vector4d(502, 501, 320, 240)) + "\n");
  }
}

TEST(DatabaseSchemas, ReadsTwoViewGeometriesWrittenByTheShell) {
  const fs::path dir = TestDir();
  const FixtureDatabase made = MakeFixture(dir, LaterFixtures().back());
  // F stored row-major: bytes of 1..9 in reading order; E, H NULL as 4.x
  // writes them when not estimated.
  Eigen::Matrix<double, 3, 3, Eigen::RowMajor> f_row_major;
  f_row_major << 1, 2, 3, 4, 5, 6, 7, 8, 9;
  const Eigen::Vector4d qvec(0.5, 0.5, -0.5, 0.5);
  const Eigen::Vector3d tvec(1, -2, 3);
  FeatureMatchesBlob inliers(1, 2);
  inliers << 4, 5;
  Sqlite3(made.path,
          "INSERT INTO two_view_geometries(pair_id, rows, cols, data, "
          "config, F, E, H, qvec, tvec) VALUES(" +
              std::to_string(ExpectedPairId(1, 2)) + ", 1, 2, X'" +
              HexOf(inliers) + "', 3, X'" + HexOf(f_row_major) +
              "', NULL, NULL, X'" + HexOf(qvec) + "', X'" + HexOf(tvec) + "');",
          /*read_only=*/false);
  const auto geometries = Database::Open(made.path, Database::Mode::kReadOnly)
                              .ReadTwoViewGeometries();
  ASSERT_EQ(geometries.size(), 1u);
  const TwoViewGeometry& geometry = geometries[0].second;
  EXPECT_EQ(geometry.config, 3);
  EXPECT_TRUE(BitIdentical(geometry.inlier_matches, inliers));
  ASSERT_TRUE(geometry.F.has_value());
  EXPECT_EQ((*geometry.F)(0, 1), 2.0);
  EXPECT_EQ((*geometry.F)(1, 0), 4.0);
  EXPECT_FALSE(geometry.E.has_value());
  EXPECT_FALSE(geometry.H.has_value());
  ASSERT_TRUE(geometry.cam2_from_cam1.has_value());
  EXPECT_TRUE(BitIdentical(geometry.cam2_from_cam1->rotation_wxyz, qvec));
  EXPECT_TRUE(BitIdentical(geometry.cam2_from_cam1->translation, tvec));
}

// database_analyzer's counts: keypoints of one image, a pair with matches,
// one with inliers, priors with and without covariance.
TEST(DatabaseStats, CountsWhatTheDatabaseHolds) {
  const fs::path dir = TestDir();
  const FixtureDatabase made = MakeFixture(dir, LaterFixtures()[3]);
  {
    Database db = Database::Open(made.path, Database::Mode::kReadWrite);
    db.WriteKeypoints(1, FeatureKeypointsBlob::Zero(5, 4));
    db.WriteKeypoints(2, FeatureKeypointsBlob::Zero(0, 4));
    FeatureMatchesBlob matches(2, 2);
    matches << 0, 1, 2, 0;
    db.WriteMatches(1, 3, matches);
    std::mt19937_64 random(1);
    PosePrior without = RandomPrior(2, &random);
    without.position_covariance.setConstant(PosePrior::kNaN);
    db.WritePosePriors({RandomPrior(1, &random), without});
  }
  const FeatureMatchesBlob inliers = FeatureMatchesBlob::Zero(3, 2);
  Sqlite3(made.path,
          "INSERT INTO two_view_geometries(pair_id, rows, cols, data, "
          "config) VALUES(" +
              std::to_string(ExpectedPairId(1, 2)) + ", 3, 2, X'" +
              HexOf(inliers) + "', 2);",
          /*read_only=*/false);
  const DatabaseStats stats = ComputeDatabaseStats(
      Database::Open(made.path, Database::Mode::kReadOnly));
  EXPECT_EQ(FormatDatabaseAnalyzerReport(stats),
            "Schema: " + DatabaseSchemaName(DatabaseSchema::kColmap4) +
                ", with rigs and frames\n"
                "Cameras: 2\n"
                "Images: 3\n"
                "Images with keypoints: 1\n"
                "Keypoints: 5\n"
                "Matched pairs: 1\n"
                "Verified pairs: 1\n"
                "Inlier matches: 3\n"
                "Pose priors: 2 (1 with position covariance)\n");
}

// ---------------------------------------------------------------------------
// Bad input.

TEST(DatabaseErrors, MissingFileIsAnErrorAndNotCreated) {
  const fs::path path = TestDir() / "no_such.db";
  for (const auto mode :
       {Database::Mode::kReadOnly, Database::Mode::kReadWrite}) {
    const std::string message =
        ErrorMessage([&] { Database::Open(path, mode); });
    EXPECT_NE(message.find(path.string()), std::string::npos) << message;
    EXPECT_FALSE(fs::exists(path));
  }
}

TEST(DatabaseErrors, NotADatabase) {
  const fs::path path = TestDir() / "notes.db";
  WriteFile(path, "dive 3 notes: this is text, not SQLite\n");
  const std::string message =
      ErrorMessage([&] { Database::Open(path, Database::Mode::kReadOnly); });
  EXPECT_NE(message.find(path.string()), std::string::npos) << message;
}

TEST(DatabaseErrors, IncompleteSchemaNamesFileAndTable) {
  const fs::path dir = TestDir();
  struct Case {
    Fixture fixture;
    const char* dropped;    // Statement left out.
    const char* mentioned;  // Must appear in the message.
  };
  const std::vector<Fixture> later = LaterFixtures();
  const std::vector<Case> cases = {
      {later[0], kImages310Sql, "'images'"},
      {Colmap38Fixture(), kImages38Sql, "'images'"},
      {Colmap38Fixture(), kTwoViewGeometriesSql, "'two_view_geometries'"},
      {later[2], kFrameDataSql, "'frame_data'"},
      {later[3], kDescriptors4Sql, "'descriptors'"},
  };
  for (size_t i = 0; i < cases.size(); ++i) {
    Fixture fixture = cases[i].fixture;
    auto& statements = fixture.statements;
    statements.erase(
        std::find(statements.begin(), statements.end(), cases[i].dropped));
    const fs::path path = dir / ("case" + std::to_string(i) + ".db");
    CreateDatabase(path, statements);
    const std::string message =
        ErrorMessage([&] { Database::Open(path, Database::Mode::kReadOnly); });
    EXPECT_NE(message.find(path.string()), std::string::npos) << message;
    EXPECT_NE(message.find(cases[i].mentioned), std::string::npos) << message;
  }

  // A column missing: 4.x pose_priors without gravity.
  std::string pose_priors = kPosePriors4Sql;
  const std::string gravity = "    gravity                    BLOB,";
  ASSERT_NE(pose_priors.find(gravity), std::string::npos);
  pose_priors.erase(pose_priors.find(gravity), gravity.size());
  Fixture fixture = later[3];
  std::replace(fixture.statements.begin(), fixture.statements.end(),
               static_cast<const char*>(kPosePriors4Sql), pose_priors.c_str());
  const fs::path path = dir / "no_gravity.db";
  CreateDatabase(path, fixture.statements);
  const std::string message =
      ErrorMessage([&] { Database::Open(path, Database::Mode::kReadOnly); });
  EXPECT_NE(message.find(path.string()), std::string::npos) << message;
  EXPECT_NE(message.find("'pose_priors'"), std::string::npos) << message;
  EXPECT_NE(message.find("'gravity'"), std::string::npos) << message;
}

TEST(DatabaseErrors, BlobSizeMismatchNamesTableAndId) {
  const FixtureDatabase made = MakeFixture(TestDir(), Colmap38Fixture());
  Sqlite3(made.path,
          "INSERT INTO keypoints VALUES(2, 5, 6, zeroblob(100));"
          "INSERT INTO keypoints VALUES(3, 1, 2, zeroblob(12));"
          "INSERT INTO descriptors VALUES(2, 5, 128, NULL);"
          "INSERT INTO matches VALUES(" +
              std::to_string(ExpectedPairId(1, 2)) + ", 3, 2, zeroblob(8));",
          /*read_only=*/false);
  const Database db = Database::Open(made.path, Database::Mode::kReadOnly);
  const std::string keypoints = ErrorMessage([&] { db.ReadKeypoints(2); });
  for (const std::string& expected :
       {made.path.string(), std::string("keypoints"), std::string("image_id 2"),
        std::string("100 bytes"), std::string("= 120")}) {
    EXPECT_NE(keypoints.find(expected), std::string::npos) << keypoints;
  }
  const std::string too_long = ErrorMessage([&] { db.ReadKeypoints(3); });
  EXPECT_NE(too_long.find("keypoints, image_id 3: data has 12 bytes"),
            std::string::npos)
      << too_long;
  const std::string descriptors = ErrorMessage([&] { db.ReadDescriptors(2); });
  EXPECT_NE(descriptors.find("descriptors, image_id 2: data has 0 bytes"),
            std::string::npos)
      << descriptors;
  const std::string matches = ErrorMessage([&] { db.ReadAllMatches(); });
  EXPECT_NE(
      matches.find("matches, pair_id " + std::to_string(ExpectedPairId(1, 2))),
      std::string::npos)
      << matches;
}

TEST(DatabaseErrors, FailedPriorWriteLeavesDatabaseUnchanged) {
  const fs::path dir = TestDir();
  std::mt19937_64 random(3);
  for (const Fixture& fixture : AllFixtures()) {
    SCOPED_TRACE("COLMAP " + fixture.tag);
    const FixtureDatabase made = MakeFixture(dir, fixture);
    Database db = Database::Open(made.path, Database::Mode::kReadWrite);
    db.WritePosePriors({RandomPrior(1, &random), RandomPrior(2, &random)});
    const std::string dump_before = Sqlite3(made.path, ".dump");

    // Image 1 and 3 are valid; 999 is not, and comes last.
    const std::string message = ErrorMessage([&] {
      db.WritePosePriors({RandomPrior(1, &random), RandomPrior(3, &random),
                          RandomPrior(999, &random)});
    });
    EXPECT_NE(message.find("image_id 999"), std::string::npos) << message;
    EXPECT_NE(message.find(made.path.string()), std::string::npos) << message;
    EXPECT_EQ(Sqlite3(made.path, ".dump"), dump_before);

    EXPECT_THROW(
        db.WritePosePriors({RandomPrior(3, &random), RandomPrior(3, &random)}),
        Error);
    EXPECT_EQ(Sqlite3(made.path, ".dump"), dump_before);

    // The connection is still usable after the rollback.
    db.WritePosePriors({RandomPrior(3, &random)});
    EXPECT_EQ(db.ReadAllPosePriors().size(), 3u);
  }
}

TEST(DatabaseErrors, ReadOnlyRefusesWrites) {
  const FixtureDatabase made = MakeFixture(TestDir(), LaterFixtures()[1]);
  const std::string dump_before = Sqlite3(made.path, ".dump");
  Database db = Database::Open(made.path, Database::Mode::kReadOnly);
  PosePrior prior;
  prior.image_id = 1;
  prior.position = Eigen::Vector3d(1, 2, 3);
  const std::string message =
      ErrorMessage([&] { db.WritePosePriors({prior}); });
  EXPECT_NE(message.find("read-only"), std::string::npos) << message;
  EXPECT_THROW(db.WriteImage({0, "x.jpg", 1}), Error);
  EXPECT_EQ(Sqlite3(made.path, ".dump"), dump_before);
}

TEST(PairIds, MatchColmapFormula) {
  EXPECT_EQ(ImagePairToPairId(1, 2), 2147483649ull);
  EXPECT_EQ(ImagePairToPairId(2, 1), 2147483649ull);
  EXPECT_EQ(ImagePairToPairId(6, 5), ExpectedPairId(5, 6));
  EXPECT_EQ(ImagePairToPairId(0, 2147483646u), 2147483646ull);
  EXPECT_EQ(PairIdToImagePair(ExpectedPairId(3, 77)),
            (std::pair<uint32_t, uint32_t>(3, 77)));
  EXPECT_EQ(PairIdToImagePair(ImagePairToPairId(2147483646u, 12345)),
            (std::pair<uint32_t, uint32_t>(12345, 2147483646u)));
  EXPECT_THROW(ImagePairToPairId(1, 2147483647u), Error);
  EXPECT_THROW(PairIdToImagePair(ExpectedPairId(1, 3) + 2147483647ull * 5),
               Error);
}

}  // namespace
}  // namespace uw
