#include "colmap_plugins/ba/ceres_covariance.h"

#include <chrono>
#include <utility>

#include <ceres/ceres.h>

#include "common/util/error.h"

namespace uw {

void CeresCovarianceOptions::Check() const {
  if (num_threads < 1) {
    throw ErrorAt("ceres covariance: num_threads = ", num_threads,
                  " must be >= 1");
  }
}

SchurCovariance ComputeCeresCovariance(
    ceres::Problem* problem, const std::vector<ReducedVariable>& reduced,
    const std::vector<EliminatedPoint>& points,
    const CeresCovarianceOptions& options) {
  options.Check();
  using Clock = std::chrono::steady_clock;
  // A variable's free blocks: constant ones have no tangent coordinates in
  // ComputeSchurCovariance's result either.
  std::vector<std::vector<double*>> free_blocks(reduced.size());
  std::vector<std::pair<const double*, const double*>> requested;
  for (size_t a = 0; a < reduced.size(); ++a) {
    for (double* block : reduced[a].blocks) {
      if (!problem->IsParameterBlockConstant(block)) {
        free_blocks[a].push_back(block);
      }
    }
    // Ceres wants each unordered pair once.
    for (size_t x = 0; x < free_blocks[a].size(); ++x) {
      for (size_t y = x; y < free_blocks[a].size(); ++y) {
        requested.emplace_back(free_blocks[a][x], free_blocks[a][y]);
      }
    }
  }
  for (const EliminatedPoint& point : points) {
    requested.emplace_back(point.block, point.block);
  }

  ceres::Covariance::Options ceres_options;
  ceres_options.algorithm_type =
      options.algorithm == CeresCovarianceAlgorithm::kSparseQr
          ? ceres::SPARSE_QR
          : ceres::DENSE_SVD;
  // DENSE_SVD: a rank-deficient problem is an error, as in ours, instead of
  // a silently truncated pseudo-inverse.
  ceres_options.null_space_rank = 0;
  ceres_options.num_threads = options.num_threads;
  ceres::Covariance covariance(ceres_options);
  const auto start = Clock::now();
  if (!covariance.Compute(requested, problem)) {
    throw ErrorAt(
        "ceres::Covariance could not compute the covariance: the problem is "
        "rank deficient (a gauge not fixed, or a variable the residuals do "
        "not determine)");
  }

  SchurCovariance result;
  result.num_residuals = problem->NumResiduals();
  result.reduced.resize(reduced.size());
  for (size_t a = 0; a < reduced.size(); ++a) {
    const std::vector<double*>& blocks = free_blocks[a];
    std::vector<int> sizes, offsets;
    int size = 0;
    for (const double* block : blocks) {
      offsets.push_back(size);
      sizes.push_back(problem->ParameterBlockTangentSize(block));
      size += sizes.back();
    }
    result.num_reduced_coordinates += size;
    Eigen::MatrixXd& marginal = result.reduced[a];
    marginal.resize(size, size);
    for (size_t x = 0; x < blocks.size(); ++x) {
      for (size_t y = x; y < blocks.size(); ++y) {
        Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>
            block(sizes[x], sizes[y]);
        covariance.GetCovarianceBlockInTangentSpace(blocks[x], blocks[y],
                                                    block.data());
        marginal.block(offsets[x], offsets[y], sizes[x], sizes[y]) = block;
        marginal.block(offsets[y], offsets[x], sizes[y], sizes[x]) =
            block.transpose();
      }
    }
    if (!marginal.allFinite()) {
      throw ErrorAt("ceres::Covariance returned non-finite values for ",
                    reduced[a].name);
    }
  }
  for (const EliminatedPoint& point : points) {
    Eigen::Matrix<double, 3, 3, Eigen::RowMajor> block;
    covariance.GetCovarianceBlock(point.block, point.block, block.data());
    if (!block.allFinite()) {
      throw ErrorAt("ceres::Covariance returned non-finite values for ",
                    point.name);
    }
    result.points.push_back(block);
  }
  result.num_point_coordinates = 3 * static_cast<int>(points.size());
  result.factor_time_s =
      std::chrono::duration<double>(Clock::now() - start).count();
  return result;
}

}  // namespace uw
