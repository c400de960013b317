#include "colmap_plugins/align/similarity_with_offsets.h"

#include <cmath>
#include <set>
#include <string>

#include <ceres/ceres.h>
#include <ceres/normal_prior.h>
#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <Eigen/SVD>

#include "colmap_plugins/align/similarity.h"
#include "colmap_plugins/align/similarity_cost.h"
#include "common/util/error.h"

namespace uw {
namespace {

// The smallest singular value of the Jacobian, its columns scaled to unit
// norm, against the largest: ~0 when the points leave a direction of the
// similarity and offsets free.
double ReciprocalCondition(ceres::Problem* problem,
                           const std::vector<double*>& variable_blocks) {
  ceres::Problem::EvaluateOptions evaluate;
  evaluate.parameter_blocks = variable_blocks;
  ceres::CRSMatrix crs;
  problem->Evaluate(evaluate, nullptr, nullptr, nullptr, &crs);
  Eigen::MatrixXd jacobian = Eigen::MatrixXd::Zero(crs.num_rows, crs.num_cols);
  for (int r = 0; r < crs.num_rows; ++r) {
    for (int e = crs.rows[r]; e < crs.rows[r + 1]; ++e) {
      jacobian(r, crs.cols[e]) = crs.values[e];
    }
  }
  for (int c = 0; c < jacobian.cols(); ++c) {
    const double norm = jacobian.col(c).norm();
    if (norm > 0.0) jacobian.col(c) /= norm;
  }
  const Eigen::VectorXd singular =
      Eigen::JacobiSVD<Eigen::MatrixXd>(jacobian).singularValues();
  return singular(singular.size() - 1) / singular(0);
}

}  // namespace

void SimilarityWithOffsetsOptions::Check() const {
  if (!(offset_prior_sigma >= 0.0 && std::isfinite(offset_prior_sigma))) {
    throw ErrorAt(
        "SimilarityWithOffsetsOptions: offset_prior_sigma must be >= 0 (0: "
        "none), got ",
        offset_prior_sigma);
  }
  if (max_iterations < 1) {
    throw ErrorAt("SimilarityWithOffsetsOptions: max_iterations must be >= 1, ",
                  "got ", max_iterations);
  }
}

SimilarityWithOffsets EstimateSimilarityWithOffsets(
    const std::vector<Eigen::Vector3d>& src,
    const std::vector<Eigen::Vector3d>& dst,
    const std::vector<Eigen::Matrix3d>& dst_covariances,
    const std::vector<int>& groups, int reference_group,
    const SimilarityWithOffsetsOptions& options) {
  options.Check();
  if (groups.size() != src.size()) {
    throw ErrorAt("similarity with offsets: ", src.size(), " points but ",
                  groups.size(), " group numbers");
  }
  const std::set<int> group_set(groups.begin(), groups.end());
  if (group_set.count(reference_group) == 0) {
    throw ErrorAt("similarity with offsets: the reference group ",
                  reference_group, " has no points");
  }
  // The plain fit of every point is the start (and checks sizes, values,
  // covariances and collinearity).
  SimilarityOptions plain;
  plain.robust = false;
  plain.estimate_scale = options.estimate_scale;
  const Sim3d start =
      EstimateSimilarity(src, dst, &dst_covariances, plain).b_from_a;

  const size_t n = src.size();
  std::vector<Eigen::Matrix3d> information(n);
  std::map<int, Eigen::Matrix3d> group_information;
  std::map<int, Eigen::Vector3d> group_weighted;
  for (size_t i = 0; i < n; ++i) {
    information[i] = dst_covariances[i].inverse();
    group_information.try_emplace(groups[i], Eigen::Matrix3d::Zero());
    group_weighted.try_emplace(groups[i], Eigen::Vector3d::Zero());
    group_information[groups[i]] += information[i];
    group_weighted[groups[i]] += information[i] * (start * src[i] - dst[i]);
  }
  // Each offset starts at its group's weighted mean residual.
  std::map<int, Eigen::Vector3d> offsets;
  for (const int group : group_set) {
    offsets[group] =
        group == reference_group
            ? Eigen::Vector3d::Zero()
            : Eigen::Vector3d(
                  group_information[group].ldlt().solve(group_weighted[group]));
  }

  // Centred, as EstimateSimilarity, so large coordinates keep their digits:
  // x_b = s R (x_a - m_a) + t_c + m_b.
  const Eigen::Vector3d src_mean = Mean(src);
  const Eigen::Vector3d dst_mean = Mean(dst);
  Eigen::Quaterniond rotation = start.rotation.normalized();
  double log_scale = std::log(start.scale);
  Eigen::Vector3d translation =
      start.translation - dst_mean + start.scale * (rotation * src_mean);
  ceres::Problem problem;
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Matrix3d sqrt_information =
        dst_covariances[i].llt().matrixL().solve(Eigen::Matrix3d::Identity());
    problem.AddResidualBlock(
        WhitenedPointResidual::Create(src[i] - src_mean, dst[i] - dst_mean,
                                      sqrt_information),
        nullptr, rotation.coeffs().data(), translation.data(), &log_scale,
        offsets.at(groups[i]).data());
  }
  problem.SetManifold(rotation.coeffs().data(),
                      new ceres::EigenQuaternionManifold);
  std::vector<double*> variable = {rotation.coeffs().data(),
                                   translation.data()};
  if (options.estimate_scale) {
    variable.push_back(&log_scale);
  } else {
    problem.SetParameterBlockConstant(&log_scale);
  }
  for (auto& [group, offset] : offsets) {
    if (group == reference_group) {
      problem.SetParameterBlockConstant(offset.data());
    } else {
      variable.push_back(offset.data());
      if (options.offset_prior_sigma > 0.0) {
        problem.AddResidualBlock(
            new ceres::NormalPrior(
                Eigen::Matrix3d::Identity() / options.offset_prior_sigma,
                Eigen::Vector3d::Zero()),
            nullptr, offset.data());
      }
    }
  }

  ceres::Solver::Summary summary;
  ceres::Solve(SimilaritySolverOptions(options.max_iterations), &problem,
               &summary);
  if (!summary.IsSolutionUsable()) {
    throw ErrorAt("similarity with offsets: the fit failed: ", summary.message);
  }
  // Two dives each on its own line, the lines parallel: an offset along
  // the lines' normal trades with the rotation about them.
  constexpr double kMinReciprocalCondition = 1e-9;
  const double condition = ReciprocalCondition(&problem, variable);
  if (!(condition > kMinReciprocalCondition)) {
    throw ErrorAt(
        "similarity with offsets: the ", n, " points in ", group_set.size(),
        " groups leave the similarity and the offsets undetermined "
        "(reciprocal condition ",
        condition,
        "): with an offset of its own, each group only gives its shape, and "
        "together the shapes do not fix a rotation (e.g. every dive a "
        "straight line, the lines parallel)");
  }

  SimilarityWithOffsets result;
  result.b_from_a.rotation = rotation.normalized();
  result.b_from_a.scale = std::exp(log_scale);
  result.b_from_a.translation =
      translation + dst_mean -
      result.b_from_a.scale * (result.b_from_a.rotation * src_mean);
  result.offsets = offsets;
  for (size_t i = 0; i < n; ++i) {
    // From the centred frames, which do not lose digits.
    const Eigen::Vector3d residual =
        (dst[i] - dst_mean) + offsets.at(groups[i]) -
        (result.b_from_a.scale *
             (result.b_from_a.rotation * (src[i] - src_mean)) +
         translation);
    result.residuals.push_back(residual);
    result.chi_square += residual.dot(information[i] * residual);
  }
  result.iterations = static_cast<int>(summary.iterations.size()) - 1;
  result.converged = summary.termination_type == ceres::CONVERGENCE;
  return result;
}

}  // namespace uw
