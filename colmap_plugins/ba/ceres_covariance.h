// The same marginal covariances as schur_covariance.h, computed by
// ceres::Covariance: the peer our Schur route is checked against (DENSE_SVD,
// exact on small problems) and timed against (SPARSE_QR, what a Ceres user
// reaches for on a bundle adjustment; bench/covariance_speed_bench.cc).
// ceres::Covariance factors the whole Jacobian, points included, and
// recovers each requested block by solves against that factor; it neither
// eliminates the points nor exploits the reduced system's sparsity, which
// is why it slows so steeply with the survey's size (anchors.md §1.6).
#pragma once

#include <vector>

#include "colmap_plugins/ba/schur_covariance.h"

namespace uw {

enum class CeresCovarianceAlgorithm {
  kSparseQr,  // SuiteSparseQR on the full Jacobian
  kDenseSvd,  // the dense pseudo-inverse: small problems only
};

struct CeresCovarianceOptions {
  CeresCovarianceAlgorithm algorithm = CeresCovarianceAlgorithm::kSparseQr;
  int num_threads = 1;

  void Check() const;
};

// Fills `reduced` (and `points` when point blocks are given) of a
// SchurCovariance, in the same tangent-space coordinates and order as
// ComputeSchurCovariance; factor_time_s holds ceres::Covariance::Compute's
// time. The gauge must be fixed by the problem (constant blocks, priors):
// ceres::Covariance knows no null-space basis. Throws uw::Error when Ceres
// reports the problem rank deficient or a value is not finite.
SchurCovariance ComputeCeresCovariance(
    ceres::Problem* problem, const std::vector<ReducedVariable>& reduced,
    const std::vector<EliminatedPoint>& points,
    const CeresCovarianceOptions& options);

}  // namespace uw
