// Navigation priors into a COLMAP database (uwcolmap pose_prior_importer):
// reads nav.csv and optionally image_times.csv and rig.json, checks them
// against each other and against the database's images and cameras, and
// writes one pose prior per image in the database's own schema, all or
// nothing.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "colmap_plugins/nav/camera_mount.h"
#include "colmap_plugins/nav/camera_prior.h"
#include "colmap_plugins/nav/nav_csv.h"
#include "colmap_plugins/nav/nav_log.h"
#include "colmap_plugins/nav/rig_config.h"
#include "colmap_plugins/scene/database.h"

namespace uw {

struct PosePriorImportOptions {
  std::filesystem::path nav_path;
  std::filesystem::path image_times_path;  // empty: none
  std::filesystem::path rig_config_path;   // empty: none
  NavToCameraOptions nav_to_camera;
  // The log's format, a geographic log's origin, an NMEA log's date.
  NavLogOptions log;

  void Check() const;
};

// "World frame: ..." for a command's summary: the log's x,y,z, or a
// geographic log's local east-north-up at its origin (with the --origin
// that reuses an automatic one).
std::string WorldFrameText(const NavLogFrame& frame);

// world_frame.json (docs/formats.md), written beside a model fused with or
// aligned to the log: the frame its coordinates are in, in a form a GIS or
// a script reads (origin in WGS84 degrees and metres, axes, units), so
// that a model in local metres keeps its place on the Earth.
nlohmann::json WorldFrameJson(const NavLogFrame& frame);

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
  // Rows naming no image of the database (LoadedCameraPriors).
  std::vector<std::string> other_images;
  // Priors whose position covariance is singular (a zero sigma in the log,
  // as in uwsim's truth/nav.csv): COLMAP cannot weight them by it.
  size_t num_singular_covariances = 0;
  // What the log alone shows to be suspect (nav_plausibility.h).
  std::vector<std::string> warnings;
  // The frame the priors are in.
  NavLogFrame frame;
  PosePriorWriteSummary written;
};

// The database's PosePrior for `prior`: position and covariance in the
// cartesian (world) frame, and the cam_from_world rotation and gravity
// (world -z) in the camera frame when the log had the attitude for them.
PosePrior DatabasePosePrior(const CameraPrior& prior, uint32_t image_id);

// The navigation inputs of `options` read, checked against each other and
// against `images` (name, camera id; named `images_source` in messages),
// and turned into one prior per image of `images` that the inputs place
// (CameraPriorsFromNavigation). With a rig and without image_times, the
// images of `images` are placed by the rig's delays after the reference
// camera's rows (RigImageTimes).
// Every real survey has images the mapper did not register (15 of 25 on a
// BlueROV2 pass), and a log may name images that never reached the
// database: rows of image_times.csv (or of nav.csv without it) naming no
// image of `images` are left out before anything is placed, and named in
// `other_images`. Throws uw::Error naming the file and line when no row
// names any of them (a log of another survey, or names spelt otherwise),
// and for an image whose camera is not the rig camera of its prefix.
struct LoadedCameraPriors {
  std::vector<NavRecord> nav;
  NavLogFrame frame;
  RigConfig rig;  // no cameras: no rig
  std::vector<CameraPrior> priors;
  // The images of the rows left out, in file order.
  std::vector<std::string> other_images;
  // What the log alone shows to be suspect (nav_plausibility.h).
  std::vector<std::string> warnings;
};
LoadedCameraPriors LoadCameraPriors(
    const PosePriorImportOptions& options,
    const std::vector<std::pair<std::string, camera_t>>& images,
    const std::string& images_source);

// Reads every input and checks it before anything is written, then writes
// the priors in one transaction. Throws uw::Error naming the file and line
// (and the database unchanged) for anything LoadCameraPriors or
// Database::WritePosePriors refuse, and for rig cameras the database does
// not have. Rows naming images the database lacks are left out and counted.
PosePriorImportSummary ImportPosePriors(
    const std::filesystem::path& database_path,
    const PosePriorImportOptions& options);

}  // namespace uw
