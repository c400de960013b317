#include "colmap_plugins/scene/database.h"

#include <unistd.h>

#include <sqlite3.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <map>
#include <set>
#include <sstream>

#include "common/util/error.h"

namespace uw {
namespace {

// An SQLite URI path: characters with a meaning in URIs are escaped.
std::string PercentEncodePath(const std::filesystem::path& path) {
  static const char kHex[] = "0123456789ABCDEF";
  std::string encoded;
  for (const unsigned char c : path.string()) {
    if (c == '%' || c == '?' || c == '#' || c < 0x20 || c >= 0x7f) {
      encoded += '%';
      encoded += kHex[c >> 4];
      encoded += kHex[c & 15];
    } else {
      encoded += static_cast<char>(c);
    }
  }
  return encoded;
}

namespace fs = std::filesystem;

// COLMAP's SensorType::CAMERA, stored in corr_sensor_type and sensor_type.
constexpr int64_t kSensorTypeCamera = 0;

std::string Lower(std::string text) {
  for (char& c : text) {
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  }
  return text;
}

void Exec(sqlite3* db, const fs::path& path, const char* sql) {
  char* message = nullptr;
  const int rc = sqlite3_exec(db, sql, nullptr, nullptr, &message);
  if (rc != SQLITE_OK) {
    const std::string text = message ? message : sqlite3_errstr(rc);
    sqlite3_free(message);
    throw ErrorAt(path.string(), ": SQLite error in \"", sql, "\": ", text);
  }
}

// A prepared statement that finalizes itself and turns every SQLite failure
// into a uw::Error naming the database file and the statement.
class Statement {
 public:
  Statement(sqlite3* db, const fs::path& path, std::string sql)
      : db_(db), path_(path), sql_(std::move(sql)) {
    const int rc = sqlite3_prepare_v2(db_, sql_.c_str(), -1, &stmt_, nullptr);
    if (rc != SQLITE_OK) Fail("prepare");
  }
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;
  ~Statement() { sqlite3_finalize(stmt_); }

  void BindInt64(int index, int64_t value) {
    Check(sqlite3_bind_int64(stmt_, index, value), "bind");
  }
  // NaN binds as NULL explicitly (SQLite would store NULL anyway).
  void BindDouble(int index, double value) {
    if (std::isnan(value)) {
      BindNull(index);
    } else {
      Check(sqlite3_bind_double(stmt_, index, value), "bind");
    }
  }
  void BindText(int index, const std::string& value) {
    Check(sqlite3_bind_text(stmt_, index, value.data(),
                            static_cast<int>(value.size()), SQLITE_TRANSIENT),
          "bind");
  }
  // An empty blob binds as NULL, as COLMAP's writers produce.
  void BindBlob(int index, const void* data, size_t num_bytes) {
    if (num_bytes == 0) {
      BindNull(index);
      return;
    }
    if (num_bytes > static_cast<size_t>(std::numeric_limits<int>::max())) {
      throw ErrorAt(path_.string(), ": blob of ", num_bytes,
                    " bytes is too large for SQLite in \"", sql_, "\"");
    }
    Check(sqlite3_bind_blob(stmt_, index, data, static_cast<int>(num_bytes),
                            SQLITE_TRANSIENT),
          "bind");
  }
  template <typename Matrix>
  void BindMatrix(int index, const Matrix& matrix) {
    BindBlob(
        index, matrix.data(),
        static_cast<size_t>(matrix.size()) * sizeof(typename Matrix::Scalar));
  }
  void BindNull(int index) { Check(sqlite3_bind_null(stmt_, index), "bind"); }

  // Makes the statement ready to be bound and run again.
  void Reset() {
    sqlite3_reset(stmt_);
    Check(sqlite3_clear_bindings(stmt_), "clear bindings");
  }

  // True while there is a row to read.
  bool Step() {
    const int rc = sqlite3_step(stmt_);
    if (rc == SQLITE_ROW) return true;
    if (rc == SQLITE_DONE) return false;
    Fail("step");
  }

  bool IsNull(int col) const {
    return sqlite3_column_type(stmt_, col) == SQLITE_NULL;
  }
  int64_t Int64(int col) const { return sqlite3_column_int64(stmt_, col); }
  double Double(int col) const { return sqlite3_column_double(stmt_, col); }
  std::string Text(int col) const {
    const auto* text =
        reinterpret_cast<const char*>(sqlite3_column_text(stmt_, col));
    return text ? std::string(text, sqlite3_column_bytes(stmt_, col))
                : std::string();
  }
  // SQLite wants the pointer fetched before the size.
  std::pair<const void*, size_t> Blob(int col) const {
    const void* data = sqlite3_column_blob(stmt_, col);
    return {data, static_cast<size_t>(sqlite3_column_bytes(stmt_, col))};
  }

 private:
  void Check(int rc, const char* what) {
    if (rc != SQLITE_OK) Fail(what);
  }
  [[noreturn]] void Fail(const char* what) const {
    throw ErrorAt(path_.string(), ": SQLite ", what,
                  " failed: ", sqlite3_errmsg(db_), " (in \"", sql_, "\")");
  }

  sqlite3* db_;
  const fs::path& path_;
  std::string sql_;
  sqlite3_stmt* stmt_ = nullptr;
};

// BEGIN IMMEDIATE ... COMMIT; rolls back unless Commit() succeeded, so a
// throw anywhere in between leaves the file as it was.
class Transaction {
 public:
  Transaction(sqlite3* db, const fs::path& path) : db_(db), path_(path) {
    Exec(db_, path_, "BEGIN IMMEDIATE");
  }
  Transaction(const Transaction&) = delete;
  Transaction& operator=(const Transaction&) = delete;
  ~Transaction() {
    if (!committed_) sqlite3_exec(db_, "ROLLBACK", nullptr, nullptr, nullptr);
  }
  void Commit() {
    Exec(db_, path_, "COMMIT");
    committed_ = true;
  }

 private:
  sqlite3* db_;
  const fs::path& path_;
  bool committed_ = false;
};

// "<file>: table <table>, <id_name> <id>" — the prefix of every blob error.
std::string RowContext(const fs::path& path, const char* table,
                       const char* id_name, int64_t id) {
  std::ostringstream context;
  context << path.string() << ": table " << table << ", " << id_name << " "
          << id;
  return context.str();
}

// Decodes a (rows, cols, data) triple at columns col..col+2.
template <typename Matrix>
Matrix ReadRowsColsBlob(const Statement& stmt, int col,
                        const std::string& context) {
  using Scalar = typename Matrix::Scalar;
  const int64_t rows = stmt.Int64(col);
  const int64_t cols = stmt.Int64(col + 1);
  const auto [data, num_bytes] = stmt.Blob(col + 2);
  constexpr int64_t kMaxBytes = std::numeric_limits<int>::max();
  if (rows < 0 || cols < 0 ||
      (rows > 0 && cols > kMaxBytes / rows / int64_t{sizeof(Scalar)})) {
    throw ErrorAt(context, ": impossible shape rows ", rows, " x cols ", cols);
  }
  const size_t expected = static_cast<size_t>(rows * cols) * sizeof(Scalar);
  if (num_bytes != expected) {
    throw ErrorAt(context, ": data has ", num_bytes, " bytes but rows ", rows,
                  " x cols ", cols, " x ", sizeof(Scalar), " = ", expected);
  }
  if (Matrix::ColsAtCompileTime != Eigen::Dynamic && rows > 0 &&
      cols != Matrix::ColsAtCompileTime) {
    throw ErrorAt(context, ": cols is ", cols, ", expected ",
                  int{Matrix::ColsAtCompileTime});
  }
  const int64_t matrix_cols = Matrix::ColsAtCompileTime == Eigen::Dynamic
                                  ? cols
                                  : int64_t{Matrix::ColsAtCompileTime};
  Matrix matrix(rows, matrix_cols);
  if (expected > 0) std::memcpy(matrix.data(), data, expected);
  return matrix;
}

// Decodes a fixed-size blob of doubles; NULL or empty reads as nullopt.
// `Stored` is the memory order COLMAP wrote (row-major for F, E, H).
template <typename Stored>
std::optional<Stored> ReadFixedBlob(const Statement& stmt, int col,
                                    const std::string& context,
                                    const char* column) {
  const auto [data, num_bytes] = stmt.Blob(col);
  if (num_bytes == 0) return std::nullopt;
  constexpr size_t kExpected = Stored::SizeAtCompileTime * sizeof(double);
  if (num_bytes != kExpected) {
    throw ErrorAt(context, ": column ", column, " has ", num_bytes,
                  " bytes, expected ", kExpected);
  }
  Stored value;
  std::memcpy(value.data(), data, kExpected);
  return value;
}

// Columns image_id, name, camera_id.
DatabaseImage ReadImageRow(const Statement& stmt) {
  DatabaseImage image;
  image.image_id = static_cast<uint32_t>(stmt.Int64(0));
  image.name = stmt.Text(1);
  image.camera_id = static_cast<uint32_t>(stmt.Int64(2));
  return image;
}

void CheckKeypointCols(const FeatureKeypointsBlob& keypoints,
                       const std::string& context) {
  const auto cols = keypoints.cols();
  if (keypoints.rows() > 0 && cols != 2 && cols != 4 && cols != 6) {
    throw ErrorAt(context, ": keypoints have ", cols,
                  " columns; COLMAP stores 2 (x, y), 4 (+ scale, orientation)"
                  " or 6 (+ affine shape)");
  }
}

// ---------------------------------------------------------------------------
// Schema detection.

using TableColumns = std::map<std::string, std::set<std::string>>;

struct TableSpec {
  const char* table;
  std::vector<const char*> columns;
};

// Tables every COLMAP >= 3.8 database has, with the columns we read.
const std::vector<TableSpec>& CoreTables() {
  static const std::vector<TableSpec> tables = {
      {"cameras",
       {"camera_id", "model", "width", "height", "params",
        "prior_focal_length"}},
      {"images", {"image_id", "name", "camera_id"}},
      {"keypoints", {"image_id", "rows", "cols", "data"}},
      {"descriptors", {"image_id", "rows", "cols", "data"}},
      {"matches", {"pair_id", "rows", "cols", "data"}},
      {"two_view_geometries",
       {"pair_id", "rows", "cols", "data", "config", "F", "E", "H", "qvec",
        "tvec"}},
  };
  return tables;
}

// Added by COLMAP 3.12.
const std::vector<TableSpec>& RigTables() {
  static const std::vector<TableSpec> tables = {
      {"rigs", {"rig_id", "ref_sensor_id", "ref_sensor_type"}},
      {"rig_sensors",
       {"rig_id", "sensor_id", "sensor_type", "sensor_from_rig"}},
      {"frames", {"frame_id", "rig_id"}},
      {"frame_data", {"frame_id", "data_id", "sensor_id", "sensor_type"}},
  };
  return tables;
}

TableColumns ReadTableColumns(sqlite3* db, const fs::path& path) {
  TableColumns tables;
  Statement list(db, path, "SELECT name FROM sqlite_master WHERE type='table'");
  while (list.Step()) tables[Lower(list.Text(0))];
  for (auto& [table, columns] : tables) {
    Statement info(db, path, "SELECT name FROM pragma_table_info(?1)");
    info.BindText(1, table);
    while (info.Step()) columns.insert(Lower(info.Text(0)));
  }
  return tables;
}

bool HasColumn(const TableColumns& tables, const char* table,
               const char* column) {
  const auto it = tables.find(table);
  return it != tables.end() && it->second.count(Lower(column)) > 0;
}

void RequireTables(const TableColumns& tables,
                   const std::vector<TableSpec>& specs, const fs::path& path,
                   const char* schema_name) {
  for (const TableSpec& spec : specs) {
    if (tables.count(spec.table) == 0) {
      throw ErrorAt(path.string(), ": not a COLMAP database we can read (",
                    schema_name, "): table '", spec.table, "' is missing");
    }
    for (const char* column : spec.columns) {
      if (!HasColumn(tables, spec.table, column)) {
        throw ErrorAt(path.string(), ": not a COLMAP database we can read (",
                      schema_name, "): table '", spec.table,
                      "' has no column '", column, "'");
      }
    }
  }
}

struct DetectedSchema {
  DatabaseSchema schema;
  bool has_rigs_and_frames;
};

DetectedSchema DetectSchema(sqlite3* db, const fs::path& path) {
  const TableColumns tables = ReadTableColumns(db, path);
  RequireTables(tables, CoreTables(), path, "COLMAP 3.8 or later");

  size_t num_rig_tables = 0;
  for (const TableSpec& spec : RigTables()) {
    num_rig_tables += tables.count(spec.table);
  }
  // A partial set is no COLMAP release's layout; naming the first missing
  // table is the most useful message.
  const bool has_rigs_and_frames = num_rig_tables > 0;
  if (has_rigs_and_frames) {
    RequireTables(tables, RigTables(), path, "COLMAP 3.12 or later");
  }

  if (tables.count("pose_priors") == 0) {
    RequireTables(tables,
                  {{"images",
                    {"prior_qw", "prior_qx", "prior_qy", "prior_qz", "prior_tx",
                     "prior_ty", "prior_tz"}}},
                  path, "COLMAP 3.8/3.9, no pose_priors table");
    return {DatabaseSchema::kColmap38, has_rigs_and_frames};
  }
  if (HasColumn(tables, "pose_priors", "pose_prior_id")) {
    const char* name = "COLMAP 4.x";
    RequireTables(
        tables,
        {{"pose_priors",
          {"corr_data_id", "corr_sensor_id", "corr_sensor_type", "position",
           "position_covariance", "gravity", "coordinate_system"}},
         {"descriptors", {"type"}}},
        path, name);
    RequireTables(tables, RigTables(), path, name);
    return {DatabaseSchema::kColmap4, true};
  }
  if (!HasColumn(tables, "pose_priors", "image_id")) {
    throw ErrorAt(path.string(),
                  ": not a COLMAP database we can read: table 'pose_priors' "
                  "has neither 'image_id' (COLMAP 3.10-3.13) nor "
                  "'pose_prior_id' (COLMAP 4.x)");
  }
  if (HasColumn(tables, "pose_priors", "position_covariance")) {
    RequireTables(tables, {{"pose_priors", {"position", "coordinate_system"}}},
                  path, "COLMAP 3.11-3.13");
    return {DatabaseSchema::kColmap311, has_rigs_and_frames};
  }
  RequireTables(tables, {{"pose_priors", {"position", "coordinate_system"}}},
                path, "COLMAP 3.10");
  return {DatabaseSchema::kColmap310, has_rigs_and_frames};
}

bool AnyNotNaN(const Eigen::Ref<const Eigen::MatrixXd>& values) {
  return !values.array().isNaN().all();
}

}  // namespace

std::string DatabaseSchemaName(DatabaseSchema schema) {
  switch (schema) {
    case DatabaseSchema::kColmap38:
      return "COLMAP 3.8/3.9";
    case DatabaseSchema::kColmap310:
      return "COLMAP 3.10";
    case DatabaseSchema::kColmap311:
      return "COLMAP 3.11-3.13";
    case DatabaseSchema::kColmap4:
      return "COLMAP 4.x";
  }
  return "unknown";
}

image_pair_t ImagePairToPairId(uint32_t image_id1, uint32_t image_id2) {
  if (image_id1 >= kMaxNumImages || image_id2 >= kMaxNumImages) {
    throw ErrorAt("image pair (", image_id1, ", ", image_id2,
                  "): COLMAP image ids must be below ", kMaxNumImages);
  }
  const uint64_t smaller = std::min(image_id1, image_id2);
  const uint64_t larger = std::max(image_id1, image_id2);
  return kMaxNumImages * smaller + larger;
}

std::pair<uint32_t, uint32_t> PairIdToImagePair(image_pair_t pair_id) {
  const uint64_t image_id2 = pair_id % kMaxNumImages;
  const uint64_t image_id1 = pair_id / kMaxNumImages;
  if (image_id1 > image_id2) {
    throw ErrorAt("pair id ", pair_id, " decodes to (", image_id1, ", ",
                  image_id2, "), which COLMAP never writes");
  }
  return {static_cast<uint32_t>(image_id1), static_cast<uint32_t>(image_id2)};
}

void Database::Closer::operator()(sqlite3* db) const { sqlite3_close_v2(db); }

Database::Database(fs::path path, Mode mode,
                   std::unique_ptr<sqlite3, Closer> db)
    : path_(std::move(path)), mode_(mode), db_(std::move(db)) {}

Database Database::Open(const fs::path& path, Mode mode) {
  std::error_code error;
  if (!fs::is_regular_file(path, error)) {
    throw ErrorAt(path.string(), ": no such database file");
  }
  // Without SQLITE_OPEN_CREATE a file deleted since the check above is an
  // error, not a new empty database.
  int flags =
      mode == Mode::kReadOnly ? SQLITE_OPEN_READONLY : SQLITE_OPEN_READWRITE;
  std::string name = path.string();
  // COLMAP keeps its database in WAL mode, where every reader must create a
  // -shm file beside it; in a folder we cannot write (a read-only archive)
  // that fails, so such a database is opened as immutable instead.
  const std::filesystem::path folder =
      path.has_parent_path() ? path.parent_path() : ".";
  if (mode == Mode::kReadOnly && ::access(folder.c_str(), W_OK) != 0) {
    name = "file:" + PercentEncodePath(std::filesystem::absolute(path)) +
           "?immutable=1";
    flags |= SQLITE_OPEN_URI;
  }
  sqlite3* raw = nullptr;
  const int rc = sqlite3_open_v2(name.c_str(), &raw, flags, nullptr);
  // SQLite hands out a handle even on failure; it must be closed too.
  std::unique_ptr<sqlite3, Closer> db(raw);
  if (rc != SQLITE_OK) {
    throw ErrorAt(path.string(), ": cannot open database: ",
                  raw ? sqlite3_errmsg(raw) : sqlite3_errstr(rc));
  }
  if (mode == Mode::kReadWrite) {
    // Per connection, not stored in the file; makes SQLite refuse rows that
    // reference a missing image or camera, as COLMAP's connections do.
    Exec(db.get(), path, "PRAGMA foreign_keys = ON");
  }
  const DetectedSchema detected = DetectSchema(db.get(), path);
  Database database(path, mode, std::move(db));
  database.schema_ = detected.schema;
  database.has_rigs_and_frames_ = detected.has_rigs_and_frames;
  return database;
}

void Database::RequireWritable(const char* what) const {
  if (mode_ != Mode::kReadWrite) {
    throw ErrorAt(path_.string(), ": cannot ", what,
                  ": database was opened read-only");
  }
}

bool Database::ImageExists(uint32_t image_id) const {
  Statement stmt(db_.get(), path_, "SELECT 1 FROM images WHERE image_id=?1");
  stmt.BindInt64(1, image_id);
  return stmt.Step();
}

std::vector<DatabaseCamera> Database::ReadAllCameras() const {
  Statement stmt(db_.get(), path_,
                 "SELECT camera_id, model, width, height, params, "
                 "prior_focal_length FROM cameras ORDER BY camera_id");
  std::vector<DatabaseCamera> cameras;
  while (stmt.Step()) {
    DatabaseCamera camera;
    camera.camera_id = static_cast<uint32_t>(stmt.Int64(0));
    camera.model_id = static_cast<int>(stmt.Int64(1));
    camera.width = static_cast<uint64_t>(stmt.Int64(2));
    camera.height = static_cast<uint64_t>(stmt.Int64(3));
    const auto [data, num_bytes] = stmt.Blob(4);
    if (num_bytes % sizeof(double) != 0) {
      throw ErrorAt(RowContext(path_, "cameras", "camera_id", camera.camera_id),
                    ": params has ", num_bytes, " bytes, not a multiple of 8");
    }
    camera.params.resize(num_bytes / sizeof(double));
    if (num_bytes > 0) std::memcpy(camera.params.data(), data, num_bytes);
    camera.prior_focal_length = stmt.Int64(5) != 0;
    cameras.push_back(std::move(camera));
  }
  return cameras;
}

std::vector<DatabaseImage> Database::ReadAllImages() const {
  Statement stmt(db_.get(), path_,
                 "SELECT image_id, name, camera_id FROM images "
                 "ORDER BY image_id");
  std::vector<DatabaseImage> images;
  while (stmt.Step()) images.push_back(ReadImageRow(stmt));
  return images;
}

std::optional<DatabaseImage> Database::ReadImageWithName(
    const std::string& name) const {
  Statement stmt(db_.get(), path_,
                 "SELECT image_id, name, camera_id FROM images WHERE name=?1");
  stmt.BindText(1, name);
  if (!stmt.Step()) return std::nullopt;
  return ReadImageRow(stmt);
}

FeatureKeypointsBlob Database::ReadKeypoints(uint32_t image_id) const {
  Statement stmt(db_.get(), path_,
                 "SELECT rows, cols, data FROM keypoints WHERE image_id=?1");
  stmt.BindInt64(1, image_id);
  if (!stmt.Step()) return FeatureKeypointsBlob();
  const std::string context =
      RowContext(path_, "keypoints", "image_id", image_id);
  FeatureKeypointsBlob keypoints =
      ReadRowsColsBlob<FeatureKeypointsBlob>(stmt, 0, context);
  CheckKeypointCols(keypoints, context);
  return keypoints;
}

DatabaseDescriptors Database::ReadDescriptors(uint32_t image_id) const {
  const bool has_type = schema_ == DatabaseSchema::kColmap4;
  Statement stmt(db_.get(), path_,
                 has_type ? "SELECT rows, cols, data, type FROM descriptors "
                            "WHERE image_id=?1"
                          : "SELECT rows, cols, data FROM descriptors "
                            "WHERE image_id=?1");
  stmt.BindInt64(1, image_id);
  DatabaseDescriptors descriptors;
  if (!stmt.Step()) return descriptors;
  descriptors.data = ReadRowsColsBlob<FeatureDescriptorsBlob>(
      stmt, 0, RowContext(path_, "descriptors", "image_id", image_id));
  if (has_type) {
    descriptors.type = static_cast<FeatureExtractorType>(stmt.Int64(3));
  }
  return descriptors;
}

std::vector<std::pair<image_pair_t, FeatureMatchesBlob>>
Database::ReadAllMatches() const {
  Statement stmt(db_.get(), path_,
                 "SELECT pair_id, rows, cols, data FROM matches "
                 "ORDER BY pair_id");
  std::vector<std::pair<image_pair_t, FeatureMatchesBlob>> all_matches;
  while (stmt.Step()) {
    const int64_t pair_id = stmt.Int64(0);
    all_matches.emplace_back(
        static_cast<image_pair_t>(pair_id),
        ReadRowsColsBlob<FeatureMatchesBlob>(
            stmt, 1, RowContext(path_, "matches", "pair_id", pair_id)));
  }
  return all_matches;
}

std::vector<std::pair<image_pair_t, TwoViewGeometry>>
Database::ReadTwoViewGeometries() const {
  using RowMajor3d = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;
  Statement stmt(db_.get(), path_,
                 "SELECT pair_id, rows, cols, data, config, F, E, H, qvec, "
                 "tvec FROM two_view_geometries ORDER BY pair_id");
  std::vector<std::pair<image_pair_t, TwoViewGeometry>> geometries;
  while (stmt.Step()) {
    const int64_t pair_id = stmt.Int64(0);
    const std::string context =
        RowContext(path_, "two_view_geometries", "pair_id", pair_id);
    TwoViewGeometry geometry;
    geometry.inlier_matches =
        ReadRowsColsBlob<FeatureMatchesBlob>(stmt, 1, context);
    geometry.config = static_cast<int>(stmt.Int64(4));
    const char* names[] = {"F", "E", "H"};
    std::optional<Eigen::Matrix3d>* targets[] = {&geometry.F, &geometry.E,
                                                 &geometry.H};
    for (int i = 0; i < 3; ++i) {
      if (const auto stored =
              ReadFixedBlob<RowMajor3d>(stmt, 5 + i, context, names[i])) {
        *targets[i] = Eigen::Matrix3d(*stored);
      }
    }
    const auto qvec = ReadFixedBlob<Eigen::Vector4d>(stmt, 8, context, "qvec");
    const auto tvec = ReadFixedBlob<Eigen::Vector3d>(stmt, 9, context, "tvec");
    if (qvec && tvec)
      geometry.cam2_from_cam1 = DatabaseRelativePose{*qvec, *tvec};
    geometries.emplace_back(static_cast<image_pair_t>(pair_id),
                            std::move(geometry));
  }
  return geometries;
}

std::vector<PosePrior> Database::ReadAllPosePriors() const {
  std::vector<PosePrior> priors;
  if (schema_ == DatabaseSchema::kColmap38) {
    Statement stmt(db_.get(), path_,
                   "SELECT image_id, prior_qw, prior_qx, prior_qy, prior_qz, "
                   "prior_tx, prior_ty, prior_tz FROM images "
                   "ORDER BY image_id");
    while (stmt.Step()) {
      bool any = false;
      double values[7];
      for (int i = 0; i < 7; ++i) {
        const bool is_null = stmt.IsNull(1 + i);
        any = any || !is_null;
        values[i] = is_null ? PosePrior::kNaN : stmt.Double(1 + i);
      }
      if (!any) continue;
      PosePrior prior;
      prior.image_id = static_cast<uint32_t>(stmt.Int64(0));
      const Eigen::Vector4d rotation(values[0], values[1], values[2],
                                     values[3]);
      if (AnyNotNaN(rotation)) prior.cam_from_world_rotation_wxyz = rotation;
      prior.position = Eigen::Vector3d(values[4], values[5], values[6]);
      priors.push_back(std::move(prior));
    }
    return priors;
  }

  const bool is_4x = schema_ == DatabaseSchema::kColmap4;
  const bool has_covariance = schema_ != DatabaseSchema::kColmap310;
  std::string sql;
  if (is_4x) {
    sql =
        "SELECT corr_data_id, coordinate_system, position, "
        "position_covariance, gravity FROM pose_priors WHERE "
        "corr_sensor_type=?1 ORDER BY corr_data_id, pose_prior_id";
  } else if (has_covariance) {
    sql =
        "SELECT image_id, coordinate_system, position, position_covariance "
        "FROM pose_priors ORDER BY image_id";
  } else {
    sql =
        "SELECT image_id, coordinate_system, position FROM pose_priors "
        "ORDER BY image_id";
  }
  Statement stmt(db_.get(), path_, sql);
  if (is_4x) stmt.BindInt64(1, kSensorTypeCamera);
  while (stmt.Step()) {
    PosePrior prior;
    const int64_t image_id = stmt.Int64(0);
    prior.image_id = static_cast<uint32_t>(image_id);
    const std::string context = RowContext(
        path_, "pose_priors", is_4x ? "corr_data_id" : "image_id", image_id);
    prior.coordinate_system =
        static_cast<PosePriorCoordinateSystem>(stmt.Int64(1));
    if (const auto position =
            ReadFixedBlob<Eigen::Vector3d>(stmt, 2, context, "position")) {
      prior.position = *position;
    }
    if (has_covariance) {
      if (const auto covariance = ReadFixedBlob<Eigen::Matrix3d>(
              stmt, 3, context, "position_covariance")) {
        prior.position_covariance = *covariance;
      }
    }
    if (is_4x) {
      if (const auto gravity =
              ReadFixedBlob<Eigen::Vector3d>(stmt, 4, context, "gravity")) {
        prior.gravity_in_cam = *gravity;
      }
    }
    priors.push_back(std::move(prior));
  }
  return priors;
}

uint32_t Database::WriteCamera(const DatabaseCamera& camera) {
  RequireWritable("write a camera");
  constexpr uint64_t kMaxInt64 = std::numeric_limits<int64_t>::max();
  if (camera.width > kMaxInt64 || camera.height > kMaxInt64) {
    throw ErrorAt(path_.string(), ": camera ", camera.camera_id,
                  ": width/height do not fit SQLite's INTEGER");
  }
  Statement stmt(db_.get(), path_,
                 "INSERT INTO cameras(camera_id, model, width, height, "
                 "params, prior_focal_length) VALUES(?1, ?2, ?3, ?4, ?5, ?6)");
  if (camera.camera_id == 0) {
    stmt.BindNull(1);
  } else {
    stmt.BindInt64(1, camera.camera_id);
  }
  stmt.BindInt64(2, camera.model_id);
  stmt.BindInt64(3, static_cast<int64_t>(camera.width));
  stmt.BindInt64(4, static_cast<int64_t>(camera.height));
  stmt.BindBlob(5, camera.params.data(), camera.params.size() * sizeof(double));
  stmt.BindInt64(6, camera.prior_focal_length ? 1 : 0);
  stmt.Step();
  return static_cast<uint32_t>(sqlite3_last_insert_rowid(db_.get()));
}

uint32_t Database::WriteImage(const DatabaseImage& image) {
  RequireWritable("write an image");
  Statement stmt(db_.get(), path_,
                 "INSERT INTO images(image_id, name, camera_id) "
                 "VALUES(?1, ?2, ?3)");
  if (image.image_id == 0) {
    stmt.BindNull(1);
  } else {
    stmt.BindInt64(1, image.image_id);
  }
  stmt.BindText(2, image.name);
  stmt.BindInt64(3, image.camera_id);
  stmt.Step();
  return static_cast<uint32_t>(sqlite3_last_insert_rowid(db_.get()));
}

void Database::WriteKeypoints(uint32_t image_id,
                              const FeatureKeypointsBlob& keypoints) {
  RequireWritable("write keypoints");
  CheckKeypointCols(keypoints,
                    RowContext(path_, "keypoints", "image_id", image_id));
  Statement stmt(db_.get(), path_,
                 "INSERT INTO keypoints(image_id, rows, cols, data) "
                 "VALUES(?1, ?2, ?3, ?4)");
  stmt.BindInt64(1, image_id);
  stmt.BindInt64(2, keypoints.rows());
  stmt.BindInt64(3, keypoints.cols());
  stmt.BindMatrix(4, keypoints);
  stmt.Step();
}

void Database::WriteDescriptors(uint32_t image_id,
                                const DatabaseDescriptors& descriptors) {
  RequireWritable("write descriptors");
  const bool has_type = schema_ == DatabaseSchema::kColmap4;
  if (!has_type && descriptors.type != FeatureExtractorType::kSift) {
    throw ErrorAt(RowContext(path_, "descriptors", "image_id", image_id),
                  ": a ", DatabaseSchemaName(schema_),
                  " database has no descriptor type column and holds SIFT "
                  "descriptors only");
  }
  Statement stmt(db_.get(), path_,
                 has_type ? "INSERT INTO descriptors(image_id, rows, cols, "
                            "data, type) VALUES(?1, ?2, ?3, ?4, ?5)"
                          : "INSERT INTO descriptors(image_id, rows, cols, "
                            "data) VALUES(?1, ?2, ?3, ?4)");
  stmt.BindInt64(1, image_id);
  stmt.BindInt64(2, descriptors.data.rows());
  stmt.BindInt64(3, descriptors.data.cols());
  stmt.BindMatrix(4, descriptors.data);
  if (has_type) stmt.BindInt64(5, static_cast<int64_t>(descriptors.type));
  stmt.Step();
}

void Database::WriteMatches(uint32_t image_id1, uint32_t image_id2,
                            const FeatureMatchesBlob& matches) {
  RequireWritable("write matches");
  const image_pair_t pair_id = ImagePairToPairId(image_id1, image_id2);
  if (image_id1 == image_id2 || !ImageExists(image_id1) ||
      !ImageExists(image_id2)) {
    throw ErrorAt(
        RowContext(path_, "matches", "pair_id", static_cast<int64_t>(pair_id)),
        ": cannot match image ", image_id1, " with image ", image_id2,
        " (same image or not in table images)");
  }
  // COLMAP stores the pair from the smaller to the larger id.
  FeatureMatchesBlob stored = matches;
  if (image_id1 > image_id2) stored.col(0).swap(stored.col(1));
  Statement stmt(db_.get(), path_,
                 "INSERT INTO matches(pair_id, rows, cols, data) "
                 "VALUES(?1, ?2, ?3, ?4)");
  stmt.BindInt64(1, static_cast<int64_t>(pair_id));
  stmt.BindInt64(2, stored.rows());
  stmt.BindInt64(3, stored.cols());
  stmt.BindMatrix(4, stored);
  stmt.Step();
}

PosePriorWriteSummary Database::WritePosePriors(
    const std::vector<PosePrior>& priors) {
  RequireWritable("write pose priors");
  std::set<uint32_t> image_ids;
  for (const PosePrior& prior : priors) {
    if (!image_ids.insert(prior.image_id).second) {
      throw ErrorAt(path_.string(), ": two pose priors for image_id ",
                    prior.image_id);
    }
  }

  // Each schema: an UPDATE of the existing representation and, where the
  // prior is a row of its own, an INSERT for images without one yet. Both
  // take the same parameters, bound by `bind`.
  std::string update_sql;
  std::string insert_sql;
  std::function<void(Statement&, const PosePrior&, int64_t camera_id)> bind;
  switch (schema_) {
    case DatabaseSchema::kColmap38:
      update_sql =
          "UPDATE images SET prior_qw=?2, prior_qx=?3, prior_qy=?4, "
          "prior_qz=?5, prior_tx=?6, prior_ty=?7, prior_tz=?8 "
          "WHERE image_id=?1";
      bind = [](Statement& stmt, const PosePrior& prior, int64_t) {
        const Eigen::Vector4d rotation =
            prior.cam_from_world_rotation_wxyz.value_or(
                Eigen::Vector4d::Constant(PosePrior::kNaN));
        stmt.BindInt64(1, prior.image_id);
        for (int i = 0; i < 4; ++i) stmt.BindDouble(2 + i, rotation(i));
        for (int i = 0; i < 3; ++i) stmt.BindDouble(6 + i, prior.position(i));
      };
      break;
    case DatabaseSchema::kColmap310:
      update_sql =
          "UPDATE pose_priors SET position=?2, coordinate_system=?3 "
          "WHERE image_id=?1";
      insert_sql =
          "INSERT INTO pose_priors(image_id, position, coordinate_system) "
          "VALUES(?1, ?2, ?3)";
      bind = [](Statement& stmt, const PosePrior& prior, int64_t) {
        stmt.BindInt64(1, prior.image_id);
        stmt.BindMatrix(2, prior.position);
        stmt.BindInt64(3, static_cast<int64_t>(prior.coordinate_system));
      };
      break;
    case DatabaseSchema::kColmap311:
      update_sql =
          "UPDATE pose_priors SET position=?2, coordinate_system=?3, "
          "position_covariance=?4 WHERE image_id=?1";
      insert_sql =
          "INSERT INTO pose_priors(image_id, position, coordinate_system, "
          "position_covariance) VALUES(?1, ?2, ?3, ?4)";
      bind = [](Statement& stmt, const PosePrior& prior, int64_t) {
        stmt.BindInt64(1, prior.image_id);
        stmt.BindMatrix(2, prior.position);
        stmt.BindInt64(3, static_cast<int64_t>(prior.coordinate_system));
        stmt.BindMatrix(4, prior.position_covariance);
      };
      break;
    case DatabaseSchema::kColmap4:
      // Keyed like COLMAP's own migration from 3.x: the image is the data
      // id of its camera sensor; an existing row keeps its pose_prior_id.
      update_sql =
          "UPDATE pose_priors SET corr_sensor_id=?2, position=?4, "
          "position_covariance=?5, gravity=?6, coordinate_system=?7 "
          "WHERE corr_data_id=?1 AND corr_sensor_type=?3";
      insert_sql =
          "INSERT INTO pose_priors(corr_data_id, corr_sensor_id, "
          "corr_sensor_type, position, position_covariance, gravity, "
          "coordinate_system) VALUES(?1, ?2, ?3, ?4, ?5, ?6, ?7)";
      bind = [](Statement& stmt, const PosePrior& prior, int64_t camera_id) {
        stmt.BindInt64(1, prior.image_id);
        stmt.BindInt64(2, camera_id);
        stmt.BindInt64(3, kSensorTypeCamera);
        stmt.BindMatrix(4, prior.position);
        stmt.BindMatrix(5, prior.position_covariance);
        stmt.BindMatrix(6, prior.gravity_in_cam);
        stmt.BindInt64(7, static_cast<int64_t>(prior.coordinate_system));
      };
      break;
  }

  const bool stores_covariance = schema_ == DatabaseSchema::kColmap311 ||
                                 schema_ == DatabaseSchema::kColmap4;
  PosePriorWriteSummary summary;
  Transaction transaction(db_.get(), path_);
  Statement camera_of_image(db_.get(), path_,
                            "SELECT camera_id FROM images WHERE image_id=?1");
  Statement update(db_.get(), path_, update_sql);
  std::optional<Statement> insert;
  if (!insert_sql.empty()) insert.emplace(db_.get(), path_, insert_sql);
  for (const PosePrior& prior : priors) {
    camera_of_image.Reset();
    camera_of_image.BindInt64(1, prior.image_id);
    if (!camera_of_image.Step()) {
      throw ErrorAt(path_.string(), ": pose prior for image_id ",
                    prior.image_id, ", which is not in table images");
    }
    const int64_t camera_id = camera_of_image.Int64(0);

    update.Reset();
    bind(update, prior, camera_id);
    update.Step();
    if (sqlite3_changes(db_.get()) == 0) {
      // Only pose_priors rows can be missing: the image row exists.
      insert->Reset();
      bind(*insert, prior, camera_id);
      insert->Step();
    }

    ++summary.num_written;
    if (!stores_covariance && AnyNotNaN(prior.position_covariance)) {
      ++summary.num_dropped_covariances;
    }
    if (schema_ != DatabaseSchema::kColmap4 &&
        AnyNotNaN(prior.gravity_in_cam)) {
      ++summary.num_dropped_gravities;
    }
    if (schema_ != DatabaseSchema::kColmap38 &&
        prior.cam_from_world_rotation_wxyz) {
      ++summary.num_dropped_rotations;
    }
    if (schema_ == DatabaseSchema::kColmap38 &&
        prior.coordinate_system != PosePriorCoordinateSystem::kUndefined) {
      ++summary.num_dropped_coordinate_systems;
    }
  }
  transaction.Commit();
  return summary;
}

}  // namespace uw
