#include "colmap_plugins/align/similarity.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <random>

#include "common/util/error.h"
#include "common/util/error_testing.h"

namespace uw {
namespace {

Sim3d TrueSim3() {
  Sim3d b_from_a;
  b_from_a.scale = 3.7;
  b_from_a.rotation = Eigen::Quaterniond(
      Eigen::AngleAxisd(2.1, Eigen::Vector3d(0.3, -1.0, 0.4).normalized()));
  // Far from the origin, as projected (UTM) coordinates are.
  b_from_a.translation = Eigen::Vector3d(4.5e5, 5.2e6, -95.0);
  return b_from_a;
}

// A survey-like cloud: a 40 m x 10 m x 2 m box, in model units.
std::vector<Eigen::Vector3d> RandomPoints(size_t n, std::mt19937_64* random) {
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::vector<Eigen::Vector3d> points;
  for (size_t i = 0; i < n; ++i) {
    points.emplace_back(5.4 * uniform(*random), 1.35 * uniform(*random),
                        0.27 * uniform(*random));
  }
  return points;
}

std::vector<Eigen::Vector3d> Transform(
    const Sim3d& b_from_a, const std::vector<Eigen::Vector3d>& src) {
  std::vector<Eigen::Vector3d> dst;
  for (const Eigen::Vector3d& point : src) dst.push_back(b_from_a * point);
  return dst;
}

// Largest distance between where the estimate and the truth put the points.
double MaxPointError(const Sim3d& estimate, const Sim3d& truth,
                     const std::vector<Eigen::Vector3d>& src) {
  double max_error = 0.0;
  for (const Eigen::Vector3d& point : src) {
    max_error = std::max(max_error, (estimate * point - truth * point).norm());
  }
  return max_error;
}

TEST(EstimateSimilarity, RecoversAKnownSimilarityFromExactPoints) {
  std::mt19937_64 random(1);
  const std::vector<Eigen::Vector3d> src = RandomPoints(30, &random);
  const std::vector<Eigen::Vector3d> dst = Transform(TrueSim3(), src);
  for (const bool robust : {false, true}) {
    SimilarityOptions options;
    options.robust = robust;
    const SimilarityResult result =
        EstimateSimilarity(src, dst, nullptr, options);
    EXPECT_NEAR(result.b_from_a.scale, TrueSim3().scale, 1e-12);
    EXPECT_NEAR(result.b_from_a.rotation.angularDistance(TrueSim3().rotation),
                0.0, 1e-10);
    EXPECT_LT(MaxPointError(result.b_from_a, TrueSim3(), src), 1e-8);
    EXPECT_LT(result.rms_m, 1e-8);
    EXPECT_EQ(result.num_inliers, src.size());
  }
}

TEST(EstimateSimilarity, WithoutScaleEstimatesARigidTransform) {
  std::mt19937_64 random(5);
  const std::vector<Eigen::Vector3d> src = RandomPoints(30, &random);
  Sim3d rigid = TrueSim3();
  rigid.scale = 1.0;
  std::vector<Eigen::Vector3d> dst = Transform(rigid, src);
  std::normal_distribution<double> noise(0.0, 0.01);
  std::vector<Eigen::Matrix3d> covariances;
  for (Eigen::Vector3d& point : dst) {
    point += Eigen::Vector3d(noise(random), noise(random), noise(random));
    covariances.push_back(1e-4 * Eigen::Matrix3d::Identity());
  }
  for (const bool robust : {false, true}) {
    SimilarityOptions options;
    options.robust = robust;
    options.estimate_scale = false;
    for (const auto* weights : std::vector<const std::vector<Eigen::Matrix3d>*>{
             nullptr, &covariances}) {
      const SimilarityResult result =
          EstimateSimilarity(src, dst, weights, options);
      EXPECT_EQ(result.b_from_a.scale, 1.0);
      EXPECT_LT(MaxPointError(result.b_from_a, rigid, src), 0.02);
    }
  }
}

TEST(EstimateSimilarity, RobustFitIgnoresOutliers) {
  std::mt19937_64 random(2);
  const std::vector<Eigen::Vector3d> src = RandomPoints(100, &random);
  std::vector<Eigen::Vector3d> dst = Transform(TrueSim3(), src);
  std::normal_distribution<double> noise(0.0, 0.01);
  std::uniform_real_distribution<double> blunder(1.0, 5.0);
  for (size_t i = 0; i < dst.size(); ++i) {
    dst[i] += Eigen::Vector3d(noise(random), noise(random), noise(random));
    // 25 % of gross errors (a wrong fix, a swapped name), all on one side.
    if (i % 4 == 0) dst[i] += Eigen::Vector3d(blunder(random), 0.0, 1.0);
  }
  SimilarityOptions options;
  const SimilarityResult robust =
      EstimateSimilarity(src, dst, nullptr, options);
  options.robust = false;
  const SimilarityResult plain = EstimateSimilarity(src, dst, nullptr, options);

  size_t flagged_outliers = 0;
  size_t rejected_inliers = 0;
  for (size_t i = 0; i < dst.size(); ++i) {
    flagged_outliers += (i % 4 == 0 && !robust.inliers[i]) ? 1 : 0;
    rejected_inliers += (i % 4 != 0 && !robust.inliers[i]) ? 1 : 0;
  }
  const double robust_error = MaxPointError(robust.b_from_a, TrueSim3(), src);
  const double plain_error = MaxPointError(plain.b_from_a, TrueSim3(), src);
  std::cout << "[ figures ] 100 points, 1 cm noise, 25 outliers of 1-5 m: "
            << "robust flags " << flagged_outliers << "/25 outliers, rejects "
            << rejected_inliers << "/75 inliers, threshold "
            << robust.max_error_m << " m, max point error " << robust_error
            << " m (least squares: " << plain_error << " m)\n";
  EXPECT_EQ(flagged_outliers, 25u);
  EXPECT_LE(rejected_inliers, 1u);
  EXPECT_LT(robust_error, 0.02);
  EXPECT_GT(plain_error, 20 * robust_error);
  EXPECT_NEAR(robust.rms_m, 0.01 * std::sqrt(3.0), 0.005);
}

TEST(EstimateSimilarity, GivenThresholdSelectsInliersByDistance) {
  std::mt19937_64 random(3);
  const std::vector<Eigen::Vector3d> src = RandomPoints(40, &random);
  std::vector<Eigen::Vector3d> dst = Transform(TrueSim3(), src);
  dst[7] += Eigen::Vector3d(0.0, 0.0, 0.5);
  SimilarityOptions options;
  options.max_error_m = 0.1;
  const SimilarityResult result =
      EstimateSimilarity(src, dst, nullptr, options);
  EXPECT_EQ(result.num_inliers, 39u);
  EXPECT_FALSE(result.inliers[7]);
  EXPECT_DOUBLE_EQ(result.max_error_m, 0.1);
  EXPECT_NEAR(result.residuals[7].z(), 0.5, 1e-6);
  EXPECT_LT(MaxPointError(result.b_from_a, TrueSim3(), src), 1e-6);
}

// USBL-like navigation: centimetre depth, metre-level horizontal noise on
// one axis. Weighting by the covariances trusts the good axes.
TEST(EstimateSimilarity, CovarianceWeightingBeatsUnweightedWithOneNoisyAxis) {
  std::mt19937_64 random(4);
  const std::vector<Eigen::Vector3d> src = RandomPoints(60, &random);
  std::vector<Eigen::Vector3d> dst = Transform(TrueSim3(), src);
  const Eigen::Vector3d sigma(0.01, 0.01, 1.0);
  std::normal_distribution<double> noise(0.0, 1.0);
  std::vector<Eigen::Matrix3d> covariances;
  for (Eigen::Vector3d& point : dst) {
    point += sigma.cwiseProduct(
        Eigen::Vector3d(noise(random), noise(random), noise(random)));
    covariances.push_back(sigma.cwiseAbs2().asDiagonal());
  }
  SimilarityOptions options;
  options.robust = false;
  const SimilarityResult unweighted =
      EstimateSimilarity(src, dst, nullptr, options);
  const SimilarityResult weighted =
      EstimateSimilarity(src, dst, &covariances, options);
  options.robust = true;
  const SimilarityResult robust_weighted =
      EstimateSimilarity(src, dst, &covariances, options);
  // The depth offset is known to σ_z / √n either way; weighting shows in
  // what the good axes determine: scale and rotation.
  const auto errors = [&](const SimilarityResult& result) {
    return Eigen::Vector2d(
        std::abs(result.b_from_a.scale / TrueSim3().scale - 1.0),
        result.b_from_a.rotation.angularDistance(TrueSim3().rotation));
  };
  const Eigen::Vector2d unweighted_error = errors(unweighted);
  const Eigen::Vector2d weighted_error = errors(weighted);
  const Eigen::Vector2d robust_error = errors(robust_weighted);
  std::cout << "[ figures ] sigma (0.01, 0.01, 1) m, 60 points: relative "
               "scale error / rotation error (rad) unweighted "
            << unweighted_error.transpose() << ", covariance-weighted "
            << weighted_error.transpose() << ", robust covariance-weighted "
            << robust_error.transpose() << " (" << robust_weighted.num_inliers
            << "/60 inliers)\n";
  EXPECT_LT(weighted_error(0), unweighted_error(0) / 5);
  EXPECT_LT(weighted_error(1), unweighted_error(1) / 5);
  EXPECT_LT(robust_error(0), unweighted_error(0) / 5);
  EXPECT_LT(robust_error(1), unweighted_error(1) / 5);
  EXPECT_GE(robust_weighted.num_inliers, 59u);
  ASSERT_EQ(weighted.mahalanobis.size(), 60u);
  double squared_sum = 0.0;
  for (const double distance : weighted.mahalanobis) {
    squared_sum += distance * distance;
  }
  // chi-square with 3 * 60 − 7 degrees of freedom.
  EXPECT_NEAR(squared_sum / (3 * 60 - 7), 1.0, 0.35);
}

// A single survey pass: 21 camera centres along an 11 m line, 6 cm (across)
// and 4 cm (up) off it, matched to navigation positions 0.95 m off
// horizontally and 2 cm in depth. The turn about the pass is then set by the
// depths alone; an isotropic start put it wherever the horizontal noise
// pointed, and the refinement stayed there (models upside down). The
// estimate must minimise the whitened cost: never above the truth's.
TEST(EstimateSimilarity, FindsTheTurnAboutASinglePassFromTheDepths) {
  const Eigen::Vector3d sigma(0.95, 0.95, 0.02);
  std::normal_distribution<double> normal(0.0, 1.0);
  int worst_trial = -1;
  double worst_angle_deg = 0.0;
  for (int trial = 0; trial < 100; ++trial) {
    std::mt19937_64 random(100 + trial);
    std::vector<Eigen::Vector3d> truth_in_b;
    for (int i = 0; i < 21; ++i) {
      truth_in_b.emplace_back(-5.7 + 0.57 * i, -7.2 + 0.06 * normal(random),
                              4.55 + 0.04 * normal(random));
    }
    const std::vector<Eigen::Vector3d> src =
        Transform(TrueSim3().Inverse(), truth_in_b);
    std::vector<Eigen::Vector3d> dst;
    std::vector<Eigen::Matrix3d> covariances;
    for (const Eigen::Vector3d& point : truth_in_b) {
      dst.push_back(point +
                    sigma.cwiseProduct(Eigen::Vector3d(
                        normal(random), normal(random), normal(random))));
      covariances.push_back(sigma.cwiseAbs2().asDiagonal());
    }
    double truth_cost = 0.0;
    for (size_t i = 0; i < dst.size(); ++i) {
      const Eigen::Vector3d error = TrueSim3() * src[i] - dst[i];
      truth_cost += error.dot(covariances[i].ldlt().solve(error));
    }
    for (const bool robust : {false, true}) {
      SimilarityOptions options;
      options.robust = robust;
      const SimilarityResult result =
          EstimateSimilarity(src, dst, &covariances, options);
      if (result.num_inliers != src.size()) continue;  // Huber's cost differs
      double cost = 0.0;
      for (const double distance : result.mahalanobis) {
        cost += distance * distance;
      }
      EXPECT_LE(cost, truth_cost * (1.0 + 1e-6))
          << "trial " << trial << (robust ? " robust" : "");
      const double angle_deg =
          result.b_from_a.rotation.angularDistance(TrueSim3().rotation) *
          180.0 / M_PI;
      if (angle_deg > worst_angle_deg) {
        worst_angle_deg = angle_deg;
        worst_trial = trial;
      }
    }
  }
  std::cout << "[ figures ] single pass, 100 trials: largest rotation error "
            << worst_angle_deg << " deg (trial " << worst_trial << ")\n";
  EXPECT_LT(worst_angle_deg, 30.0);
}

TEST(EstimateSimilarity, DegenerateInputsThrow) {
  const SimilarityOptions options;
  const std::vector<Eigen::Vector3d> two = {{0, 0, 0}, {1, 0, 0}};
  ExpectErrorContaining([&] { EstimateSimilarity(two, two, nullptr, options); },
                        "2 point pairs; a similarity needs at least 3");
  const std::vector<Eigen::Vector3d> line = {
      {0, 0, 0}, {1, 1, 1}, {2, 2, 2}, {5, 5, 5}};
  std::vector<Eigen::Vector3d> off_line = line;
  off_line[1].x() += 1.0;
  ExpectErrorContaining(
      [&] { EstimateSimilarity(line, off_line, nullptr, options); },
      "the 4 source points are collinear");
  ExpectErrorContaining(
      [&] { EstimateSimilarity(off_line, line, nullptr, options); },
      "the 4 target points are collinear");
  const std::vector<Eigen::Vector3d> same(5, Eigen::Vector3d(1, 2, 3));
  ExpectErrorContaining(
      [&] { EstimateSimilarity(same, same, nullptr, options); }, "collinear");
  ExpectErrorContaining(
      [&] { EstimateSimilarity(off_line, two, nullptr, options); },
      "4 source points, 2 target points");
  std::vector<Eigen::Matrix3d> covariances(4, Eigen::Matrix3d::Identity());
  covariances[2](2, 2) = -1.0;
  ExpectErrorContaining(
      [&] { EstimateSimilarity(off_line, off_line, &covariances, options); },
      "covariance of point 2 is not symmetric positive definite");
  std::vector<Eigen::Vector3d> nan = off_line;
  nan[3].y() = std::nan("");
  ExpectErrorContaining(
      [&] { EstimateSimilarity(off_line, nan, nullptr, options); },
      "point pair 3 is not finite");
  SimilarityOptions bad;
  bad.max_error_m = -1.0;
  ExpectErrorContaining([&] { bad.Check(); }, "max_error_m");
}

}  // namespace
}  // namespace uw
