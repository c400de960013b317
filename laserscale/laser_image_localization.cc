#include "laserscale/laser_image_localization.h"

#include <fstream>
#include <set>
#include <utility>

#include "common/util/error.h"

namespace uw {

std::vector<std::string> ReadLaserImageList(const std::string& path) {
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

std::vector<std::string> UnregisteredImageNames(
    const Database& database, const Reconstruction& model,
    const std::string& database_path) {
  std::set<std::string> registered;
  for (const Image& image : model.Images()) registered.insert(image.name);
  std::vector<std::string> names;
  for (const DatabaseImage& image : database.ReadAllImages()) {
    if (!registered.count(image.name)) names.push_back(image.name);
  }
  if (names.empty()) {
    throw ErrorAt(database_path,
                  ": every image is registered in the model; give "
                  "--image_list_path");
  }
  return names;
}

std::vector<LocalizedImage> LocalizeLaserImages(
    const DatabaseModelMatches& matcher, const std::vector<std::string>& names,
    const LocalizationOptions& options, const LocalizedImageCallback& done) {
  options.Check();
  std::vector<LocalizedImage> results;
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
      result.cam_from_world = localization.cam_from_world;
      result.rms_error_px = localization.rms_error_px;
      for (const int k : localization.inliers) {
        result.inliers.push_back(matches.matches[k]);
      }
    }
    if (done) done(i, names.size(), result, matches.camera_from_model);
    results.push_back(std::move(result));
  }
  return results;
}

}  // namespace uw
