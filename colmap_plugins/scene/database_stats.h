// What a COLMAP database holds, counted as `uwcolmap database_analyzer`
// prints it (the same counts the sqlite3 shell gives).
#pragma once

#include <cstddef>
#include <string>

#include "colmap_plugins/scene/database.h"

namespace uw {

struct DatabaseStats {
  DatabaseSchema schema = DatabaseSchema::kColmap38;
  bool has_rigs_and_frames = false;
  size_t num_cameras = 0;
  size_t num_images = 0;
  size_t num_images_with_keypoints = 0;
  size_t num_keypoints = 0;
  size_t num_matched_pairs = 0;   // pairs with at least one match
  size_t num_verified_pairs = 0;  // pairs with at least one inlier match
  size_t num_inlier_matches = 0;
  size_t num_pose_priors = 0;
  size_t num_pose_priors_with_covariance = 0;
};

DatabaseStats ComputeDatabaseStats(const Database& database);

// One "Name: value" line per figure.
std::string FormatDatabaseAnalyzerReport(const DatabaseStats& stats);

}  // namespace uw
