#include "colmap_plugins/align/similarity.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>

#include <ceres/ceres.h>
#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <Eigen/SVD>

#include "colmap_plugins/align/similarity_cost.h"
#include "common/util/error.h"
#include "common/util/median.h"

namespace uw {
namespace {

// RANSAC draws at least this many triples (or all there are).
constexpr int kMinRansacIterations = 100;
// Huber's 95 %-efficiency constant, in units of σ.
constexpr double kHuberScaleInSigmas = 1.345;
// A set of points is collinear when its second singular value is below this
// fraction of the first: the rotation about the line is then undetermined.
constexpr double kMinSpreadRatio = 1e-6;

// Closed-form weighted least squares (Umeyama 1991); weights may be empty
// (all 1). Without estimate_scale, the rotation is the same and the scale 1.
Sim3d UmeyamaSimilarity(const std::vector<Eigen::Vector3d>& src,
                        const std::vector<Eigen::Vector3d>& dst,
                        const std::vector<double>& weights,
                        bool estimate_scale) {
  const auto weight = [&](size_t i) {
    return weights.empty() ? 1.0 : weights[i];
  };
  double weight_sum = 0.0;
  Eigen::Vector3d src_mean = Eigen::Vector3d::Zero();
  Eigen::Vector3d dst_mean = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < src.size(); ++i) {
    weight_sum += weight(i);
    src_mean += weight(i) * src[i];
    dst_mean += weight(i) * dst[i];
  }
  src_mean /= weight_sum;
  dst_mean /= weight_sum;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  double src_variance = 0.0;
  for (size_t i = 0; i < src.size(); ++i) {
    const Eigen::Vector3d src_centred = src[i] - src_mean;
    covariance += weight(i) * (dst[i] - dst_mean) * src_centred.transpose();
    src_variance += weight(i) * src_centred.squaredNorm();
  }
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(
      covariance, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Vector3d sign = Eigen::Vector3d::Ones();
  if (svd.matrixU().determinant() * svd.matrixV().determinant() < 0.0) {
    sign(2) = -1.0;
  }
  const Eigen::Matrix3d rotation =
      svd.matrixU() * sign.asDiagonal() * svd.matrixV().transpose();
  Sim3d b_from_a;
  b_from_a.rotation = Eigen::Quaterniond(rotation).normalized();
  b_from_a.scale =
      estimate_scale ? svd.singularValues().dot(sign) / src_variance : 1.0;
  b_from_a.translation = dst_mean - b_from_a.scale * (rotation * src_mean);
  return b_from_a;
}

// RMS spread of the points along their principal axes, largest first.
Eigen::Vector3d Spread(const std::vector<Eigen::Vector3d>& points) {
  const Eigen::Vector3d mean = Mean(points);
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d& point : points) {
    scatter += (point - mean) * (point - mean).transpose();
  }
  return (Eigen::JacobiSVD<Eigen::Matrix3d>(scatter).singularValues() /
          static_cast<double>(points.size()))
      .cwiseSqrt();
}

bool Collinear(const std::vector<Eigen::Vector3d>& points) {
  const Eigen::Vector3d spread = Spread(points);
  return !(spread(1) > kMinSpreadRatio * spread(0));
}

void ThrowIfCollinear(const std::vector<Eigen::Vector3d>& points,
                      const char* which) {
  if (!Collinear(points)) return;
  const Eigen::Vector3d spread = Spread(points);
  throw ErrorAt("similarity: the ", points.size(), " ", which,
                " points are collinear (RMS spread ", spread(0),
                " along their line, ", spread(1),
                " across it): the rotation about that line is undetermined; "
                "a similarity needs at least 3 points that are not on a line");
}

template <typename T>
std::vector<T> Select(const std::vector<T>& values,
                      const std::vector<bool>& selected) {
  std::vector<T> result;
  for (size_t i = 0; i < values.size(); ++i) {
    if (selected[i]) result.push_back(values[i]);
  }
  return result;
}

// Draws (or, when there are few, enumerates) triples of distinct indices.
class TripleSampler {
 public:
  TripleSampler(size_t num_points, int max_iterations, uint64_t seed)
      : num_points_(num_points), random_(seed) {
    const double num_triples = static_cast<double>(num_points) *
                               (num_points - 1) * (num_points - 2) / 6.0;
    enumerate_ = num_triples <= max_iterations;
    num_iterations_ =
        enumerate_ ? static_cast<int>(num_triples) : max_iterations;
  }

  int NumIterations() const { return num_iterations_; }
  bool Exhaustive() const { return enumerate_; }

  std::array<size_t, 3> Next() {
    if (enumerate_) {
      const std::array<size_t, 3> triple = next_;
      // Lexicographic order of i < j < k.
      if (++next_[2] == num_points_) {
        if (++next_[1] == num_points_ - 1) {
          ++next_[0];
          next_[1] = next_[0] + 1;
        }
        next_[2] = next_[1] + 1;
      }
      return triple;
    }
    std::uniform_int_distribution<size_t> index(0, num_points_ - 1);
    std::array<size_t, 3> triple;
    do {
      triple = {index(random_), index(random_), index(random_)};
    } while (triple[0] == triple[1] || triple[0] == triple[2] ||
             triple[1] == triple[2]);
    return triple;
  }

 private:
  size_t num_points_;
  std::mt19937_64 random_;
  bool enumerate_ = false;
  int num_iterations_ = 0;
  std::array<size_t, 3> next_ = {0, 1, 2};
};

struct Problem {
  std::vector<Eigen::Vector3d> src;  // centred
  std::vector<Eigen::Vector3d> dst;  // centred
  // L^-1 with Σ = L L^T; identity without covariances.
  std::vector<Eigen::Matrix3d> sqrt_information;

  double SquaredError(const Sim3d& b_from_a, size_t i) const {
    return (b_from_a * src[i] - dst[i]).squaredNorm();
  }
  double SquaredMahalanobis(const Sim3d& b_from_a, size_t i) const {
    return (sqrt_information[i] * (b_from_a * src[i] - dst[i])).squaredNorm();
  }
};

// The inlier test: metres, or Mahalanobis distance.
struct InlierTest {
  double max_error_m = 0.0;
  double max_mahalanobis = 0.0;

  bool IsInlier(const Problem& problem, const Sim3d& b_from_a, size_t i) const {
    if (max_mahalanobis > 0.0) {
      return problem.SquaredMahalanobis(b_from_a, i) <=
             max_mahalanobis * max_mahalanobis;
    }
    return problem.SquaredError(b_from_a, i) <= max_error_m * max_error_m;
  }
  // Truncated squared error in units of the threshold (MSAC score).
  double Cost(const Problem& problem, const Sim3d& b_from_a, size_t i) const {
    const double normalised =
        max_mahalanobis > 0.0
            ? problem.SquaredMahalanobis(b_from_a, i) /
                  (max_mahalanobis * max_mahalanobis)
            : problem.SquaredError(b_from_a, i) / (max_error_m * max_error_m);
    return std::min(normalised, 1.0);
  }
};

std::vector<bool> Inliers(const Problem& problem, const Sim3d& b_from_a,
                          const InlierTest& test) {
  std::vector<bool> inliers(problem.src.size());
  for (size_t i = 0; i < inliers.size(); ++i) {
    inliers[i] = test.IsInlier(problem, b_from_a, i);
  }
  return inliers;
}

// The order statistic n/2 (the upper median), LMedS's criterion.
// RANSAC over minimal sets. With a threshold: MSAC (least sum of squared
// errors truncated at the threshold). Without: least median of squares, whose
// median then sets the threshold at 2.5 robust σ (Rousseeuw & Leroy 1987,
// small-sample correction 1 + 5 / (n − 3)).
Sim3d RansacSimilarity(const Problem& problem, const SimilarityOptions& options,
                       InlierTest* test, int* num_iterations) {
  const size_t n = problem.src.size();
  const bool least_median =
      test->max_error_m == 0.0 && test->max_mahalanobis == 0.0;
  TripleSampler sampler(n, options.max_ransac_iterations, options.random_seed);
  double best_score = std::numeric_limits<double>::infinity();
  Sim3d best;
  std::vector<double> squared_errors(n);
  int iterations = 0;
  int required_iterations = sampler.NumIterations();
  for (; iterations < std::min(sampler.NumIterations(), required_iterations);
       ++iterations) {
    const std::array<size_t, 3> triple = sampler.Next();
    std::vector<Eigen::Vector3d> src, dst;
    for (const size_t i : triple) {
      src.push_back(problem.src[i]);
      dst.push_back(problem.dst[i]);
    }
    if (Collinear(src) || Collinear(dst)) continue;
    const Sim3d hypothesis =
        UmeyamaSimilarity(src, dst, {}, options.estimate_scale);
    double score = 0.0;
    if (least_median) {
      for (size_t i = 0; i < n; ++i) {
        squared_errors[i] = problem.SquaredError(hypothesis, i);
      }
      score = Median(squared_errors);
    } else {
      size_t num_inliers = 0;
      for (size_t i = 0; i < n; ++i) {
        score += test->Cost(problem, hypothesis, i);
        num_inliers += test->IsInlier(problem, hypothesis, i) ? 1 : 0;
      }
      // Stop once another draw is unlikely (1e-3) to find a larger
      // consensus; enumeration always runs to the end.
      if (score < best_score && !sampler.Exhaustive()) {
        const double inlier_ratio = static_cast<double>(num_inliers) / n;
        const double all_inliers = std::pow(inlier_ratio, 3);
        // At least kMinRansacIterations: a first consensus of all points
        // may still have a poor truncated cost.
        if (all_inliers >= 1.0) {
          required_iterations = kMinRansacIterations;
        } else if (all_inliers > 0.0) {
          required_iterations =
              std::max(kMinRansacIterations,
                       static_cast<int>(std::ceil(std::log(1e-3) /
                                                  std::log1p(-all_inliers))));
        }
      }
    }
    if (score < best_score) {
      best_score = score;
      best = hypothesis;
    }
  }
  *num_iterations = iterations;
  if (!std::isfinite(best_score)) {
    throw ErrorAt("similarity: every triple of the ", n,
                  " points is collinear");
  }
  if (least_median) {
    const double robust_sigma = 1.4826 *
                                (1.0 + 5.0 / std::max<double>(1, n - 3)) *
                                std::sqrt(best_score);
    // Noise-free data has a zero median; keep rounding errors inliers.
    double extent = 0.0;
    for (const Eigen::Vector3d& point : problem.dst) {
      extent = std::max(extent, point.norm());
    }
    test->max_error_m = std::max(2.5 * robust_sigma, 1e-9 * extent);
  }
  return best;
}

// Minimises the (whitened) squared residuals of the inliers, with a Huber
// loss when robust, from `initial`; `cost` gets the final cost.
Sim3d RefineSimilarityFrom(const Problem& problem,
                           const std::vector<bool>& inliers,
                           const Sim3d& initial, double huber_scale,
                           bool estimate_scale, double* cost) {
  Eigen::Quaterniond rotation = initial.rotation.normalized();
  Eigen::Vector3d translation = initial.translation;
  double log_scale = std::log(initial.scale);
  Eigen::Vector3d no_offset = Eigen::Vector3d::Zero();
  ceres::Problem ceres_problem;
  for (size_t i = 0; i < problem.src.size(); ++i) {
    if (!inliers[i]) continue;
    ceres_problem.AddResidualBlock(
        WhitenedPointResidual::Create(problem.src[i], problem.dst[i],
                                      problem.sqrt_information[i]),
        huber_scale > 0.0 ? new ceres::HuberLoss(huber_scale) : nullptr,
        rotation.coeffs().data(), translation.data(), &log_scale,
        no_offset.data());
  }
  ceres_problem.SetParameterBlockConstant(no_offset.data());
  ceres_problem.SetManifold(rotation.coeffs().data(),
                            new ceres::EigenQuaternionManifold);
  if (!estimate_scale) ceres_problem.SetParameterBlockConstant(&log_scale);
  ceres::Solver::Summary summary;
  ceres::Solve(SimilaritySolverOptions(100), &ceres_problem, &summary);
  if (!summary.IsSolutionUsable()) {
    throw ErrorAt("similarity: refinement failed: ", summary.message);
  }
  Sim3d refined;
  refined.rotation = rotation.normalized();
  refined.translation = translation;
  refined.scale = std::exp(log_scale);
  *cost = summary.final_cost;
  return refined;
}

// Turns about the source's longest axis tried besides the start itself.
constexpr int kAxisStarts = 8;

// RefineSimilarityFrom, from `initial` and from `initial` turned about the
// longest axis of the (centred) inlier sources by multiples of 45 deg,
// keeping the lowest cost. Why: the start comes from Umeyama's closed form
// (or a RANSAC triple), which weighs every axis alike. Points along a
// line (a single survey pass: 21 centres 6 cm off an 11 m line) fix the
// rotation about it only through the coordinate the target knows best (the
// depth, 2 cm, against 1 m across), so the isotropic start puts that
// rotation wherever the across-track noise points, and the whitened cost
// is so flat there that a local refinement stays (seen: models turned by
// 140 deg about the pass, upside down, with exit 0). The cost is close to a
// single wave in that angle, so one of the turned starts lies in its valley.
Sim3d RefineSimilarity(const Problem& problem, const std::vector<bool>& inliers,
                       const Sim3d& initial, double huber_scale,
                       bool estimate_scale) {
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (size_t i = 0; i < problem.src.size(); ++i) {
    if (inliers[i]) scatter += problem.src[i] * problem.src[i].transpose();
  }
  const Eigen::Vector3d axis =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(scatter)
          .eigenvectors()
          .col(2);
  double best_cost = 0.0;
  Sim3d best = RefineSimilarityFrom(problem, inliers, initial, huber_scale,
                                    estimate_scale, &best_cost);
  for (int k = 1; k < kAxisStarts; ++k) {
    Sim3d start = initial;
    start.rotation =
        initial.rotation * Eigen::Quaterniond(Eigen::AngleAxisd(
                               2.0 * M_PI * k / kAxisStarts, axis));
    double cost = 0.0;
    const Sim3d refined = RefineSimilarityFrom(
        problem, inliers, start, huber_scale, estimate_scale, &cost);
    // Only a clearly lower cost replaces the plain start's answer: the same
    // minimum reached from elsewhere must not move it by rounding.
    if (cost < best_cost * (1.0 - 1e-9)) {
      best_cost = cost;
      best = refined;
    }
  }
  return best;
}

}  // namespace

void SimilarityOptions::Check() const {
  if (!(max_error_m >= 0.0) || !std::isfinite(max_error_m)) {
    throw ErrorAt(
        "SimilarityOptions: max_error_m must be >= 0 (0: "
        "automatic), got ",
        max_error_m);
  }
  if (max_ransac_iterations < 1) {
    throw ErrorAt("SimilarityOptions: max_ransac_iterations must be >= 1, got ",
                  max_ransac_iterations);
  }
}

SimilarityResult EstimateSimilarity(
    const std::vector<Eigen::Vector3d>& src,
    const std::vector<Eigen::Vector3d>& dst,
    const std::vector<Eigen::Matrix3d>* dst_covariances,
    const SimilarityOptions& options) {
  options.Check();
  if (src.size() != dst.size() ||
      (dst_covariances != nullptr && dst_covariances->size() != dst.size())) {
    throw ErrorAt(
        "similarity: ", src.size(), " source points, ", dst.size(),
        " target points",
        dst_covariances != nullptr
            ? ", " + std::to_string(dst_covariances->size()) + " covariances"
            : "",
        ": expected the same number");
  }
  const size_t n = src.size();
  if (n < 3) {
    throw ErrorAt("similarity: ", n, " point pair", n == 1 ? "" : "s",
                  "; a similarity needs at least 3 points that are not on a "
                  "line");
  }
  for (size_t i = 0; i < n; ++i) {
    if (!src[i].allFinite() || !dst[i].allFinite()) {
      throw ErrorAt("similarity: point pair ", i, " is not finite");
    }
  }
  ThrowIfCollinear(src, "source");
  ThrowIfCollinear(dst, "target");

  // Centring keeps large coordinates (UTM, 1e5 m) from costing precision.
  const Eigen::Vector3d src_mean = Mean(src);
  const Eigen::Vector3d dst_mean = Mean(dst);
  Problem problem;
  std::vector<double> weights;
  for (size_t i = 0; i < n; ++i) {
    problem.src.push_back(src[i] - src_mean);
    problem.dst.push_back(dst[i] - dst_mean);
    if (dst_covariances == nullptr) {
      problem.sqrt_information.push_back(Eigen::Matrix3d::Identity());
      continue;
    }
    const Eigen::Matrix3d& covariance = (*dst_covariances)[i];
    const Eigen::LLT<Eigen::Matrix3d> llt(covariance);
    if (!covariance.allFinite() ||
        !covariance.isApprox(covariance.transpose(), 1e-9) ||
        llt.info() != Eigen::Success ||
        !(llt.matrixL().toDenseMatrix().diagonal().minCoeff() > 0.0)) {
      throw ErrorAt("similarity: covariance of point ", i,
                    " is not symmetric positive definite");
    }
    problem.sqrt_information.push_back(
        llt.matrixL().solve(Eigen::Matrix3d::Identity()));
    weights.push_back(3.0 / covariance.trace());
  }
  const bool has_covariances = dst_covariances != nullptr;

  SimilarityResult result;
  InlierTest test;
  Sim3d centred_b_from_a;
  std::vector<bool> inliers(n, true);
  if (options.robust) {
    test.max_error_m = options.max_error_m;
    if (options.max_error_m == 0.0 && has_covariances) {
      test.max_mahalanobis = std::sqrt(kChiSquare3Dof999);
    }
    centred_b_from_a =
        RansacSimilarity(problem, options, &test, &result.ransac_iterations);
    // Whitened residuals are in σ; metric ones in metres of the threshold.
    const double huber_scale =
        has_covariances ? kHuberScaleInSigmas : 0.5 * test.max_error_m;
    // Refining moves the fit, which may move points across the threshold:
    // repeat until the inlier set is stable.
    for (int round = 0; round < 10; ++round) {
      const std::vector<bool> next = Inliers(problem, centred_b_from_a, test);
      if (round > 0 && next == inliers) break;
      inliers = next;
      if (std::count(inliers.begin(), inliers.end(), true) < 3) {
        throw ErrorAt("similarity: only ",
                      std::count(inliers.begin(), inliers.end(), true), " of ",
                      n, " points agree with any similarity");
      }
      ThrowIfCollinear(Select(src, inliers), "inlier source");
      centred_b_from_a = RefineSimilarity(problem, inliers, centred_b_from_a,
                                          huber_scale, options.estimate_scale);
    }
    result.max_error_m = test.max_mahalanobis > 0.0 ? 0.0 : test.max_error_m;
    result.max_mahalanobis = test.max_mahalanobis;
  } else {
    centred_b_from_a = UmeyamaSimilarity(problem.src, problem.dst, weights,
                                         options.estimate_scale);
    if (has_covariances) {
      centred_b_from_a = RefineSimilarity(problem, inliers, centred_b_from_a,
                                          0.0, options.estimate_scale);
    }
  }

  // Back from centred frames: x_b = s R (x_a − m_a) + t_c + m_b.
  result.b_from_a = centred_b_from_a;
  result.b_from_a.translation =
      centred_b_from_a.translation + dst_mean -
      centred_b_from_a.scale * (centred_b_from_a.rotation * src_mean);
  result.inliers = inliers;
  double squared_sum = 0.0;
  for (size_t i = 0; i < n; ++i) {
    // From the centred frames, which do not lose digits to large
    // coordinates.
    result.residuals.push_back(
        -(centred_b_from_a * problem.src[i] - problem.dst[i]));
    if (has_covariances) {
      result.mahalanobis.push_back(
          std::sqrt(problem.SquaredMahalanobis(centred_b_from_a, i)));
    }
    if (inliers[i]) {
      ++result.num_inliers;
      squared_sum += result.residuals.back().squaredNorm();
    }
  }
  result.rms_m = std::sqrt(squared_sum / result.num_inliers);
  return result;
}

}  // namespace uw
