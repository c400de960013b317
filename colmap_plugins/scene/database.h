// COLMAP's SQLite database (database.db) as written by COLMAP 3.8 up to 4.x.
//
// Format source: COLMAP's own source at the tags 3.8 (src/base/database.cc),
// 3.10, 3.11.0, 3.12.0 (src/colmap/scene/database.cc), 3.13.0, 4.0.0, 4.1.1
// and HEAD 5d968cf (src/colmap/scene/database_sqlite.cc).
//
// COLMAP upgrades a database in place every time it opens one (ALTER TABLE,
// new tables, rewritten sentinels). We never do: a file keeps the schema it
// came with, its layout is detected from sqlite_master and table_info (not
// from PRAGMA user_version, which 3.10-3.13 all set to 3900), and every write
// goes into the representation that schema already has. So a user can keep
// working on the database with the COLMAP version that made it.
//
// Blob layouts (all little-endian, as COLMAP memcpy's them on x86/ARM):
//  - keypoints: float32 rows x cols row-major (cols 2, 4 or 6);
//  - descriptors: uint8 rows x cols row-major (4.x: cols counts bytes, and
//    the `type` column says how to interpret them);
//  - matches and inlier matches: uint32 rows x 2 row-major, column 0 indexes
//    the keypoints of the image with the smaller id;
//  - two-view F, E, H: 9 float64 row-major; qvec (w, x, y, z); tvec;
//  - pose prior position: 3 float64; position_covariance: 9 float64 in
//    Eigen's column-major order (COLMAP writes Matrix3d::data() as is);
//    gravity: 3 float64.
#pragma once

#include <cstdint>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

struct sqlite3;

namespace uw {

// Which of COLMAP's database layouts a file has. One value covers every
// release that writes the same pose-prior representation.
enum class DatabaseSchema {
  kColmap38,   // 3.8, 3.9: priors are images.prior_qw..prior_tz columns.
  kColmap310,  // 3.10: pose_priors(image_id, position, coordinate_system).
  kColmap311,  // 3.11-3.13: pose_priors + position_covariance; rigs and
               // frames tables from 3.12 on (Database::HasRigsAndFrames).
  kColmap4,    // 4.x: pose_priors keyed by pose_prior_id with corr_data_id,
               // corr_sensor_id, corr_sensor_type, gravity; descriptors.type.
};
std::string DatabaseSchemaName(DatabaseSchema schema);

// COLMAP's pair id: kMaxNumImages * min(id1, id2) + max(id1, id2). Image ids
// must be below kMaxNumImages (the images table enforces it with a CHECK).
using image_pair_t = uint64_t;
constexpr uint64_t kMaxNumImages =
    static_cast<uint64_t>(std::numeric_limits<int32_t>::max());
// Throws uw::Error if an id is >= kMaxNumImages.
image_pair_t ImagePairToPairId(uint32_t image_id1, uint32_t image_id2);
// Returns (smaller id, larger id); throws uw::Error on an impossible pair id.
std::pair<uint32_t, uint32_t> PairIdToImagePair(image_pair_t pair_id);

using FeatureKeypointsBlob =
    Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
using FeatureDescriptorsBlob =
    Eigen::Matrix<uint8_t, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
using FeatureMatchesBlob =
    Eigen::Matrix<uint32_t, Eigen::Dynamic, 2, Eigen::RowMajor>;

struct DatabaseCamera {
  uint32_t camera_id = 0;  // 0 on write: let SQLite assign the next id.
  int model_id = -1;       // COLMAP's CameraModelId.
  uint64_t width = 0;
  uint64_t height = 0;
  std::vector<double> params;
  bool prior_focal_length = false;
};

struct DatabaseImage {
  uint32_t image_id = 0;  // 0 on write: let SQLite assign the next id.
  std::string name;
  uint32_t camera_id = 0;
};

// COLMAP 4.x's FeatureExtractorType, stored in descriptors.type. Databases
// without that column hold SIFT descriptors only.
enum class FeatureExtractorType : int {
  kUndefined = -1,
  kSift = 0,
  kAlikedN16Rot = 1,
  kAlikedN32 = 2,
};

struct DatabaseDescriptors {
  FeatureExtractorType type = FeatureExtractorType::kSift;
  FeatureDescriptorsBlob data;
};

// A rigid transform cam2_from_cam1 as two_view_geometries stores it:
// x_cam2 = R(rotation_wxyz) * x_cam1 + translation.
struct DatabaseRelativePose {
  Eigen::Vector4d rotation_wxyz = Eigen::Vector4d(1, 0, 0, 0);
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
};

// One two_view_geometries row, oriented from the smaller to the larger image
// id of its pair. A NULL or empty blob reads as std::nullopt. Sentinels are
// returned as stored: COLMAP <= 3.13 wrote identity/zero poses and zero
// matrices for "not estimated", which 4.x rewrites to NULL on open.
struct TwoViewGeometry {
  // COLMAP's TwoViewGeometry::ConfigurationType (0 undefined, 1 degenerate,
  // 2 calibrated, 3 uncalibrated, 4 planar, 5 panoramic, 6 planar or
  // panoramic, 7 watermark, 8 multiple).
  int config = 0;
  FeatureMatchesBlob inlier_matches;
  std::optional<Eigen::Matrix3d> F;
  std::optional<Eigen::Matrix3d> E;
  std::optional<Eigen::Matrix3d> H;
  std::optional<DatabaseRelativePose> cam2_from_cam1;
};

enum class PosePriorCoordinateSystem : int {
  kUndefined = -1,
  kWGS84 = 0,  // position = (latitude deg, longitude deg, altitude m)
  kCartesian = 1,
};

// The prior of one image, whatever the schema stores it as. Absent values
// are NaN (or std::nullopt), as in COLMAP's PosePrior.
struct PosePrior {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

  uint32_t image_id = 0;
  // Camera centre in the world frame named by coordinate_system (3.8 stored
  // it in prior_tx/ty/tz, which spatial_matcher reads as a location; those
  // REAL columns give back -0.0 as +0.0).
  Eigen::Vector3d position = Eigen::Vector3d::Constant(kNaN);
  // Covariance of `position` (3.11 and later only).
  Eigen::Matrix3d position_covariance = Eigen::Matrix3d::Constant(kNaN);
  // 3.10 and later only; 3.8 databases read as kUndefined.
  PosePriorCoordinateSystem coordinate_system =
      PosePriorCoordinateSystem::kUndefined;
  // Direction of gravity ("down") in the camera frame (4.x only).
  Eigen::Vector3d gravity_in_cam = Eigen::Vector3d::Constant(kNaN);
  // Rotation prior (w, x, y, z) of cam_from_world (3.8 prior_qw..qz only).
  std::optional<Eigen::Vector4d> cam_from_world_rotation_wxyz;

  bool HasPosition() const { return position.allFinite(); }
  bool HasPositionCovariance() const { return position_covariance.allFinite(); }
  bool HasGravity() const { return gravity_in_cam.allFinite(); }
};

// What WritePosePriors could not store because the schema has no place for
// it. A CLI should report non-zero counts; the values are not written.
struct PosePriorWriteSummary {
  size_t num_written = 0;
  size_t num_dropped_covariances = 0;         // 3.8, 3.10
  size_t num_dropped_coordinate_systems = 0;  // 3.8 (kUndefined not counted)
  size_t num_dropped_gravities = 0;           // before 4.x
  size_t num_dropped_rotations = 0;           // after 3.8
};

class Database {
 public:
  enum class Mode { kReadOnly, kReadWrite };

  // Opens an existing database and detects its schema. Never creates a file.
  // Throws uw::Error naming the file if it is missing, not an SQLite
  // database, or lacks a table or column its schema requires.
  static Database Open(const std::filesystem::path& path, Mode mode);

  Database(Database&&) noexcept = default;
  Database& operator=(Database&&) noexcept = default;

  const std::filesystem::path& Path() const { return path_; }
  DatabaseSchema Schema() const { return schema_; }
  // The rigs, rig_sensors, frames and frame_data tables exist (COLMAP 3.12+).
  bool HasRigsAndFrames() const { return has_rigs_and_frames_; }

  // All Read* functions return rows ordered by id. Blob sizes are checked
  // against rows * cols; a mismatch throws uw::Error naming the table and id.
  std::vector<DatabaseCamera> ReadAllCameras() const;
  std::vector<DatabaseImage> ReadAllImages() const;
  std::optional<DatabaseImage> ReadImageWithName(const std::string& name) const;
  // Empty (0 x 0) when the image has no row.
  FeatureKeypointsBlob ReadKeypoints(uint32_t image_id) const;
  DatabaseDescriptors ReadDescriptors(uint32_t image_id) const;
  std::vector<std::pair<image_pair_t, FeatureMatchesBlob>> ReadAllMatches()
      const;
  std::vector<std::pair<image_pair_t, TwoViewGeometry>> ReadTwoViewGeometries()
      const;
  // One entry per image with a prior. 3.8: images with any non-NULL prior_*
  // column. 4.x: camera priors only (corr_sensor_type CAMERA); COLMAP has no
  // other kind of image prior. A NULL blob reads as NaN. A database that
  // COLMAP 3.10+ opened still has the 3.8 prior_* columns; like COLMAP we
  // then read only pose_priors.
  std::vector<PosePrior> ReadAllPosePriors() const;

  // Writers for single rows. They insert (never replace) and throw uw::Error
  // if the row exists or a referenced row does not. They touch only their own
  // table: on 3.12+ schemas an image written here has no frame, as with
  // COLMAP's own Database::WriteImage.
  uint32_t WriteCamera(const DatabaseCamera& camera);
  uint32_t WriteImage(const DatabaseImage& image);
  void WriteKeypoints(uint32_t image_id, const FeatureKeypointsBlob& keypoints);
  // Before 4.x only SIFT descriptors can be stored (no type column).
  void WriteDescriptors(uint32_t image_id,
                        const DatabaseDescriptors& descriptors);
  // `matches` column 0 indexes image_id1's keypoints; stored swapped when
  // image_id1 > image_id2, as COLMAP does.
  void WriteMatches(uint32_t image_id1, uint32_t image_id2,
                    const FeatureMatchesBlob& matches);

  // Inserts or replaces the prior of each prior.image_id, in the
  // representation of the detected schema, all in one transaction: on any
  // error (unknown image, duplicate image id in `priors`, SQLite failure)
  // nothing is written and uw::Error is thrown.
  //  - 3.8: UPDATE images SET prior_qw..qz (cam_from_world_rotation_wxyz,
  //    NULL when absent) and prior_tx..tz (position).
  //  - 3.10: position and coordinate_system.
  //  - 3.11: position, coordinate_system and position_covariance.
  //  - 4.x: the row with corr_data_id = image id and corr_sensor_type CAMERA
  //    (its pose_prior_id is kept), corr_sensor_id = the image's camera id,
  //    position, position_covariance, coordinate_system, gravity.
  // Absent values are written as NaN blobs, never NULL, because COLMAP reads
  // a NULL blob as zeros (a zero covariance or gravity would be used).
  // Values the schema cannot hold are dropped and counted in the summary.
  PosePriorWriteSummary WritePosePriors(const std::vector<PosePrior>& priors);

 private:
  struct Closer {
    void operator()(sqlite3* db) const;
  };

  Database(std::filesystem::path path, Mode mode,
           std::unique_ptr<sqlite3, Closer> db);
  void RequireWritable(const char* what) const;
  bool ImageExists(uint32_t image_id) const;

  std::filesystem::path path_;
  Mode mode_ = Mode::kReadOnly;
  std::unique_ptr<sqlite3, Closer> db_;
  DatabaseSchema schema_ = DatabaseSchema::kColmap38;
  bool has_rigs_and_frames_ = false;
};

}  // namespace uw
