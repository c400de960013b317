#include "colmap_plugins/exe/database_commands.h"

#include <cstdio>

#include "colmap_plugins/scene/database.h"
#include "common/cli/command.h"

namespace uw {

int RunDatabaseAnalyzer(int argc, char** argv) {
  CLI::App app(
      "Prints the schema of a COLMAP database (3.8 to 4.x, detected from its "
      "tables) and what it holds. Opens the file read-only; never changes "
      "it.\n\n"
      "Example:\n"
      "  uwcolmap database_analyzer --database_path database.db",
      "uwcolmap database_analyzer");
  std::string database_path;
  app.add_option("--database_path", database_path, "COLMAP database")
      ->required();
  return RunCommand(app, argc, argv, [&] {
    const Database database =
        Database::Open(database_path, Database::Mode::kReadOnly);
    const std::vector<DatabaseImage> images = database.ReadAllImages();
    size_t num_keypoints = 0;
    size_t num_images_with_keypoints = 0;
    for (const DatabaseImage& image : images) {
      const auto rows = database.ReadKeypoints(image.image_id).rows();
      num_keypoints += rows;
      num_images_with_keypoints += rows > 0 ? 1 : 0;
    }
    size_t num_matched_pairs = 0;
    for (const auto& [pair_id, matches] : database.ReadAllMatches()) {
      num_matched_pairs += matches.rows() > 0 ? 1 : 0;
    }
    size_t num_verified_pairs = 0;
    size_t num_inlier_matches = 0;
    for (const auto& [pair_id, geometry] : database.ReadTwoViewGeometries()) {
      num_verified_pairs += geometry.inlier_matches.rows() > 0 ? 1 : 0;
      num_inlier_matches += geometry.inlier_matches.rows();
    }
    size_t num_priors_with_covariance = 0;
    const std::vector<PosePrior> priors = database.ReadAllPosePriors();
    for (const PosePrior& prior : priors) {
      num_priors_with_covariance += prior.HasPositionCovariance() ? 1 : 0;
    }
    std::printf(
        "Schema: %s%s\n"
        "Cameras: %zu\n"
        "Images: %zu\n"
        "Images with keypoints: %zu\n"
        "Keypoints: %zu\n"
        "Matched pairs: %zu\n"
        "Verified pairs: %zu\n"
        "Inlier matches: %zu\n"
        "Pose priors: %zu (%zu with position covariance)\n",
        DatabaseSchemaName(database.Schema()).c_str(),
        database.HasRigsAndFrames() ? ", with rigs and frames" : "",
        database.ReadAllCameras().size(), images.size(),
        num_images_with_keypoints, num_keypoints, num_matched_pairs,
        num_verified_pairs, num_inlier_matches, priors.size(),
        num_priors_with_covariance);
  });
}

}  // namespace uw
