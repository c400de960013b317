// Bringing a model into the navigation's frame before (or instead of) the
// navigation-fused adjustment.
#pragma once

#include <vector>

#include "colmap_plugins/align/sim3.h"
#include "colmap_plugins/align/similarity.h"
#include "colmap_plugins/ba/nav_bundle_adjuster.h"
#include "colmap_plugins/scene/model.h"

namespace uw {

// Covariance-weighted similarity from the model's camera centres to the
// priors' positions (robust by default: `options`), applied to the model.
// A model from SfM has an arbitrary frame and scale; the adjustment only
// refines locally, so it starts from here (as COLMAP's pose-prior BA does).
// Returns world_from_model. Throws uw::Error for fewer than 3 or collinear
// priors.
Sim3d AlignToPriors(const std::vector<ImagePosePrior>& priors,
                    Reconstruction* reconstruction,
                    const SimilarityOptions& options = SimilarityOptions());

}  // namespace uw
