#include "laserscale/model_matches.h"

#include <algorithm>
#include <set>

#include "common/util/error.h"

namespace uw {

DatabaseModelMatches::DatabaseModelMatches(const Database& database,
                                           const Reconstruction& model)
    : database_(database), model_(model) {
  std::unordered_map<std::string, const Image*> model_by_name;
  for (const Image& image : model.Images()) {
    model_by_name[image.name] = &image;
  }
  for (const DatabaseImage& image : database.ReadAllImages()) {
    database_ids_[image.name] = image.image_id;
    const auto found = model_by_name.find(image.name);
    if (found != model_by_name.end()) {
      model_images_[image.image_id] = found->second;
    }
  }
  if (model_images_.empty() && !model.Images().empty()) {
    throw ErrorAt(database.Path().string(), ": none of the model's ",
                  model.Images().size(),
                  " images is in this database (is it the model's?)");
  }
  for (const auto& [pair_id, geometry] : database.ReadTwoViewGeometries()) {
    const auto [id1, id2] = PairIdToImagePair(pair_id);
    for (int row = 0; row < geometry.inlier_matches.rows(); ++row) {
      const uint32_t keypoint1 = geometry.inlier_matches(row, 0);
      const uint32_t keypoint2 = geometry.inlier_matches(row, 1);
      verified_[id1].push_back({id2, keypoint2, keypoint1});
      verified_[id2].push_back({id1, keypoint1, keypoint2});
    }
  }
}

ImageModelMatches DatabaseModelMatches::For(
    const std::string& image_name) const {
  const auto found = database_ids_.find(image_name);
  if (found == database_ids_.end()) {
    throw ErrorAt(database_.Path().string(), ": no image named '", image_name,
                  "' (add it with colmap feature_extractor and match it)");
  }
  const uint32_t image_id = found->second;
  ImageModelMatches result;
  result.image_name = image_name;
  const std::optional<DatabaseImage> row =
      database_.ReadImageWithName(image_name);
  const Camera* model_camera = model_.FindCamera(row->camera_id);
  if (model_camera != nullptr) {
    result.camera = *model_camera;
    result.camera_from_model = true;
  } else {
    for (const DatabaseCamera& camera : database_.ReadAllCameras()) {
      if (camera.camera_id != row->camera_id) continue;
      result.camera.camera_id = camera.camera_id;
      result.camera.model_id = static_cast<CameraModelId>(camera.model_id);
      result.camera.width = camera.width;
      result.camera.height = camera.height;
      result.camera.params = camera.params;
    }
    CheckCameraModelParams(result.camera.model_id, result.camera.params.size());
  }
  const auto matches = verified_.find(image_id);
  if (matches == verified_.end()) return result;
  const FeatureKeypointsBlob keypoints = database_.ReadKeypoints(image_id);
  std::set<std::pair<uint32_t, point3D_t>> seen;
  std::set<uint32_t> matched_images;
  for (const auto& [other_id, other_keypoint, keypoint] : matches->second) {
    const auto other = model_images_.find(other_id);
    if (other == model_images_.end()) continue;
    const Image& model_image = *other->second;
    if (other_keypoint >= model_image.points2D.size()) {
      throw ErrorAt(database_.Path().string(), ": a match refers to keypoint ",
                    other_keypoint, " of image '", model_image.name,
                    "', which has ", model_image.points2D.size(),
                    " in the model: model and database disagree");
    }
    const Point2D& observation = model_image.points2D[other_keypoint];
    if (!observation.HasPoint3D()) continue;
    if (keypoint >= static_cast<uint32_t>(keypoints.rows())) {
      throw ErrorAt(database_.Path().string(), ": a match of image '",
                    image_name, "' refers to keypoint ", keypoint, " of ",
                    keypoints.rows());
    }
    if (!seen.insert({keypoint, observation.point3D_id}).second) continue;
    const Point3D* point = model_.FindPoint3D(observation.point3D_id);
    if (point == nullptr) continue;
    matched_images.insert(other_id);
    result.matches.push_back(
        {Eigen::Vector2d(keypoints(keypoint, 0), keypoints(keypoint, 1)),
         point->xyz, observation.point3D_id});
  }
  result.num_matched_model_images = matched_images.size();
  return result;
}

}  // namespace uw
