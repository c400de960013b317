#include <cstdio>
#include <fstream>
#include <set>

#include "colmap_plugins/scene/database.h"
#include "colmap_plugins/scene/model_io.h"
#include "common/cli/command.h"
#include "common/util/error.h"
#include "common/util/file.h"
#include "laserscale/exe/commands.h"
#include "laserscale/laser_poses_io.h"
#include "laserscale/model_matches.h"

namespace uw {
namespace {

std::vector<std::string> ReadImageList(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw ErrorAt(path, ": cannot open the image list");
  std::vector<std::string> names;
  std::string line;
  while (std::getline(in, line)) {
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) {
      line.pop_back();
    }
    if (!line.empty()) names.push_back(line);
  }
  if (names.empty()) throw ErrorAt(path, ": the image list is empty");
  return names;
}

}  // namespace

int RunLocalize(int argc, char** argv) {
  CLI::App app(
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
      "laserscale localize");
  std::string database_path;
  std::string input_path;
  std::string image_list_path;
  std::string out;
  LocalizationOptions options;
  app.add_option("--database_path", database_path, "COLMAP database")
      ->required();
  app.add_option("--input_path", input_path, "COLMAP model (.bin or .txt)")
      ->required();
  app.add_option("--image_list_path", image_list_path,
                 "Images to localize, one name per line (default: every "
                 "database image the model has not registered)");
  app.add_option("--out", out, "poses.json to write")->required();
  app.add_option("--max_error_px", options.max_error_px,
                 "Inlier threshold (px)")
      ->capture_default_str();
  app.add_option("--min_num_inliers", options.min_num_inliers,
                 "Fewer inliers is a failed localization")
      ->capture_default_str();
  app.add_option("--seed", options.seed, "Seed of the robust PnP")
      ->capture_default_str();
  return RunCommand(app, argc, argv, [&] {
    options.Check();
    const Reconstruction model = ReadModel(input_path);
    const Database database =
        Database::Open(database_path, Database::Mode::kReadOnly);
    std::vector<std::string> names;
    if (!image_list_path.empty()) {
      names = ReadImageList(image_list_path);
    } else {
      std::set<std::string> registered;
      for (const Image& image : model.Images()) registered.insert(image.name);
      for (const DatabaseImage& image : database.ReadAllImages()) {
        if (!registered.count(image.name)) names.push_back(image.name);
      }
      if (names.empty()) {
        throw ErrorAt(database_path,
                      ": every image is registered in the model; give "
                      "--image_list_path");
      }
    }
    const DatabaseModelMatches matcher(database, model);
    std::vector<LocalizedImage> results;
    size_t num_localized = 0;
    for (size_t i = 0; i < names.size(); ++i) {
      const ImageModelMatches matches = matcher.For(names[i]);
      const Localization localization =
          LocalizeImage(matches.camera, matches.matches, options);
      LocalizedImage result;
      result.name = names[i];
      result.camera = matches.camera;
      result.success = localization.success;
      result.problem = localization.problem;
      result.num_matches = matches.matches.size();
      result.num_matched_model_images = matches.num_matched_model_images;
      if (localization.success) {
        ++num_localized;
        result.cam_from_world = localization.cam_from_world;
        result.rms_error_px = localization.rms_error_px;
        for (const int k : localization.inliers) {
          result.inliers.push_back(matches.matches[k]);
        }
        std::printf(
            "[localize %zu/%zu] %s: %zu inliers of %zu matches with %zu "
            "model images, RMS %.3f px%s\n",
            i + 1, names.size(), names[i].c_str(), result.inliers.size(),
            result.num_matches, result.num_matched_model_images,
            result.rms_error_px,
            matches.camera_from_model ? "" : " (database camera)");
      } else {
        std::printf("[localize %zu/%zu] %s: FAILED: %s\n", i + 1, names.size(),
                    names[i].c_str(), result.problem.c_str());
      }
      std::fflush(stdout);
      results.push_back(std::move(result));
    }
    WriteFilesAtomically({{out,
                           [&](std::ostream& stream) {
                             stream << LaserPosesJsonText(results);
                           }}},
                         false);
    std::printf("[localize] %zu of %zu images localized; wrote %s\n",
                num_localized, names.size(), out.c_str());
  });
}

}  // namespace uw
