// Bringing a model into the navigation's frame before (or instead of) the
// navigation-fused adjustment.
#pragma once

#include <string>
#include <vector>

#include "colmap_plugins/align/alignment_plausibility.h"
#include "colmap_plugins/align/sim3.h"
#include "colmap_plugins/align/similarity.h"
#include "colmap_plugins/align/similarity_with_offsets.h"
#include "colmap_plugins/ba/nav_bundle_adjuster.h"
#include "colmap_plugins/scene/model.h"

namespace uw {

// Covariance-weighted similarity from the model's camera centres to the
// priors' positions (robust by default: `options`), applied to the model.
// A model from SfM has an arbitrary frame and scale; the adjustment only
// refines locally, so it starts from here (as COLMAP's pose-prior BA does).
// Returns the similarity (b_from_a: world_from_model). Throws uw::Error for
// fewer than 3 or collinear priors.
SimilarityResult AlignToPriors(
    const std::vector<ImagePosePrior>& priors, Reconstruction* reconstruction,
    const SimilarityOptions& options = SimilarityOptions());

// The camera centre of the prior's image in `reconstruction`; throws
// uw::Error naming the image id when the model lacks it.
Eigen::Vector3d CenterOfPriorImage(const Reconstruction& reconstruction,
                                   const ImagePosePrior& prior);

// The least-squares fit of a similarity from `centres` (the model's camera
// centres of the priors' images, in the priors' order) onto the priors'
// positions, with adjuster.dive_offsets jointly with one offset per dive
// but the reference one (adjuster.reference_dive; 0: the lowest dive
// number) under the offsets' prior (adjuster.dive_offset_sigma_m),
// similarity_with_offsets.h. Throws as EstimateSimilarityWithOffsets, and
// when the fit does not converge.
SimilarityWithOffsets FitToPriors(const std::vector<ImagePosePrior>& priors,
                                  const std::vector<Eigen::Vector3d>& centres,
                                  const NavBundleAdjustmentOptions& adjuster);

// AlignToPriors with the robust default, once the similarity has passed
// CheckAlignmentPlausibility (the priors named `what`): throws its errors
// unless plausibility.accept_implausible (whose flag is `flag`), the model
// then unchanged. The warnings to report are added to `warnings`.
// With adjuster.dive_offsets and more than one dive, the similarity is
// fitted jointly with the offsets (least squares,
// similarity_with_offsets.h) and checked on the residuals without them: a
// robust similarity alone takes one dive and calls the others outliers
// (three dives 1.2 m apart at 7 cm: 283 of 1257 positions "agree").
SimilarityResult AlignToPriorsPlausibly(
    const std::vector<ImagePosePrior>& priors,
    const AlignmentPlausibilityOptions& plausibility, const std::string& what,
    const std::string& flag, const NavBundleAdjustmentOptions& adjuster,
    Reconstruction* reconstruction, std::vector<std::string>* warnings);

}  // namespace uw
