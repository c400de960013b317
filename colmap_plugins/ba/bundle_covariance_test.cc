#include "colmap_plugins/ba/bundle_covariance.h"

#include <algorithm>
#include <cmath>
#include <iostream>

#include <Eigen/Geometry>

#include <gtest/gtest.h>

#include "colmap_plugins/ba/test_scene.h"
#include "common/util/error_testing.h"

namespace uw {
namespace {

Eigen::Vector3d RotationVector(const Eigen::Matrix3d& rotation) {
  const Eigen::AngleAxisd angle_axis(rotation);
  return angle_axis.angle() * angle_axis.axis();
}

struct Nees {
  double pose_sum = 0.0;
  int poses = 0;
  double point_sum = 0.0;
  int points = 0;
  double Pose() const { return pose_sum / poses; }
  double Point() const { return point_sum / points; }
};

// e^T Sigma^-1 e of every free pose (6 DOF) and point of `estimate` against
// the truth.
void AddNees(const Reconstruction& estimate, const Reconstruction& truth,
             const BundleCovariance& covariance, Nees* nees) {
  for (const ImageCovariance& image : covariance.images) {
    if (image.held) continue;
    const Image& a = *estimate.FindImage(image.image_id);
    const Image& b = *truth.FindImage(image.image_id);
    Eigen::Matrix<double, 6, 1> error;
    // world_from_cam_estimate = Exp(w) world_from_cam_truth.
    error.head<3>() =
        RotationVector(a.cam_from_world.RotationMatrix().transpose() *
                       b.cam_from_world.RotationMatrix());
    error.tail<3>() = a.ProjectionCenter() - b.ProjectionCenter();
    const Eigen::LDLT<Eigen::Matrix<double, 6, 6>> ldlt(image.rotation_center);
    if (ldlt.rcond() < 1e-12) continue;  // the image holding one coordinate
    nees->pose_sum += error.dot(ldlt.solve(error));
    ++nees->poses;
  }
  for (const PointCovariance& point : covariance.points) {
    const Eigen::Vector3d error = estimate.FindPoint3D(point.point3D_id)->xyz -
                                  truth.FindPoint3D(point.point3D_id)->xyz;
    nees->point_sum += error.dot(point.xyz.ldlt().solve(error));
    ++nees->points;
  }
}

NavBundleAdjustmentOptions RefinedIntrinsics() {
  NavBundleAdjustmentOptions options;  // focal length and k1 refined
  options.num_threads = 1;

  options.weight_px_per_m = 0.5 / 0.3;  // the scene's sigma_v / sigma_n
  return options;
}

// Monte Carlo: re-adjustments of one survey under fresh pixel and
// navigation noise; the mean NEES must be the dimension (6 for poses, 3 for
// points) when the covariance is right. Here 30 trials per gauge on the
// unit test scene with the intrinsics known: its flat constant-altitude
// strip does not determine the focal length (sigma_f ~ 25 %), and there the
// estimate is biased far beyond what any linearised covariance describes
// (see NearlyDegenerateSelfCalibrationIsFlagged).
TEST(BundleCovariance, MonteCarloNeesMatchesTheDimensions) {
  constexpr int kTrials = 30;
  NavBundleAdjustmentOptions adjuster = RefinedIntrinsics();
  adjuster.refine_focal_length = false;
  adjuster.refine_extra_params = false;
  for (const CovarianceGauge gauge :
       {CovarianceGauge::kPriors, CovarianceGauge::kHeld}) {
    Nees nees;
    for (int trial = 0; trial < kTrials; ++trial) {
      test::TestSceneOptions scene_options;
      scene_options.num_lines = 3;
      scene_options.images_per_line = 6;
      scene_options.num_points = 600;
      scene_options.seed = 100 + trial;
      const test::TestScene scene = test::MakeTestScene(scene_options);
      Reconstruction model = scene.observed;
      test::Perturb(0.01, 0.002, 200 + trial, &model);
      std::vector<ImagePosePrior> priors;
      if (gauge == CovarianceGauge::kPriors) {
        priors = scene.priors;
      } else {
        for (const int i : {0, 1}) {
          model.Images()[i].cam_from_world =
              scene.truth.Images()[i].cam_from_world;
        }
      }
      AdjustWithNavigation(adjuster, priors, nullptr, {}, &model);
      BundleCovarianceOptions options;
      options.gauge = gauge;
      const BundleCovariance covariance = EstimateBundleCovariance(
          adjuster, priors, nullptr, {}, model, options);
      AddNees(model, scene.truth, covariance, &nees);
    }
    std::cout << "[ figures ] " << CovarianceGaugeName(gauge) << ": mean NEES "
              << nees.Pose() << " over " << nees.poses << " poses (6), "
              << nees.Point() << " over " << nees.points << " points (3), "
              << kTrials << " trials\n";
    EXPECT_NEAR(nees.Pose(), 6.0, 0.6);
    EXPECT_NEAR(nees.Point(), 3.0, 0.3);
  }
}

TEST(BundleCovariance, PixelSigmaIsEstimatedWithTheRedundancy) {
  test::TestSceneOptions scene_options;
  scene_options.pixel_sigma = 0.8;
  const test::TestScene scene = test::MakeTestScene(scene_options);
  Reconstruction model = scene.observed;
  // k1 refined, f held: on this scene the adjustment run to convergence
  // (since 2026-12-07 it no longer stops at 100 iterations) moves f to
  // 55 px (800 true) at the cost it has at 800, and to 548 px with 5 cm
  // navigation and a 0.5 m vertical wiggle of the track; stopped at 100
  // iterations it had stayed near the truth, which this test relied on.
  // Why f is that free here is not understood yet (docs/dev/issue17_plan.md).
  NavBundleAdjustmentOptions adjuster = RefinedIntrinsics();
  adjuster.refine_focal_length = false;
  const NavBundleAdjustmentReport report =
      AdjustWithNavigation(adjuster, scene.priors, nullptr, {}, &model);
  EXPECT_EQ(report.termination, "CONVERGENCE");
  const BundleCovariance estimated =
      EstimateBundleCovariance(adjuster, scene.priors, nullptr, {}, model, {});
  EXPECT_NEAR(estimated.pixel_sigma_px, 0.8, 0.04);
  BundleCovarianceOptions given;
  given.pixel_sigma_px = 1.6;
  const BundleCovariance doubled = EstimateBundleCovariance(
      adjuster, scene.priors, nullptr, {}, model, given);
  EXPECT_EQ(doubled.pixel_sigma_source, "given");
  // Twice the pixel noise: the images' share of the information is a
  // quarter, so what only the images determine (k1) has nearly 4x the
  // variance. (A point's variance in the world is mostly the datum's,
  // which the 0.3 m navigation holds: it barely grows.)
  ASSERT_EQ(estimated.cameras.size(), 1u);
  EXPECT_GT(doubled.cameras[0].params(0, 0),
            3.5 * estimated.cameras[0].params(0, 0));
  EXPECT_EQ(estimated.cameras[0].param_indices, (std::vector<int>{3}));
  EXPECT_EQ(estimated.cameras[0].params.rows(), 1);
}

// The priors as the adjustment weighted them: a weight lambda makes their
// sigmas stated x sigma_px / (lambda sigma_n), exactly as if stated so.
TEST(BundleCovariance, NavWeightTakesThePriorsAsTheAdjustmentWeightedThem) {
  const test::TestScene scene = test::MakeTestScene({});
  Reconstruction model = scene.observed;
  NavBundleAdjustmentOptions adjuster = RefinedIntrinsics();
  adjuster.weight_px_per_m *= 3.0;  // navigation trusted 3x its sigmas
  AdjustWithNavigation(adjuster, scene.priors, nullptr, {}, &model);
  BundleCovarianceOptions weighted;
  weighted.nav_weight_px_per_m = adjuster.weight_px_per_m;
  const BundleCovariance a = EstimateBundleCovariance(
      adjuster, scene.priors, nullptr, {}, model, weighted);
  EXPECT_NEAR(
      a.nav_sigma_scale,
      a.pixel_sigma_px / (adjuster.weight_px_per_m * NavSigma(scene.priors)),
      1e-15);
  EXPECT_LT(a.nav_sigma_scale, 0.5);

  std::vector<ImagePosePrior> scaled = scene.priors;
  for (ImagePosePrior& prior : scaled) {
    prior.position_covariance *= a.nav_sigma_scale * a.nav_sigma_scale;
    prior.rotation_covariance *= a.nav_sigma_scale * a.nav_sigma_scale;
  }
  BundleCovarianceOptions as_stated;
  as_stated.pixel_sigma_px = a.pixel_sigma_px;
  const BundleCovariance b =
      EstimateBundleCovariance(adjuster, scaled, nullptr, {}, model, as_stated);
  EXPECT_EQ(b.nav_sigma_scale, 1.0);
  ASSERT_EQ(a.images.size(), b.images.size());
  for (size_t i = 0; i < a.images.size(); ++i) {
    EXPECT_LT(
        (a.images[i].rotation_center - b.images[i].rotation_center).norm(),
        1e-9 * b.images[i].rotation_center.norm());
  }

  // As stated, the navigation holds the datum 3x less tightly.
  const BundleCovariance stated =
      EstimateBundleCovariance(adjuster, scene.priors, nullptr, {}, model, {});
  EXPECT_GT(stated.images[0].CenterCovariance().trace(),
            2.0 * a.images[0].CenterCovariance().trace());

  weighted.nav_weight_px_per_m = -1.0;
  EXPECT_THROW(EstimateBundleCovariance(adjuster, scene.priors, nullptr, {},
                                        model, weighted),
               Error);
}

// A soft rig's terms enter the adjustment in pixels by the same lambda
// sigma_n as the priors (nav_bundle_adjuster.h), so a navigation weighted 3x
// its sigmas weighs the rig 3x too: the covariance must take the rig's
// sigmas with the priors' factor, exactly as if both were stated so.
TEST(BundleCovariance, SoftRigSigmasScaleAsTheAdjustmentWeightedThem) {
  test::TestSceneOptions scene_options;
  scene_options.rig = true;
  const test::TestScene scene = test::MakeTestScene(scene_options);
  Reconstruction model = scene.observed;
  NavBundleAdjustmentOptions adjuster = test::FixedIntrinsics();
  adjuster.weight_px_per_m = 3.0 * 0.5 / 0.3;
  AdjustWithNavigation(adjuster, scene.priors, &scene.rig, scene.image_times,
                       &model);
  BundleCovarianceOptions weighted;
  weighted.nav_weight_px_per_m = adjuster.weight_px_per_m;
  const BundleCovariance a = EstimateBundleCovariance(
      adjuster, scene.priors, &scene.rig, scene.image_times, model, weighted);
  const double factor = a.nav_sigma_scale;
  ASSERT_LT(factor, 0.5);

  std::vector<ImagePosePrior> scaled = scene.priors;
  for (ImagePosePrior& prior : scaled) {
    prior.position_covariance *= factor * factor;
    prior.rotation_covariance *= factor * factor;
  }
  SoftRig scaled_rig = scene.rig;
  for (SoftRigCamera& camera : scaled_rig.cameras) {
    camera.rotation_sigma_rad *= factor;
    camera.translation_sigma_m *= factor;
  }
  BundleCovarianceOptions as_stated;
  as_stated.pixel_sigma_px = a.pixel_sigma_px;
  const BundleCovariance b = EstimateBundleCovariance(
      adjuster, scaled, &scaled_rig, scene.image_times, model, as_stated);
  // The rig left as stated: its images' relative poses held 1/factor less
  // tightly than the adjustment held them.
  const BundleCovariance rig_as_stated = EstimateBundleCovariance(
      adjuster, scaled, &scene.rig, scene.image_times, model, as_stated);
  ASSERT_EQ(a.images.size(), b.images.size());
  ASSERT_EQ(a.images.size(), model.Images().size());
  double worst = 0.0;
  double worst_rig_as_stated = 0.0;
  for (size_t i = 0; i < a.images.size(); ++i) {
    const double norm = b.images[i].rotation_center.norm();
    worst = std::max(
        worst,
        (a.images[i].rotation_center - b.images[i].rotation_center).norm() /
            norm);
    worst_rig_as_stated = std::max(
        worst_rig_as_stated,
        (rig_as_stated.images[i].rotation_center - b.images[i].rotation_center)
                .norm() /
            norm);
  }
  std::cout << "[ figures ] rig: factor " << factor
            << ", largest relative difference of a pose covariance from the "
               "sigmas stated so "
            << worst << ", with the rig as stated " << worst_rig_as_stated
            << "\n";
  EXPECT_LT(worst, 1e-9);
  EXPECT_GT(worst_rig_as_stated, 1e-3);
}

TEST(BundleCovariance, NearlyDegenerateSelfCalibrationIsFlagged) {
  const test::TestScene scene = test::MakeTestScene({});
  Reconstruction model = scene.observed;
  AdjustWithNavigation(RefinedIntrinsics(), scene.priors, nullptr, {}, &model);
  const BundleCovariance refined = EstimateBundleCovariance(
      RefinedIntrinsics(), scene.priors, nullptr, {}, model, {});
  ASSERT_EQ(refined.warnings.size(), 1u);
  EXPECT_NE(refined.warnings[0].find("camera 1: focal length sigma"),
            std::string::npos);
  const BundleCovariance fixed = EstimateBundleCovariance(
      test::FixedIntrinsics(), scene.priors, nullptr, {}, model, {});
  EXPECT_TRUE(fixed.warnings.empty());
}

TEST(BundleCovariance, FreeNetworkHasTheSmallestTrace) {
  test::TestSceneOptions scene_options;
  scene_options.num_lines = 2;
  scene_options.images_per_line = 6;
  scene_options.num_points = 400;
  const test::TestScene scene = test::MakeTestScene(scene_options);
  Reconstruction model = scene.observed;
  AdjustWithNavigation(RefinedIntrinsics(), {}, nullptr, {}, &model);
  BundleCovarianceOptions held;
  held.gauge = CovarianceGauge::kHeld;
  BundleCovarianceOptions free = held;
  free.gauge = CovarianceGauge::kFreeNetwork;
  const BundleCovariance a = EstimateBundleCovariance(RefinedIntrinsics(), {},
                                                      nullptr, {}, model, held);
  const BundleCovariance b = EstimateBundleCovariance(RefinedIntrinsics(), {},
                                                      nullptr, {}, model, free);
  double trace_held = 0.0;
  double trace_free = 0.0;
  for (size_t j = 0; j < a.points.size(); ++j) {
    trace_held += a.points[j].xyz.trace();
    trace_free += b.points[j].xyz.trace();
  }
  EXPECT_TRUE(a.images[0].held);
  EXPECT_FALSE(b.images[0].held);
  EXPECT_GT(b.images[0].CenterCovariance().trace(), 0.0);
  EXPECT_LT(trace_free, trace_held);
}

// --Covariance.method ceres_sparse_qr: ceres::Covariance on the adjuster's
// own problem gives the same marginals (the benchmark's peer computes what
// ours does), held and prior gauges, intrinsics refined.
TEST(BundleCovariance, CeresMethodGivesTheSameMarginals) {
  test::TestSceneOptions scene_options;
  scene_options.num_lines = 2;
  scene_options.images_per_line = 6;
  scene_options.num_points = 400;
  const test::TestScene scene = test::MakeTestScene(scene_options);
  for (const CovarianceGauge gauge :
       {CovarianceGauge::kHeld, CovarianceGauge::kPriors}) {
    const std::vector<ImagePosePrior> priors =
        gauge == CovarianceGauge::kPriors ? scene.priors
                                          : std::vector<ImagePosePrior>();
    Reconstruction model = scene.observed;
    AdjustWithNavigation(RefinedIntrinsics(), priors, nullptr, {}, &model);
    BundleCovarianceOptions schur;
    schur.gauge = gauge;
    BundleCovarianceOptions ceres = schur;
    ceres.method = CovarianceMethod::kCeresSparseQr;
    const BundleCovariance a = EstimateBundleCovariance(
        RefinedIntrinsics(), priors, nullptr, {}, model, schur);
    const BundleCovariance b = EstimateBundleCovariance(
        RefinedIntrinsics(), priors, nullptr, {}, model, ceres);
    EXPECT_EQ(b.method, CovarianceMethod::kCeresSparseQr);
    ASSERT_EQ(a.images.size(), b.images.size());
    ASSERT_EQ(a.points.size(), b.points.size());
    double worst = 0.0;
    for (size_t i = 0; i < a.images.size(); ++i) {
      if (a.images[i].held) continue;
      worst = std::max(
          worst,
          (a.images[i].rotation_center - b.images[i].rotation_center).norm() /
              a.images[i].rotation_center.norm());
    }
    worst = std::max(worst, (a.cameras[0].params - b.cameras[0].params).norm() /
                                a.cameras[0].params.norm());
    for (size_t j = 0; j < a.points.size(); ++j) {
      worst = std::max(worst, (a.points[j].xyz - b.points[j].xyz).norm() /
                                  a.points[j].xyz.norm());
    }
    std::cout << "[ figures ] " << CovarianceGaugeName(gauge)
              << ": ceres_sparse_qr against schur, worst relative block "
                 "difference "
              << worst << "\n";
    // The flat strip's self-calibration is ill-conditioned (sigma_f ~ 25 %):
    // the engines agree to ~1e-7 there, not to 1e-9
    // (schur_covariance_test.cc, IllConditionedProblemsLoseAt1e8To1e7).
    EXPECT_LT(worst, 1e-6);
  }
  BundleCovarianceOptions free;
  free.gauge = CovarianceGauge::kFreeNetwork;
  free.method = CovarianceMethod::kCeresSparseQr;
  ExpectErrorContaining([&] { free.Check(); }, "cannot give the free network");
  BundleCovarianceOptions draws;
  draws.method = CovarianceMethod::kCeresSparseQr;
  draws.num_samples = 10;
  ExpectErrorContaining([&] { draws.Check(); }, "marginals only");
  EXPECT_EQ(CovarianceMethodFromName(
                CovarianceMethodName(CovarianceMethod::kCeresSparseQr)),
            CovarianceMethod::kCeresSparseQr);
  ExpectErrorContaining([] { CovarianceMethodFromName("dense"); },
                        "unknown covariance method 'dense'");
}

TEST(BundleCovariance, RefusesWhatHasNoCovariance) {
  const test::TestScene scene = test::MakeTestScene({});
  const NavBundleAdjustmentOptions adjuster = RefinedIntrinsics();
  BundleCovarianceOptions held;
  held.gauge = CovarianceGauge::kHeld;
  ExpectErrorContaining(
      [&] {
        EstimateBundleCovariance(adjuster, {}, nullptr, {}, scene.observed, {});
      },
      "the gauge is not fixed");
  ExpectErrorContaining(
      [&] {
        EstimateBundleCovariance(adjuster, scene.priors, nullptr, {},
                                 scene.observed, held);
      },
      "fix it twice");
  {
    // An image that keeps 2 of its points.
    Reconstruction model = scene.observed;
    Image& image = model.Images()[5];
    int kept = 0;
    for (size_t k = 0; k < image.points2D.size(); ++k) {
      Point2D& point2D = image.points2D[k];
      if (!point2D.HasPoint3D() || ++kept <= 2) continue;
      std::vector<TrackElement>& track =
          model.Points3D()[point2D.point3D_id - 1].track;
      track.erase(std::remove_if(track.begin(), track.end(),
                                 [&](const TrackElement& element) {
                                   return element.image_id == image.image_id;
                                 }),
                  track.end());
      point2D.point3D_id = kInvalidPoint3DId;
    }
    ExpectErrorContaining(
        [&] {
          EstimateBundleCovariance(adjuster, scene.priors, nullptr, {}, model,
                                   {});
        },
        "image 6 (img6.png) sees 2 points");
  }
  {
    Reconstruction model = scene.observed;
    Point3D& point = model.Points3D()[3];
    const TrackElement keep = point.track[0];
    for (size_t k = 1; k < point.track.size(); ++k) {
      model.Images()[point.track[k].image_id - 1]
          .points2D[point.track[k].point2D_idx]
          .point3D_id = kInvalidPoint3DId;
    }
    point.track = {keep};
    ExpectErrorContaining(
        [&] {
          EstimateBundleCovariance(adjuster, scene.priors, nullptr, {}, model,
                                   {});
        },
        "point " + std::to_string(point.point3D_id) + " is seen by 1 image");
  }
  {
    Reconstruction model = scene.observed;
    model.Points3D()[7].xyz.x() = std::nan("");
    ExpectErrorContaining(
        [&] {
          EstimateBundleCovariance(adjuster, scene.priors, nullptr, {}, model,
                                   {});
        },
        "point " + std::to_string(model.Points3D()[7].point3D_id) +
            " has a non-finite position");
  }
}

}  // namespace
}  // namespace uw
