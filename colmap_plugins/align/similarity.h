// The similarity that best maps one set of 3D points onto another: camera
// centres of a model onto navigation, reference positions or the truth
// (ch4 spec §7.3, a-posteriori fusion).
//
// Least squares in closed form (Umeyama 1991, weighted); with per-point
// covariances of the target, the covariance-weighted (Mahalanobis) cost is
// minimised by Ceres from there, so a noisy axis (USBL horizontal vs depth
// sensor vertical) counts for what it is worth. Robust: RANSAC over minimal
// sets of 3 points picks the inliers (exhaustively when there are few
// triples), then a Huber-weighted refinement on them; outliers are reported,
// not hidden.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "colmap_plugins/align/sim3.h"

namespace uw {

// The robust fit's inlier threshold with covariances: the 99.9 % quantile
// of the chi-square distribution with 3 degrees of freedom (4.03 sigma).
constexpr double kChiSquare3Dof999 = 16.266;

struct SimilarityOptions {
  // RANSAC + Huber refinement; otherwise every point is an inlier and the
  // fit is plain (weighted) least squares.
  bool robust = true;
  // false: a rigid transform (scale 1), for models already in metres.
  bool estimate_scale = true;
  // Inlier threshold (robust only) on |dst − b_from_a * src|, metres of the
  // target frame. 0: automatic — with covariances, a point is an inlier when
  // its Mahalanobis distance is within the 99.9 % quantile of a 3-DOF
  // chi-square (4.03 σ); without, within 2.5 robust σ of the
  // least-median-of-squares fit (tolerates up to half of outliers).
  double max_error_m = 0.0;
  // RANSAC draws at most this many triples; when there are fewer distinct
  // triples, it tries each once.
  int max_ransac_iterations = 2000;
  // Seed of the triples drawn; the result does not depend on the thread.
  uint64_t random_seed = 1;

  void Check() const;
};

struct SimilarityResult {
  Sim3d b_from_a;
  std::vector<bool> inliers;
  size_t num_inliers = 0;
  // dst_i − b_from_a * src_i, metres of the target frame, for every point.
  std::vector<Eigen::Vector3d> residuals;
  // sqrt(r^T Σ^-1 r) per point when covariances were given; else empty.
  std::vector<double> mahalanobis;
  // RMS of |residual| over the inliers, metres.
  double rms_m = 0.0;
  // The inlier test used (robust only): |residual| <= max_error_m, or, with
  // covariances and an automatic threshold, Mahalanobis <= max_mahalanobis.
  // Both 0 when every point is an inlier by construction.
  double max_error_m = 0.0;
  double max_mahalanobis = 0.0;
  int ransac_iterations = 0;
};

// Finds b_from_a minimising Σ_inliers ρ(|L_i^-1 (b_from_a * src_i − dst_i)|²)
// with Σ_i = L_i L_i^T (identity without covariances). dst_covariances, when
// given, holds one symmetric positive definite 3x3 matrix per point (m²).
// Throws uw::Error when the sizes differ, a value is not finite, a
// covariance is not positive definite, there are fewer than 3 points, or the
// points (or the inliers) are collinear: the message says how many points
// and why.
SimilarityResult EstimateSimilarity(
    const std::vector<Eigen::Vector3d>& src,
    const std::vector<Eigen::Vector3d>& dst,
    const std::vector<Eigen::Matrix3d>* dst_covariances,
    const SimilarityOptions& options);

}  // namespace uw
