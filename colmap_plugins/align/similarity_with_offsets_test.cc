#include "colmap_plugins/align/similarity_with_offsets.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "common/util/error.h"
#include "common/util/error_testing.h"

namespace uw {
namespace {

Sim3d TrueSim3() {
  Sim3d b_from_a;
  b_from_a.scale = 2.3;
  b_from_a.rotation = Eigen::Quaterniond(
      Eigen::AngleAxisd(1.2, Eigen::Vector3d(0.2, -0.4, 1.0).normalized()));
  // Far from the origin, as projected (UTM) coordinates are.
  b_from_a.translation = Eigen::Vector3d(4.5e5, 5.2e6, -95.0);
  return b_from_a;
}

// Camera centres of a three-dive survey in the world (b), metres: each dive
// a lawnmower patch at constant depth, the patches 30-40 m apart (where
// an offset of one dive looks most like a rotation about another).
struct Survey {
  std::vector<Eigen::Vector3d> world;
  std::vector<int> dives;
};

Survey ThreeDives() {
  const Eigen::Vector3d corners[3] = {{0, 0, -50}, {40, 0, -50}, {0, 35, -50}};
  Survey survey;
  for (int dive = 1; dive <= 3; ++dive) {
    for (int line = 0; line < 4; ++line) {
      for (int k = 0; k < 25; ++k) {
        survey.world.push_back(
            corners[dive - 1] +
            Eigen::Vector3d(0.8 * k, 3.0 * line, 0.1 * std::sin(0.3 * k)));
        survey.dives.push_back(dive);
      }
    }
  }
  return survey;
}

// A USBL: 7 cm horizontally, a depth sensor 2 cm.
Eigen::Matrix3d NavCovariance() {
  return Eigen::Vector3d(0.07 * 0.07, 0.07 * 0.07, 0.02 * 0.02).asDiagonal();
}

// Offsets added to the navigation: it estimates -bias of dives 2 and 3.
std::map<int, Eigen::Vector3d> Biases() {
  return {{1, Eigen::Vector3d::Zero()},
          {2, Eigen::Vector3d(0.9, -0.8, 0.05)},
          {3, Eigen::Vector3d(-0.6, -1.1, -0.03)}};
}

// The model (a) and its navigation (b): the navigation is the truth plus the
// dive's bias and, with `noisy`, noise of NavCovariance.
void MakeProblem(bool noisy, std::vector<Eigen::Vector3d>* model,
                 std::vector<Eigen::Vector3d>* navigation,
                 std::vector<Eigen::Matrix3d>* covariances,
                 std::vector<int>* dives) {
  const Survey survey = ThreeDives();
  const Sim3d model_from_world = TrueSim3().Inverse();
  std::mt19937_64 random(7);
  std::normal_distribution<double> normal;
  const Eigen::Vector3d sigma = NavCovariance().diagonal().cwiseSqrt();
  for (size_t i = 0; i < survey.world.size(); ++i) {
    model->push_back(model_from_world * survey.world[i]);
    Eigen::Vector3d noise = Eigen::Vector3d::Zero();
    if (noisy) {
      noise =
          Eigen::Vector3d(sigma(0) * normal(random), sigma(1) * normal(random),
                          sigma(2) * normal(random));
    }
    navigation->push_back(survey.world[i] + Biases().at(survey.dives[i]) +
                          noise);
    covariances->push_back(NavCovariance());
  }
  *dives = survey.dives;
}

TEST(EstimateSimilarityWithOffsets, RecoversTheSimilarityAndOffsetsExactly) {
  std::vector<Eigen::Vector3d> model, navigation;
  std::vector<Eigen::Matrix3d> covariances;
  std::vector<int> dives;
  MakeProblem(false, &model, &navigation, &covariances, &dives);
  const SimilarityWithOffsets fit = EstimateSimilarityWithOffsets(
      model, navigation, covariances, dives, 1, SimilarityWithOffsetsOptions());
  EXPECT_TRUE(fit.converged);
  EXPECT_NEAR(fit.b_from_a.scale, TrueSim3().scale, 1e-9);
  EXPECT_LT(fit.b_from_a.rotation.angularDistance(TrueSim3().rotation), 1e-9);
  for (size_t i = 0; i < model.size(); ++i) {
    // The model lands on the truth, which is the navigation less its bias.
    EXPECT_LT((fit.b_from_a * model[i] - ThreeDives().world[i]).norm(), 1e-6);
  }
  ASSERT_EQ(fit.offsets.size(), 3u);
  for (const auto& [dive, bias] : Biases()) {
    EXPECT_LT((fit.offsets.at(dive) + bias).norm(), 1e-6) << "dive " << dive;
  }
  EXPECT_LT(fit.chi_square, 1e-6);
}

// With noise the fit is the least-squares one: at its minimum the gradient
// in each offset and in the translation is zero, i.e. every dive's (and the
// whole survey's) information-weighted mean residual vanishes; and the
// chi-square is what its degrees of freedom give. A few Gauss-Newton steps
// get there, where fitting the offsets and the similarity in turn needs
// hundreds of rounds on this geometry.
TEST(EstimateSimilarityWithOffsets, ReachesTheLeastSquaresMinimumInFewSteps) {
  std::vector<Eigen::Vector3d> model, navigation;
  std::vector<Eigen::Matrix3d> covariances;
  std::vector<int> dives;
  MakeProblem(true, &model, &navigation, &covariances, &dives);
  const SimilarityWithOffsets fit = EstimateSimilarityWithOffsets(
      model, navigation, covariances, dives, 2, SimilarityWithOffsetsOptions());
  EXPECT_TRUE(fit.converged);
  EXPECT_LE(fit.iterations, 10);
  EXPECT_EQ(fit.offsets.at(2), Eigen::Vector3d::Zero());
  const Eigen::Matrix3d information = NavCovariance().inverse();
  std::map<int, Eigen::Vector3d> gradient;
  Eigen::Vector3d total = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < model.size(); ++i) {
    gradient.try_emplace(dives[i], Eigen::Vector3d::Zero());
    gradient[dives[i]] += information * fit.residuals[i];
    total += information * fit.residuals[i];
  }
  // Against one point's whitened residual (1) times the points.
  const double tolerance = 1e-6 * std::sqrt(information(0, 0)) * model.size();
  EXPECT_LT(gradient.at(1).norm(), tolerance);
  EXPECT_LT(gradient.at(3).norm(), tolerance);
  EXPECT_LT(total.norm(), tolerance);
  // Relative to dive 2: offset_d = bias_2 - bias_d, to within what the
  // noise allows. Not 7 mm (a 100-point mean): with the dives 35-40 m
  // apart an offset also absorbs the similarity's rotation and scale
  // error, by about that distance times theirs (5 cm seen). A sanity
  // bound; the conditions above are the test.
  for (const int dive : {1, 3}) {
    const Eigen::Vector3d expected = Biases().at(2) - Biases().at(dive);
    EXPECT_LT((fit.offsets.at(dive) - expected).norm(), 0.1) << dive;
  }
  const double dof = 3.0 * model.size() - 7.0 - 6.0;
  EXPECT_NEAR(fit.chi_square / dof, 1.0, 0.15);
}

TEST(EstimateSimilarityWithOffsets, OneGroupIsThePlainWeightedFit) {
  std::vector<Eigen::Vector3d> model, navigation;
  std::vector<Eigen::Matrix3d> covariances;
  std::vector<int> dives;
  MakeProblem(false, &model, &navigation, &covariances, &dives);
  // Dive 1 alone, which has no bias: exact.
  model.resize(100);
  navigation.resize(100);
  covariances.resize(100);
  dives.resize(100);
  const SimilarityWithOffsets fit = EstimateSimilarityWithOffsets(
      model, navigation, covariances, dives, 1, SimilarityWithOffsetsOptions());
  EXPECT_TRUE(fit.converged);
  EXPECT_EQ(fit.offsets.size(), 1u);
  EXPECT_NEAR(fit.b_from_a.scale, TrueSim3().scale, 1e-9);
}

// The offsets' zero-mean prior (the adjustment's --Dive.offset_sigma) pulls
// them in: a tight one holds them at zero, a loose one barely moves them.
TEST(EstimateSimilarityWithOffsets, AnOffsetPriorPullsTheOffsetsToZero) {
  std::vector<Eigen::Vector3d> model, navigation;
  std::vector<Eigen::Matrix3d> covariances;
  std::vector<int> dives;
  MakeProblem(true, &model, &navigation, &covariances, &dives);
  SimilarityWithOffsetsOptions options;
  const SimilarityWithOffsets free = EstimateSimilarityWithOffsets(
      model, navigation, covariances, dives, 1, options);
  options.offset_prior_sigma = 10.0;
  const SimilarityWithOffsets loose = EstimateSimilarityWithOffsets(
      model, navigation, covariances, dives, 1, options);
  options.offset_prior_sigma = 1e-6;
  const SimilarityWithOffsets tight = EstimateSimilarityWithOffsets(
      model, navigation, covariances, dives, 1, options);
  for (const int dive : {2, 3}) {
    EXPECT_LT((loose.offsets.at(dive) - free.offsets.at(dive)).norm(), 1e-4);
    EXPECT_GT((loose.offsets.at(dive) - free.offsets.at(dive)).norm(), 0.0);
    EXPECT_LT(tight.offsets.at(dive).norm(), 1e-4);
  }
  options.offset_prior_sigma = -1.0;
  ExpectErrorContaining([&] { options.Check(); }, "offset_prior_sigma");
}

// Two dives, each one straight line, the lines parallel: dive 2's offset
// across the lines trades with the rotation about them.
TEST(EstimateSimilarityWithOffsets, RefusesParallelLinesAsUndetermined) {
  std::vector<Eigen::Vector3d> model, navigation;
  std::vector<Eigen::Matrix3d> covariances;
  std::vector<int> dives;
  for (int dive = 1; dive <= 2; ++dive) {
    for (int k = 0; k < 20; ++k) {
      const Eigen::Vector3d world(1.0 * k, 10.0 * dive, -50.0);
      model.push_back(TrueSim3().Inverse() * world);
      navigation.push_back(world);
      covariances.push_back(NavCovariance());
      dives.push_back(dive);
    }
  }
  ExpectErrorContaining(
      [&] {
        EstimateSimilarityWithOffsets(model, navigation, covariances, dives, 1,
                                      SimilarityWithOffsetsOptions());
      },
      "undetermined");
}

TEST(EstimateSimilarityWithOffsets, RefusesBadInput) {
  std::vector<Eigen::Vector3d> model, navigation;
  std::vector<Eigen::Matrix3d> covariances;
  std::vector<int> dives;
  MakeProblem(false, &model, &navigation, &covariances, &dives);
  const SimilarityWithOffsetsOptions options;
  ExpectErrorContaining(
      [&] {
        EstimateSimilarityWithOffsets(model, navigation, covariances, dives, 4,
                                      options);
      },
      "reference group 4 has no points");
  std::vector<int> short_dives(dives.begin(), dives.end() - 1);
  ExpectErrorContaining(
      [&] {
        EstimateSimilarityWithOffsets(model, navigation, covariances,
                                      short_dives, 1, options);
      },
      "300 points but 299 group numbers");
  covariances[5] = -NavCovariance();
  ExpectErrorContaining(
      [&] {
        EstimateSimilarityWithOffsets(model, navigation, covariances, dives, 1,
                                      options);
      },
      "not symmetric positive definite");
  SimilarityWithOffsetsOptions none;
  none.max_iterations = 0;
  ExpectErrorContaining([&] { none.Check(); }, "max_iterations must be >= 1");
}

}  // namespace
}  // namespace uw
