#include "colmap_plugins/ba/prior_alignment.h"

#include "colmap_plugins/align/similarity.h"
#include "common/util/error.h"

namespace uw {

Sim3d AlignToPriors(const std::vector<ImagePosePrior>& priors,
                    Reconstruction* reconstruction,
                    const SimilarityOptions& options) {
  std::vector<Eigen::Vector3d> centers;
  std::vector<Eigen::Vector3d> positions;
  std::vector<Eigen::Matrix3d> covariances;
  for (const ImagePosePrior& prior : priors) {
    const Image* image = reconstruction->FindImage(prior.image_id);
    if (image == nullptr) {
      throw ErrorAt("a prior names image id ", prior.image_id,
                    ", which is not in the model");
    }
    centers.push_back(image->ProjectionCenter());
    positions.push_back(prior.position_in_world);
    covariances.push_back(prior.position_covariance);
  }
  const SimilarityResult result =
      EstimateSimilarity(centers, positions, &covariances, options);
  TransformReconstruction(result.b_from_a, reconstruction);
  return result.b_from_a;
}

}  // namespace uw
