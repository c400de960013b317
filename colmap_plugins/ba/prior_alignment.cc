#include "colmap_plugins/ba/prior_alignment.h"

#include "colmap_plugins/align/similarity.h"
#include "common/util/error.h"

namespace uw {
namespace {

struct PriorSimilarity {
  SimilarityResult similarity;
  std::vector<Eigen::Vector3d> positions;  // of the priors, in their order
};

PriorSimilarity EstimateToPriors(const std::vector<ImagePosePrior>& priors,
                                 const Reconstruction& reconstruction,
                                 const SimilarityOptions& options) {
  std::vector<Eigen::Vector3d> centers;
  std::vector<Eigen::Matrix3d> covariances;
  PriorSimilarity result;
  for (const ImagePosePrior& prior : priors) {
    const Image* image = reconstruction.FindImage(prior.image_id);
    if (image == nullptr) {
      throw ErrorAt("a prior names image id ", prior.image_id,
                    ", which is not in the model");
    }
    centers.push_back(image->ProjectionCenter());
    result.positions.push_back(prior.position_in_world);
    covariances.push_back(prior.position_covariance);
  }
  result.similarity =
      EstimateSimilarity(centers, result.positions, &covariances, options);
  return result;
}

}  // namespace

SimilarityResult AlignToPriors(const std::vector<ImagePosePrior>& priors,
                               Reconstruction* reconstruction,
                               const SimilarityOptions& options) {
  PriorSimilarity result = EstimateToPriors(priors, *reconstruction, options);
  TransformReconstruction(result.similarity.b_from_a, reconstruction);
  return std::move(result.similarity);
}

SimilarityResult AlignToPriorsPlausibly(
    const std::vector<ImagePosePrior>& priors,
    const AlignmentPlausibilityOptions& plausibility, const std::string& what,
    const std::string& flag, Reconstruction* reconstruction,
    std::vector<std::string>* warnings) {
  PriorSimilarity result =
      EstimateToPriors(priors, *reconstruction, SimilarityOptions());
  const std::vector<std::string> found = PlausibilityWarnings(
      CheckAlignmentPlausibility(*reconstruction, result.similarity,
                                 result.positions, what, plausibility),
      plausibility, flag);
  warnings->insert(warnings->end(), found.begin(), found.end());
  TransformReconstruction(result.similarity.b_from_a, reconstruction);
  return std::move(result.similarity);
}

}  // namespace uw
