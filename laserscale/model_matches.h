// The 2D-3D correspondences of an image with a COLMAP model, from the
// COLMAP database the model was made from (ch4 spec §2.2 step 1): the
// image's verified matches (two_view_geometries inliers) with the model's
// registered images, each keypoint matched to a keypoint that observes a 3D
// point. This is how a user's laser images, added to the database with
// `colmap feature_extractor` and matched with `colmap exhaustive_matcher`
// (or any matcher), are tied to a model without being in it.
#pragma once

#include <string>
#include <unordered_map>
#include <vector>

#include "colmap_plugins/scene/database.h"
#include "colmap_plugins/scene/model.h"
#include "laserscale/localization.h"

namespace uw {

struct ImageModelMatches {
  std::string image_name;
  // The model's camera of the image when the database gives the image a
  // camera id the model has (so its refined intrinsics), else the
  // database's camera.
  Camera camera;
  bool camera_from_model = false;
  // Unique (keypoint, 3D point) pairs; one keypoint may carry several 3D
  // points (through different images), which the robust PnP sorts out.
  std::vector<Correspondence2D3D> matches;
  size_t num_matched_model_images = 0;
};

class DatabaseModelMatches {
 public:
  // Reads the verified matches once. Throws uw::Error if the database has
  // no image of the model's (by name): not the model's database.
  DatabaseModelMatches(const Database& database, const Reconstruction& model);

  // Throws uw::Error naming the image if the database does not hold it.
  ImageModelMatches For(const std::string& image_name) const;

 private:
  const Database& database_;
  const Reconstruction& model_;
  std::unordered_map<std::string, uint32_t> database_ids_;   // by name
  std::unordered_map<uint32_t, const Image*> model_images_;  // by db id
  // Per database image id: (other image id, its keypoint, our keypoint).
  std::unordered_map<uint32_t, std::vector<std::array<uint32_t, 3>>> verified_;
};

}  // namespace uw
