#include "laserscale/exe/localize_command.h"

#include <fmt/format.h>

#include "colmap_plugins/scene/model_io.h"
#include "common/util/file.h"
#include "laserscale/laser_image_localization.h"

namespace uw {
namespace {

void AddLocalizeFlags(CommandLine* cli, LocalizeOptions* options) {
  cli->Add("--database_path", &options->database_path, "COLMAP database")
      ->required();
  cli->Add("--input_path", &options->input_path, "COLMAP model (.bin or .txt)")
      ->required();
  cli->Add("--image_list_path", &options->image_list_path,
           "Images to localize, one name per line (default: every "
           "database image the model has not registered)");
  cli->Add("--out", &options->out, "poses.json to write")->required();
  LocalizationOptions& localization = options->localization;
  cli->Add("--max_error_px", &localization.max_error_px,
           "Inlier threshold (px)");
  cli->Add("--min_num_inliers", &localization.min_num_inliers,
           "Fewer inliers is a failed localization");
  cli->Add("--seed", &localization.seed, "Seed of the robust PnP");
}

void RunLocalize(const LocalizeOptions& options) {
  const Reconstruction model = ReadModel(options.input_path);
  const Database database =
      Database::Open(options.database_path, Database::Mode::kReadOnly);
  const std::vector<std::string> names =
      options.image_list_path.empty()
          ? UnregisteredImageNames(database, model, options.database_path)
          : ReadLaserImageList(options.image_list_path);
  const DatabaseModelMatches matcher(database, model);
  size_t num_localized = 0;
  const std::vector<LocalizedImage> results = LocalizeLaserImages(
      matcher, names, options.localization,
      [&](size_t i, size_t count, const LocalizedImage& result,
          bool camera_from_model) {
        if (result.success) {
          ++num_localized;
          fmt::print(
              "[localize {}/{}] {}: {} inliers of {} matches with {} "
              "model images, RMS {:.3f} px{}\n",
              i + 1, count, result.name.c_str(), result.inliers.size(),
              result.num_matches, result.num_matched_model_images,
              result.rms_error_px,
              camera_from_model ? "" : " (database camera)");
        } else {
          fmt::print("[localize {}/{}] {}: FAILED: {}\n", i + 1, count,
                     result.name.c_str(), result.problem.c_str());
        }
        std::fflush(stdout);
      });
  WriteFilesAtomically(
      {{options.out,
        [&](std::ostream& stream) { stream << LaserPosesJsonText(results); }}},
      false);
  fmt::print("[localize] {} of {} images localized; wrote {}\n", num_localized,
             names.size(), options.out.c_str());
}

}  // namespace

Subcommand LocalizeCommand() {
  return MakeSubcommand<LocalizeOptions>(
      "localize",
      "localize laser images against a COLMAP model and its database",
      "Localizes laser images against a COLMAP model: the image's verified "
      "matches in the model's database give 2D-3D correspondences, a robust "
      "PnP (USAC, MAGSAC++) the pose and inliers, a refinement with the 3D "
      "points fixed the final pose and its RMS reprojection error, the "
      "feature noise that `estimate` re-samples. Add the laser images to the "
      "database first (colmap feature_extractor with "
      "--ImageReader.existing_camera_id, then a matcher).\n\n"
      "Example:\n"
      "  laserscale localize --database_path database.db --input_path "
      "sparse/0 --image_list_path laser_list.txt --out poses.json",
      AddLocalizeFlags, RunLocalize);
}

}  // namespace uw
