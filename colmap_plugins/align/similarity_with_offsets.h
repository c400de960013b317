// The similarity that places a model on navigation made of several dives,
// each dive but a reference one off by its own unknown constant offset
// (a USBL's per-deployment bias): one joint least-squares fit of the
// similarity and the offsets.
//
// Why joint: fitted in turn (offsets for the similarity, the similarity for
// the offsets), the two trade off along a shallow valley when the dives lie
// apart, since an offset of one dive then looks like a rotation or a scale
// about the other; alternation crawls there, and stopping it early leaves
// the bias in the residuals (the noise estimate 16x the realised noise,
// docs/dev/issue17_plan.md §1f). Jointly, Gauss-Newton on the 7 + 3(D - 1)
// parameters converges in a few steps.
//
// The model: b_from_a * src_i = dst_i + offset_{g_i} + e_i with
// e_i ~ N(0, Σ_i) and the reference group's offset 0. Minimised:
// Σ_i |L_i^-1 (b_from_a * src_i - dst_i - offset_{g_i})|², Σ_i = L_i L_i^T.
#pragma once

#include <map>
#include <vector>

#include <Eigen/Core>

#include "colmap_plugins/align/sim3.h"

namespace uw {

struct SimilarityWithOffsetsOptions {
  bool estimate_scale = true;
  // Levenberg-Marquardt steps; a fit that needs more is returned with
  // converged = false (the caller says what that means for it).
  int max_iterations = 100;
  // > 0: each offset also has a zero-mean prior of this sigma (per axis, in
  // the units of the targets), as the navigation-fused adjustment gives it
  // (--Dive.offset_sigma); a fit without it would undo the prior's pull
  // wherever the adjustment is placed by this fit. The chi-square excludes
  // it.
  double offset_prior_sigma = 0.0;

  void Check() const;
};

struct SimilarityWithOffsets {
  Sim3d b_from_a;
  // Per group; the reference group's is zero. Added to dst.
  std::map<int, Eigen::Vector3d> offsets;
  // dst_i + offset_{g_i} - b_from_a * src_i, metres of frame b.
  std::vector<Eigen::Vector3d> residuals;
  double chi_square = 0.0;  // Σ_i squared Mahalanobis norm of residual i
  int iterations = 0;
  bool converged = false;
};

// groups[i] is point i's group (a dive number); reference_group must be one
// of them. Throws uw::Error when the sizes differ, a value is not finite, a
// covariance is not positive definite, a group has no points, or the
// points leave the similarity and offsets undetermined (fewer than 3
// points, collinear points, or every group but the reference collinear
// with it in a way that frees a rotation): the message says which.
SimilarityWithOffsets EstimateSimilarityWithOffsets(
    const std::vector<Eigen::Vector3d>& src,
    const std::vector<Eigen::Vector3d>& dst,
    const std::vector<Eigen::Matrix3d>& dst_covariances,
    const std::vector<int>& groups, int reference_group,
    const SimilarityWithOffsetsOptions& options);

}  // namespace uw
