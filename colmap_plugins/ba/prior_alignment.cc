#include "colmap_plugins/ba/prior_alignment.h"

#include <algorithm>
#include <cmath>
#include <set>

#include <Eigen/Cholesky>

#include "colmap_plugins/align/similarity.h"
#include "colmap_plugins/align/similarity_with_offsets.h"
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
    centers.push_back(CenterOfPriorImage(reconstruction, prior));
    result.positions.push_back(prior.position_in_world);
    covariances.push_back(prior.position_covariance);
  }
  result.similarity =
      EstimateSimilarity(centers, result.positions, &covariances, options);
  return result;
}

// With dive offsets: the least-squares fit of the similarity and the
// offsets, as a SimilarityResult whose residuals have the offsets taken
// out and whose inliers are those within the robust fit's threshold.
PriorSimilarity EstimateWithOffsetsToPriors(
    const std::vector<ImagePosePrior>& priors,
    const Reconstruction& reconstruction,
    const NavBundleAdjustmentOptions& adjuster) {
  std::vector<Eigen::Vector3d> centers;
  PriorSimilarity result;
  for (const ImagePosePrior& prior : priors) {
    centers.push_back(CenterOfPriorImage(reconstruction, prior));
    result.positions.push_back(prior.position_in_world);
  }
  const SimilarityWithOffsets fit = FitToPriors(priors, centers, adjuster);
  SimilarityResult& similarity = result.similarity;
  similarity.b_from_a = fit.b_from_a;
  similarity.residuals = fit.residuals;
  const double max_mahalanobis = std::sqrt(kChiSquare3Dof999);
  double squared_sum = 0.0;
  for (size_t i = 0; i < priors.size(); ++i) {
    const Eigen::Vector3d& residual = fit.residuals[i];
    similarity.mahalanobis.push_back(std::sqrt(
        residual.dot(priors[i].position_covariance.ldlt().solve(residual))));
    similarity.inliers.push_back(similarity.mahalanobis.back() <=
                                 max_mahalanobis);
    if (similarity.inliers.back()) {
      ++similarity.num_inliers;
      squared_sum += residual.squaredNorm();
    }
  }
  similarity.rms_m =
      similarity.num_inliers > 0
          ? std::sqrt(squared_sum / static_cast<double>(similarity.num_inliers))
          : 0.0;
  similarity.max_mahalanobis = max_mahalanobis;
  return result;
}

}  // namespace

Eigen::Vector3d CenterOfPriorImage(const Reconstruction& reconstruction,
                                   const ImagePosePrior& prior) {
  const Image* image = reconstruction.FindImage(prior.image_id);
  if (image == nullptr) {
    throw ErrorAt("a prior names image id ", prior.image_id,
                  ", which is not in the model");
  }
  return image->ProjectionCenter();
}

SimilarityWithOffsets FitToPriors(const std::vector<ImagePosePrior>& priors,
                                  const std::vector<Eigen::Vector3d>& centres,
                                  const NavBundleAdjustmentOptions& adjuster) {
  std::vector<Eigen::Vector3d> positions;
  std::vector<Eigen::Matrix3d> covariances;
  std::vector<int> dives;
  for (const ImagePosePrior& prior : priors) {
    positions.push_back(prior.position_in_world);
    covariances.push_back(prior.position_covariance);
    dives.push_back(prior.dive);
  }
  const int reference_dive =
      adjuster.reference_dive != 0 || dives.empty()
          ? adjuster.reference_dive
          : *std::min_element(dives.begin(), dives.end());
  if (!adjuster.dive_offsets) dives.assign(dives.size(), reference_dive);
  SimilarityWithOffsetsOptions options;
  if (adjuster.dive_offsets) {
    options.offset_prior_sigma = adjuster.dive_offset_sigma_m;
  }
  SimilarityWithOffsets fit = EstimateSimilarityWithOffsets(
      centres, positions, covariances, dives, reference_dive, options);
  if (!fit.converged) {
    throw ErrorAt(
        "the similarity", adjuster.dive_offsets ? " and dive offsets" : "",
        " from the model to the ", priors.size(),
        " navigation priors did not converge in ", fit.iterations, " steps");
  }
  return fit;
}

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
    const std::string& flag, const NavBundleAdjustmentOptions& adjuster,
    Reconstruction* reconstruction, std::vector<std::string>* warnings) {
  std::set<int> dives;
  for (const ImagePosePrior& prior : priors) dives.insert(prior.dive);
  PriorSimilarity result =
      adjuster.dive_offsets && dives.size() > 1
          ? EstimateWithOffsetsToPriors(priors, *reconstruction, adjuster)
          : EstimateToPriors(priors, *reconstruction, SimilarityOptions());
  const std::vector<std::string> found = PlausibilityWarnings(
      CheckAlignmentPlausibility(*reconstruction, result.similarity,
                                 result.positions, what, plausibility),
      plausibility, flag);
  warnings->insert(warnings->end(), found.begin(), found.end());
  TransformReconstruction(result.similarity.b_from_a, reconstruction);
  return std::move(result.similarity);
}

}  // namespace uw
