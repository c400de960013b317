// Navigation priors into a COLMAP database (uwcolmap pose_prior_importer):
// reads nav.csv and optionally image_times.csv and rig.json, checks them
// against each other and against the database's images and cameras, and
// writes one pose prior per image in the database's own schema, all or
// nothing.
#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "colmap_plugins/nav/camera_mount.h"
#include "colmap_plugins/nav/camera_prior.h"
#include "colmap_plugins/nav/nav_csv.h"
#include "colmap_plugins/nav/rig_config.h"
#include "colmap_plugins/scene/database.h"

namespace uw {

struct PosePriorImportOptions {
  std::filesystem::path nav_path;
  std::filesystem::path image_times_path;  // empty: none
  std::filesystem::path rig_config_path;   // empty: none
  NavToCameraOptions nav_to_camera;

  void Check() const;
};

struct PosePriorImportSummary {
  DatabaseSchema schema = DatabaseSchema::kColmap38;
  size_t num_database_images = 0;
  size_t num_nav_rows = 0;
  size_t num_dives = 0;
  size_t num_rig_cameras = 0;  // 0: no rig
  size_t num_priors = 0;       // = exact + interpolated + extrapolated
  size_t num_exact = 0;
  size_t num_interpolated = 0;
  size_t num_extrapolated = 0;
  // Images of the database that got no prior (no row, no time, no rig
  // camera): they keep whatever prior they had.
  size_t num_images_without_priors = 0;
  // Priors whose position covariance is singular (a zero sigma in the log,
  // as in uwsim's truth/nav.csv): COLMAP cannot weight them by it.
  size_t num_singular_covariances = 0;
  PosePriorWriteSummary written;
};

// The database's PosePrior for `prior`: position and covariance in the
// cartesian (world) frame, cam_from_world rotation, and gravity (world -z)
// in the camera frame.
PosePrior DatabasePosePrior(const CameraPrior& prior, uint32_t image_id);

// Which images the navigation may name.
enum class ImagesNamedByNavigation {
  // Only the given images (pose_prior_importer, bundle_adjuster): a row of
  // nav.csv (without image_times) or of image_times.csv naming another
  // image is an error, and so is an image whose camera is not the rig
  // camera of its prefix.
  kOnlyGiven,
  // Any (model_aligner): a reconstruction rarely registers every image, so
  // rows of other images are priors too, for the caller to leave out.
  kAny,
};

// The navigation inputs of `options` read, checked against each other and,
// as `named` says, against `images` (name, camera id; named
// `images_source` in messages), and turned into one prior per image
// (CameraPriorsFromNavigation). With a rig and without image_times, the
// images of `images` are placed by the rig's delays after the reference
// camera's rows (RigImageTimes). Throws uw::Error naming the file and line.
struct LoadedCameraPriors {
  std::vector<NavRecord> nav;
  RigConfig rig;  // no cameras: no rig
  std::vector<CameraPrior> priors;
};
LoadedCameraPriors LoadCameraPriors(
    const PosePriorImportOptions& options,
    const std::vector<std::pair<std::string, camera_t>>& images,
    const std::string& images_source,
    ImagesNamedByNavigation named = ImagesNamedByNavigation::kOnlyGiven);

// Reads every input and checks it before anything is written, then writes
// the priors in one transaction. Throws uw::Error naming the file and line
// (and the database unchanged) for anything Read*, CameraPriorsFromNavigation
// or Database::WritePosePriors refuse, and for navigation rows (without
// image_times) or image_times rows that name no image of the database, rig
// cameras the database does not have, and images whose database camera is
// not the rig camera of their prefix.
PosePriorImportSummary ImportPosePriors(
    const std::filesystem::path& database_path,
    const PosePriorImportOptions& options);

}  // namespace uw
