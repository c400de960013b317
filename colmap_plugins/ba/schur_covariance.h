// Marginal covariances of a Ceres least-squares problem at its solution,
// without a dense inverse (docs/covariance.md; thesis spec ch5_6 §1.7):
//
//   Lambda = J^T J = [A  B; B^T  C]   J whitened, in tangent space, losses
//                                      applied as Ceres applies them;
//   S = A - B C^-1 B^T                 the reduced system of the "reduced"
//                                      variables (poses, intrinsics, offsets);
//   S = L L^T                          one supernodal Cholesky (CHOLMOD);
//   Z = S^-1 on the pattern of L       the sparse-inverse (Takahashi)
//                                      recursion, supernode by supernode;
//   Sigma_j = C_j^-1 + C_j^-1 B_j^T Z[V(j),V(j)] B_j C_j^-1
//                                      each point from the reduced
//                                      variables V(j) that see it.
//
// Every pair of reduced variables that shares a residual (two cameras that
// see one point) is a block of S, hence of L's pattern, so every marginal
// and co-visible cross-covariance is read off Z; nothing else is formed.
//
// The gauge is the problem's (constant blocks, priors) unless a null-space
// basis N is given: then the result is the minimum-norm pseudo-inverse
// Lambda^+ = P G P, with G the inverse after holding dim(N) coordinates
// chosen where N is best conditioned and P = I - Q Q^T, Q = orth(N)
// (any such G is a generalised inverse, and P G P is the same for all).
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

namespace ceres {
class Problem;
}

namespace uw {

// A variable of the reduced system: one or more parameter blocks of the
// problem (a pose: its rotation and translation), in tangent space, in the
// order given. Constant blocks contribute no coordinates.
struct ReducedVariable {
  std::vector<double*> blocks;
  std::string name;  // in messages: "image 12 (img12.png)"
};

// An eliminated variable: one Euclidean 3-vector block (a 3D point).
struct EliminatedPoint {
  double* block = nullptr;
  std::string name;  // "point 77"
};

struct SchurCovarianceOptions {
  bool point_marginals = true;
  // Cross-covariances of reduced variables that share a residual.
  bool covisible_cross = false;
  // Free network: a basis of the gauge null space, rows per reduced
  // variable (its full tangent size) and per point (3), k columns each;
  // empty: the problem fixes its gauge.
  std::vector<Eigen::MatrixXd> null_space_reduced;
  std::vector<Eigen::MatrixXd> null_space_points;
  // An information matrix whose Cholesky has a reciprocal condition number
  // (CHOLMOD's estimate) below this is treated as rank deficient.
  double min_reciprocal_condition = 1e-14;
  // Joint draws from the whole posterior N(x*, Lambda^-1) (Lambda^+ for a
  // free network), correlations between every variable kept: the reduced
  // part as P^T L^-T z from the same factor, each point conditionally on
  // it, x_j = -C_j^-1 B_j^T x_c + C_j^-1/2 z_j. What a Monte Carlo
  // downstream (the laser scale) re-samples a model with. 0: none.
  int num_samples = 0;
  uint64_t sample_seed = 0;  // the draws depend on it alone (any threads)
  // Threads evaluating the Jacobian and assembling the reduced system and
  // the points' marginals. Each residual block writes its own rows, and each
  // point and each column of the reduced system is one task's, summed in a
  // fixed order, so the result is the same for any count.
  int num_threads = 1;

  void Check() const;
};

struct SchurCovariance {
  // Per reduced variable: its tangent-space covariance (the coordinates of
  // its non-constant blocks, in order).
  std::vector<Eigen::MatrixXd> reduced;
  std::vector<Eigen::Matrix3d> points;  // when point_marginals
  // (a, b), a < b: the cross-covariance of two reduced variables that share
  // a residual (rows a's coordinates, columns b's), when covisible_cross.
  std::map<std::pair<int, int>, Eigen::MatrixXd> cross;
  // num_samples draws of the tangent-space error, one per column; rows:
  // every reduced variable's coordinates (from sample_row_of_reduced[a],
  // its full tangent size), then each point's 3 (from sample_row_of_points
  // + 3 j). Zero at constant blocks and held coordinates.
  Eigen::MatrixXd samples;
  std::vector<int> sample_row_of_reduced;
  int sample_row_of_points = 0;

  int num_residuals = 0;
  int num_reduced_coordinates = 0;
  int num_point_coordinates = 0;
  int gauge_dimension = 0;   // dim(N), 0 without
  long factor_nonzeros = 0;  // of L
  double reciprocal_condition = 0.0;
  double jacobian_time_s = 0.0;
  double schur_time_s = 0.0;
  double factor_time_s = 0.0;
  double inverse_time_s = 0.0;  // sparse inverse, point marginals, gauge
};

// Throws uw::Error naming the variable when the problem cannot give a
// covariance: a point whose own information is singular (seen once, or by
// parallel rays), a reduced variable left undetermined (rank deficiency,
// including a gauge not fixed), a residual coupling two points, a
// parameter block that is neither listed nor constant, non-finite values.
SchurCovariance ComputeSchurCovariance(
    ceres::Problem* problem, const std::vector<ReducedVariable>& reduced,
    const std::vector<EliminatedPoint>& points,
    const SchurCovarianceOptions& options);

}  // namespace uw
