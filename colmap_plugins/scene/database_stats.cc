#include "colmap_plugins/scene/database_stats.h"

#include <fmt/format.h>

namespace uw {

DatabaseStats ComputeDatabaseStats(const Database& database) {
  DatabaseStats stats;
  stats.schema = database.Schema();
  stats.has_rigs_and_frames = database.HasRigsAndFrames();
  stats.num_cameras = database.ReadAllCameras().size();
  const std::vector<DatabaseImage> images = database.ReadAllImages();
  stats.num_images = images.size();
  for (const DatabaseImage& image : images) {
    const auto rows = database.ReadKeypoints(image.image_id).rows();
    stats.num_keypoints += rows;
    stats.num_images_with_keypoints += rows > 0 ? 1 : 0;
  }
  for (const auto& [pair_id, matches] : database.ReadAllMatches()) {
    stats.num_matched_pairs += matches.rows() > 0 ? 1 : 0;
  }
  for (const auto& [pair_id, geometry] : database.ReadTwoViewGeometries()) {
    stats.num_verified_pairs += geometry.inlier_matches.rows() > 0 ? 1 : 0;
    stats.num_inlier_matches += geometry.inlier_matches.rows();
  }
  const std::vector<PosePrior> priors = database.ReadAllPosePriors();
  stats.num_pose_priors = priors.size();
  for (const PosePrior& prior : priors) {
    stats.num_pose_priors_with_covariance +=
        prior.HasPositionCovariance() ? 1 : 0;
  }
  return stats;
}

std::string FormatDatabaseAnalyzerReport(const DatabaseStats& stats) {
  return fmt::format(
      "Schema: {}{}\n"
      "Cameras: {}\n"
      "Images: {}\n"
      "Images with keypoints: {}\n"
      "Keypoints: {}\n"
      "Matched pairs: {}\n"
      "Verified pairs: {}\n"
      "Inlier matches: {}\n"
      "Pose priors: {} ({} with position covariance)\n",
      DatabaseSchemaName(stats.schema),
      stats.has_rigs_and_frames ? ", with rigs and frames" : "",
      stats.num_cameras, stats.num_images, stats.num_images_with_keypoints,
      stats.num_keypoints, stats.num_matched_pairs, stats.num_verified_pairs,
      stats.num_inlier_matches, stats.num_pose_priors,
      stats.num_pose_priors_with_covariance);
}

}  // namespace uw
