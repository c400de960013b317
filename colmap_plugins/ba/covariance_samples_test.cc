#include "colmap_plugins/ba/covariance_samples.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>

#include <Eigen/Geometry>

#include <gtest/gtest.h>

#include "colmap_plugins/ba/bundle_covariance.h"
#include "colmap_plugins/ba/covariance_files.h"
#include "colmap_plugins/ba/test_scene.h"
#include "common/util/error_testing.h"
#include "common/util/file.h"
#include "tests/support/process.h"

namespace uw {
namespace {

namespace fs = std::filesystem;

test::TestScene SmallScene(unsigned seed) {
  test::TestSceneOptions options;
  options.num_lines = 3;
  options.images_per_line = 6;
  options.num_points = 600;
  options.seed = seed;
  return test::MakeTestScene(options);
}

// Draws laid out for `model`: every image and point, no intrinsics.
CovarianceSamples EmptyDraws(const Reconstruction& model, int count) {
  CovarianceSamples samples;
  for (const Image& image : model.Images()) {
    samples.image_ids.push_back(image.image_id);
  }
  for (const Point3D& point : model.Points3D()) {
    samples.point3D_ids.push_back(point.point3D_id);
  }
  samples.log_scale = Eigen::VectorXd::Zero(count);
  samples.camera_deltas.resize(0, count);
  samples.image_deltas =
      Eigen::MatrixXf::Zero(6 * model.Images().size(), count);
  samples.point_deltas =
      Eigen::MatrixXf::Zero(3 * model.Points3D().size(), count);
  samples.Index();
  return samples;
}

TEST(CovarianceSamples, ASimilarityIsRemovedAndItsScaleKept) {
  const Reconstruction model = SmallScene(1).truth;
  CovarianceSamples samples = EmptyDraws(model, 2);
  // Draw 0: the whole model moved by a first-order similarity, delta =
  // omega x x + tau + sigma x (draw 1 stays zero).
  const double log_scale = 0.004;
  const Eigen::Vector3d omega(2e-2, -1e-2, 3e-2);
  const Eigen::Vector3d shift(0.05, -0.02, 0.03);
  const auto move = [&](const Eigen::Vector3d& x) {
    return Eigen::Vector3d(omega.cross(x) + shift + log_scale * x);
  };
  for (size_t j = 0; j < model.Points3D().size(); ++j) {
    samples.point_deltas.block<3, 1>(3 * j, 0) =
        move(model.Points3D()[j].xyz).cast<float>();
  }
  for (size_t i = 0; i < model.Images().size(); ++i) {
    samples.image_deltas.block<3, 1>(6 * i, 0) = omega.cast<float>();
    samples.image_deltas.block<3, 1>(6 * i + 3, 0) =
        move(model.Images()[i].ProjectionCenter()).cast<float>();
  }
  SeparateSimilarity(model, &samples);
  EXPECT_NEAR(samples.log_scale(0), log_scale, 1e-7);
  EXPECT_NEAR(samples.log_scale(1), 0.0, 1e-15);
  // What is left is rounding: float deltas of centimetres.
  EXPECT_LT(samples.point_deltas.cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_LT(samples.image_deltas.cwiseAbs().maxCoeff(), 1e-6);
  // Collinear points fit no similarity.
  Reconstruction line = model;
  for (Point3D& point : line.Points3D()) point.xyz.tail<2>().setZero();
  ExpectErrorContaining([&] { SeparateSimilarity(line, &samples); },
                        "collinear");
}

TEST(CovarianceSamples, TheFileRoundTripsAndRefusesAnotherModel) {
  const test::TestScene scene = SmallScene(2);
  Reconstruction model = scene.observed;
  NavBundleAdjustmentOptions adjuster;  // focal length and k1 refined
  adjuster.num_threads = 1;
  AdjustWithNavigation(adjuster, scene.priors, nullptr, {}, &model);
  BundleCovarianceOptions options;
  options.num_samples = 7;
  options.sample_seed = 3;
  const BundleCovariance covariance = EstimateBundleCovariance(
      adjuster, scene.priors, nullptr, {}, model, options);
  const CovarianceSamples& samples = covariance.samples;
  ASSERT_EQ(samples.NumSamples(), 7);
  ASSERT_EQ(samples.camera_ids.size(), 1u);
  EXPECT_EQ(samples.camera_param_indices[0], (std::vector<int>{0, 3}));
  EXPECT_EQ(samples.CameraRow(samples.camera_ids[0]), 0);
  EXPECT_EQ(samples.camera_deltas.rows(), 2);
  // The focal length's draws have its marginal's size.
  const double sigma_f = std::sqrt(covariance.cameras[0].params(0, 0));
  EXPECT_LT(samples.camera_deltas.row(0).cwiseAbs().maxCoeff(), 5 * sigma_f);
  EXPECT_GT(samples.camera_deltas.row(0).cwiseAbs().maxCoeff(), 0.1 * sigma_f);

  const fs::path folder = testing::FreshTestDir("covariance_samples_test");
  WriteCovarianceFiles(covariance, model, folder / "cov");
  const fs::path path = folder / "cov" / "samples.bin";
  const CovarianceSamples back = ReadCovarianceSamples(path, model);
  EXPECT_EQ(back.log_scale, samples.log_scale);
  EXPECT_EQ(back.camera_deltas, samples.camera_deltas);
  EXPECT_EQ(back.image_deltas, samples.image_deltas);
  EXPECT_EQ(back.point_deltas, samples.point_deltas);
  EXPECT_EQ(back.point3D_ids, samples.point3D_ids);
  const point3D_t id = samples.point3D_ids[5];
  EXPECT_EQ(back.PointRow(id), 15);

  Reconstruction other = model;
  other.Points3D().pop_back();
  ExpectErrorContaining([&] { ReadCovarianceSamples(path, other); },
                        "belongs to another model");
  const std::string bytes = ReadFileToString(path);
  std::ofstream(folder / "short.bin", std::ios::binary)
      << bytes.substr(0, bytes.size() - 5);
  ExpectErrorContaining(
      [&] { ReadCovarianceSamples(folder / "short.bin", model); },
      "bytes of draws, expected");
  // Written again without draws: the old samples.bin must not pass for the
  // new covariance's.
  BundleCovariance without = covariance;
  without.samples = CovarianceSamples();
  WriteCovarianceFiles(without, model, folder / "cov");
  EXPECT_FALSE(fs::exists(path));
}

// The draws against the truth, over independent surveys: what is left
// after the similarity (each point's deformation, and ratios of distances,
// which no similarity changes) and the similarity's scale (fixed here by
// 0.3 m navigation priors) must err by as much as the draws spread: mean
// NEES 3 per point, mean z^2 1. An exact (Umeyama) removal of the
// similarity from these first-order draws fails it: its second-order terms
// inflate the deformation (point NEES ~1, ratio z^2 ~0.2).
TEST(CovarianceSamples, DrawsSpreadAsTheEstimatesErr) {
  constexpr int kTrials = 30;
  NavBundleAdjustmentOptions adjuster = test::FixedIntrinsics();
  adjuster.weight_px_per_m = 0.5 / 0.3;  // the scene's sigma_v / sigma_n
  double ratio_z2 = 0.0;
  int ratios = 0;
  double scale_z2 = 0.0;
  double point_nees = 0.0;
  int points = 0;
  for (int trial = 0; trial < kTrials; ++trial) {
    const test::TestScene scene = SmallScene(300 + trial);
    Reconstruction model = scene.observed;
    test::Perturb(0.01, 0.002, 400 + trial, &model);
    AdjustWithNavigation(adjuster, scene.priors, nullptr, {}, &model);
    BundleCovarianceOptions options;
    options.num_samples = 200;
    options.sample_seed = trial;
    const BundleCovariance covariance = EstimateBundleCovariance(
        adjuster, scene.priors, nullptr, {}, model, options);
    const CovarianceSamples& samples = covariance.samples;
    const int num_points = static_cast<int>(samples.point3D_ids.size());
    const auto xyz = [&](const Reconstruction& r, int j) {
      return r.FindPoint3D(samples.point3D_ids[j])->xyz;
    };
    const auto drawn = [&](int j, int s) {
      return Eigen::Vector3d(
          xyz(model, j) +
          samples.point_deltas.block<3, 1>(3 * j, s).cast<double>());
    };
    // Four pairs of points a quarter of the list apart.
    for (int k = 0; k < 4; ++k) {
      const int a = k * num_points / 8;
      const int b = a + num_points / 2;
      const int c = a + num_points / 4;
      const int d = (b + num_points / 4) % num_points;
      const auto ratio = [&](const auto& at) {
        return (at(a) - at(b)).norm() / (at(c) - at(d)).norm();
      };
      const double estimate = ratio([&](int j) { return xyz(model, j); });
      const double truth = ratio([&](int j) { return xyz(scene.truth, j); });
      double sum2 = 0.0;
      for (int s = 0; s < samples.NumSamples(); ++s) {
        const double r = ratio([&](int j) { return drawn(j, s); });
        sum2 += (r - estimate) * (r - estimate);
      }
      const double sigma = std::sqrt(sum2 / samples.NumSamples());
      ratio_z2 += std::pow((estimate - truth) / sigma, 2);
      ++ratios;
    }
    // The estimate's scale against the truth: Umeyama estimated -> truth.
    Eigen::Matrix3Xd from(3, num_points);
    Eigen::Matrix3Xd to(3, num_points);
    for (int j = 0; j < num_points; ++j) {
      from.col(j) = xyz(model, j);
      to.col(j) = xyz(scene.truth, j);
    }
    const Eigen::Matrix4d t = Eigen::umeyama(from, to, true);
    for (int j = 0; j < num_points; ++j) {
      const Eigen::Vector3d error = t.topLeftCorner<3, 3>() * from.col(j) +
                                    t.topRightCorner<3, 1>() - to.col(j);
      const Eigen::MatrixXd deltas =
          samples.point_deltas.middleRows<3>(3 * j).cast<double>();
      const Eigen::Matrix3d spread =
          deltas * deltas.transpose() / samples.NumSamples();
      point_nees += error.dot(spread.ldlt().solve(error));
      ++points;
    }
    {  // DEBUG
      double nees = 0, trace_ratio = 0;
      for (int j = 0; j < num_points; ++j) {
        Eigen::Vector3d e =
            (t.topLeftCorner<3, 3>() * from.col(j) + t.topRightCorner<3, 1>()) -
            to.col(j);
        Eigen::Matrix3d c = Eigen::Matrix3d::Zero();
        for (int s = 0; s < samples.NumSamples(); ++s) {
          Eigen::Vector3d d =
              samples.point_deltas.block<3, 1>(3 * j, s).cast<double>();
          c += d * d.transpose() / samples.NumSamples();
        }
        nees += e.dot(c.ldlt().solve(e));
        trace_ratio += c.trace() / covariance.points[j].xyz.trace();
      }
      std::cout << "DEBUG px " << covariance.pixel_sigma_px << " "
                << covariance.pixel_sigma_source << " deformation nees "
                << nees / num_points << " trace ratio "
                << trace_ratio / num_points << "\n";
    }
    const double log_scale_error =
        -std::log(std::cbrt(t.topLeftCorner<3, 3>().determinant()));
    const double sigma =
        std::sqrt(samples.log_scale.squaredNorm() / samples.NumSamples());
    scale_z2 += std::pow(log_scale_error / sigma, 2);
  }
  std::cout << "[ figures ] mean NEES of the deformation of " << points
            << " points: " << point_nees / points << " (3); mean z^2 of "
            << ratios << " distance ratios: " << ratio_z2 / ratios << "; of "
            << kTrials << " scales (navigation priors): " << scale_z2 / kTrials
            << " (1 if the draws are right)\n";
  // chi^2 means: the ratios' sigma of the mean z^2 is sqrt(2 / 120) = 0.13,
  // the scales' sqrt(2 / 30) = 0.26; bounds at ~3 of them. The points are
  // correlated within a survey: 30 surveys bound their mean NEES looser.
  EXPECT_NEAR(point_nees / points, 3.0, 0.45);
  EXPECT_NEAR(ratio_z2 / ratios, 1.0, 0.4);
  EXPECT_NEAR(scale_z2 / kTrials, 1.0, 0.8);
}

}  // namespace
}  // namespace uw
