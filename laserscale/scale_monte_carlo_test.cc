#include "laserscale/scale_monte_carlo.h"

#include <cmath>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "common/mesh/test_meshes.h"
#include "experiments/laser_experiment.h"
#include "sim/laser.h"

#include "sim/generate.h"

namespace uw {
namespace {

Camera TestCamera() { return sim::SimConfig::DefaultCamera(); }

// A wall 3 m in front of the camera, tilted 20 degrees, with a 10 cm step
// (relief) across its middle; the world frame is the camera's turned and
// moved.
struct Scene {
  TriangleMesh world_mesh;
  Rigid3d cam_from_world;
};
Scene MakeScene() {
  Scene scene;
  const double tilt = 20.0 * M_PI / 180.0;
  const Eigen::Vector3d u(std::cos(tilt), 0.0, std::sin(tilt));
  const Eigen::Vector3d v(0.0, 1.0, 0.0);
  const Eigen::Vector3d corner = Eigen::Vector3d(0, 0, 3) - 4.0 * u - 4.0 * v;
  AddGrid(corner, 8.0 * u, 4.0 * v, 16, 8, &scene.world_mesh);
  AddGrid(corner + 4.0 * v + Eigen::Vector3d(0, 0, 0.1), 8.0 * u, 4.0 * v, 16,
          8, &scene.world_mesh);
  const Eigen::Quaterniond rotation(
      Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, -2, 3).normalized()));
  const Eigen::Vector3d offset(2.0, 1.0, -5.0);
  for (Eigen::Vector3d& vertex : scene.world_mesh.vertices) {
    vertex = rotation * vertex + offset;
  }
  scene.cam_from_world.rotation = rotation.conjugate();
  scene.cam_from_world.translation = -(rotation.conjugate() * offset);
  return scene;
}

LaserSetup SetupC() {
  sim::LaserOptions options;
  options.setup = "C";
  return sim::TrueLaserSetup(options);
}

struct Case {
  SyntheticShot shot;
  TriangleMesh model_mesh;
};
Case MakeCase(const ShotNoise& noise, double model_scale, uint64_t seed) {
  const Scene scene = MakeScene();
  const RayCaster world_caster(scene.world_mesh);
  ShotOptions options;
  options.noise = noise;
  options.model_scale = model_scale;
  Case result{MakeSyntheticShot(world_caster, TestCamera(),
                                scene.cam_from_world, SetupC(), options, seed),
              ScaledMesh(scene.world_mesh, model_scale)};
  EXPECT_TRUE(result.shot.localized) << result.shot.problem;
  return result;
}

ShotNoise Noisy() {
  ShotNoise noise;
  noise.feature_px = 0.5;
  noise.spot_px = 0.5;
  noise.direction_deg = 0.05;
  noise.origin_m = 0.001;
  return noise;
}

TEST(EstimateImageScale, NoiseFreeEverySampleIsOneOverK) {
  for (const double k : {0.237, 4.2}) {
    const Case c = MakeCase(ShotNoise(), k, 1);
    const RayCaster caster(c.model_mesh);
    MonteCarloOptions options;
    options.num_iterations = 200;
    const ImageScaleResult result =
        EstimateImageScale(c.shot.image, 0, c.shot.calibration, caster,
                           ScaleMethod::kFum, options);
    ASSERT_TRUE(result.nominal);
    EXPECT_NEAR(*result.nominal * k, 1.0, 1e-9);
    EXPECT_EQ(result.monte_carlo.num_samples, 200u);
    EXPECT_NEAR(result.monte_carlo.p2_5 * k, 1.0, 1e-9);
    EXPECT_NEAR(result.monte_carlo.p97_5 * k, 1.0, 1e-9);
    EXPECT_TRUE(result.accepted) << result.rejection;
    ASSERT_EQ(result.items.size(), 4u);
    for (const ItemResult& item : result.items) {
      EXPECT_EQ(item.num_invalid, 0u);
      EXPECT_NEAR(item.monte_carlo.mean * k, 1.0, 1e-9);
    }
  }
}

TEST(EstimateImageScale, SameResultOnAnyThreadCount) {
  const Case c = MakeCase(Noisy(), 1.0, 2);
  const RayCaster caster(c.model_mesh);
  MonteCarloOptions options;
  options.num_iterations = 700;
  options.seed = 11;
  options.num_threads = 1;
  const ImageScaleResult one = EstimateImageScale(
      c.shot.image, 3, c.shot.calibration, caster, ScaleMethod::kFum, options);
  options.num_threads = 2;
  const ImageScaleResult two = EstimateImageScale(
      c.shot.image, 3, c.shot.calibration, caster, ScaleMethod::kFum, options);
  EXPECT_EQ(one.samples, two.samples);
  EXPECT_GT(one.monte_carlo.std_dev, 0.0);
  // Another image index or seed draws other numbers.
  const ImageScaleResult other = EstimateImageScale(
      c.shot.image, 4, c.shot.calibration, caster, ScaleMethod::kFum, options);
  EXPECT_NE(one.samples, other.samples);
}

// The linearized re-localization against a refinement to convergence on the
// same draws: sample by sample the same scales.
TEST(EstimateImageScale, LinearizedRelocalizationMatchesTheFullOne) {
  ShotNoise noise;
  noise.feature_px = 1.0;
  const Case c = MakeCase(noise, 1.0, 3);
  const RayCaster caster(c.model_mesh);
  MonteCarloOptions options;
  options.num_iterations = 400;
  options.sample_spots = false;
  options.sample_calibration = false;
  const ImageScaleResult linear = EstimateImageScale(
      c.shot.image, 0, c.shot.calibration, caster, ScaleMethod::kFum, options);
  options.exact_relocalization = true;
  const ImageScaleResult exact = EstimateImageScale(
      c.shot.image, 0, c.shot.calibration, caster, ScaleMethod::kFum, options);
  ASSERT_EQ(linear.samples.size(), exact.samples.size());
  double max_difference = 0.0;
  for (size_t i = 0; i < linear.samples.size(); ++i) {
    max_difference = std::max(max_difference,
                              std::abs(linear.samples[i] - exact.samples[i]));
  }
  EXPECT_GT(exact.monte_carlo.std_dev, 1e-5);
  EXPECT_LT(max_difference, 0.01 * exact.monte_carlo.std_dev);
  EXPECT_NEAR(linear.monte_carlo.std_dev / exact.monte_carlo.std_dev, 1.0,
              0.01);
}

// Draws of the model in which every point and the surface move by one
// vector d per draw: `num_draws` columns, d of norm about `step`.
ImageModelDraws TranslationDraws(size_t num_matches, int num_draws,
                                 double step) {
  ImageModelDraws draws;
  draws.point_deltas.resize(3 * static_cast<Eigen::Index>(num_matches),
                            num_draws);
  draws.surface_shifts.resize(3, num_draws);
  for (int m = 0; m < num_draws; ++m) {
    const Eigen::Vector3d d =
        step * Eigen::Vector3d(std::sin(1.0 + m), std::cos(2.0 * m), 0.5);
    draws.surface_shifts.col(m) = d.cast<float>();
    for (size_t j = 0; j < num_matches; ++j) {
      draws.point_deltas.block<3, 1>(3 * static_cast<Eigen::Index>(j), m) =
          d.cast<float>();
    }
  }
  return draws;
}

// A model moved as a whole measures the same scale: the re-localized camera
// follows its points and the surface shift brings the mesh along. A sign
// error in the shift would change the scale by ~2 |d| / range.
TEST(EstimateImageScale, AModelDrawnTranslatedMeasuresTheSameScale) {
  Case c = MakeCase(ShotNoise(), 1.0, 6);
  const RayCaster caster(c.model_mesh);
  c.shot.image.model = TranslationDraws(c.shot.image.matches.size(), 20, 0.05);
  MonteCarloOptions options;
  options.num_iterations = 40;
  const ImageScaleResult result = EstimateImageScale(
      c.shot.image, 0, c.shot.calibration, caster, ScaleMethod::kFum, options);
  ASSERT_TRUE(result.nominal);
  EXPECT_EQ(result.num_model_draws, 20);
  ASSERT_EQ(result.samples.size(), 40u);
  for (const double scale : result.samples) {
    EXPECT_NEAR(scale, *result.nominal, 1e-6);
  }
  // Only the surface moving is a change of the model's shape: the scale
  // moves by about the shift over the range (3 m).
  c.shot.image.model.point_deltas.setZero();
  const ImageScaleResult surface_only = EstimateImageScale(
      c.shot.image, 0, c.shot.calibration, caster, ScaleMethod::kFum, options);
  EXPECT_GT(surface_only.monte_carlo.std_dev, 0.002);
  EXPECT_LT(surface_only.monte_carlo.std_dev, 0.05);
}

// The focal length drawn with sigma sigma_f: the scale's spread grows
// linearly with it, sample for sample the same as an image whose camera
// and pose are those of the draw, and the draws' pose refinement keeps
// the result independent of the thread count.
TEST(EstimateImageScale, DrawnIntrinsicsMoveTheScaleAsTheirOwnImageWould) {
  const Case c = MakeCase(Noisy(), 1.0, 7);
  const RayCaster caster(c.model_mesh);
  LaserImage image = c.shot.image;
  const int num_draws = 30;
  image.model.param_indices = {0};
  image.model.camera_deltas.resize(1, num_draws);
  for (int m = 0; m < num_draws; ++m) {
    image.model.camera_deltas(0, m) = 4.0 * std::sin(0.7 * m + 0.3);
  }
  image.model.point_deltas.setZero(3 * image.matches.size(), num_draws);
  image.model.surface_shifts.setZero(3, num_draws);
  MonteCarloOptions options = MonteCarloOptions().Only(ScaleSource::kModel);
  options.num_iterations = num_draws;
  options.num_threads = 1;
  const ImageScaleResult one = EstimateImageScale(
      image, 0, c.shot.calibration, caster, ScaleMethod::kFum, options);
  options.num_threads = 2;
  const ImageScaleResult two = EstimateImageScale(
      image, 0, c.shot.calibration, caster, ScaleMethod::kFum, options);
  EXPECT_EQ(one.samples, two.samples);
  ASSERT_EQ(one.per_iteration.size(), static_cast<size_t>(num_draws));
  for (const int m : {0, 7, 19}) {
    LaserImage drawn = c.shot.image;
    drawn.camera.params[0] += image.model.camera_deltas(0, m);
    ASSERT_TRUE(
        RefinePose(drawn.camera, drawn.matches, {}, 50, &drawn.cam_from_world));
    MonteCarloOptions nominal_only = options;
    nominal_only.num_iterations = 1;
    const ImageScaleResult alone = EstimateImageScale(
        drawn, 0, c.shot.calibration, caster, ScaleMethod::kFum,
        nominal_only.Only(ScaleSource::kModel));
    ASSERT_TRUE(alone.nominal);
    EXPECT_NEAR(one.per_iteration[m], *alone.nominal, 1e-9) << m;
  }
  image.model.camera_deltas *= 2.0;
  const ImageScaleResult doubled = EstimateImageScale(
      image, 0, c.shot.calibration, caster, ScaleMethod::kFum, options);
  EXPECT_GT(one.monte_carlo.std_dev, 1e-5);
  EXPECT_NEAR(doubled.monte_carlo.std_dev / one.monte_carlo.std_dev, 2.0, 0.05);
  // Not sampling the model ignores the draws.
  options.sample_model = false;
  const ImageScaleResult exact = EstimateImageScale(
      image, 0, c.shot.calibration, caster, ScaleMethod::kFum, options);
  EXPECT_EQ(exact.num_model_draws, 0);
  EXPECT_LT(exact.monte_carlo.std_dev, 1e-12);
}

TEST(EstimateImageScale, SummariesAndConvergenceTrace) {
  const Case c = MakeCase(Noisy(), 1.0, 4);
  const RayCaster caster(c.model_mesh);
  MonteCarloOptions options;
  options.num_iterations = 1000;
  options.convergence_every = 100;
  const ImageScaleResult result = EstimateImageScale(
      c.shot.image, 0, c.shot.calibration, caster, ScaleMethod::kFum, options);
  ASSERT_EQ(result.convergence.size(), 10u);
  EXPECT_EQ(result.convergence.back().iterations, 1000);
  EXPECT_NEAR(result.convergence.back().mean, result.monte_carlo.mean, 1e-12);
  EXPECT_NEAR(result.convergence.back().std_dev, result.monte_carlo.std_dev,
              1e-9);
  const SampleSummary& mc = result.monte_carlo;
  EXPECT_LT(mc.p2_5, mc.p16);
  EXPECT_LT(mc.p16, mc.p50);
  EXPECT_LT(mc.p50, mc.p84);
  EXPECT_LT(mc.p84, mc.p97_5);
  // Averaging four lasers narrows the spread (thesis Table 1, FUM-all vs
  // FUM-single).
  for (const ItemResult& item : result.items) {
    EXPECT_GT(item.monte_carlo.std_dev, 1.3 * mc.std_dev) << item.item.name;
  }
}

TEST(EstimateImageScale, AcceptanceRules) {
  Case c = MakeCase(ShotNoise(), 1.0, 5);
  const RayCaster caster(c.model_mesh);
  MonteCarloOptions options;
  options.num_iterations = 50;
  // One laser's calibration 1 degree off: its scale disagrees.
  LaserSetup wrong = c.shot.calibration;
  wrong.lasers[2].direction_in_cam =
      (Eigen::AngleAxisd(M_PI / 180.0, Eigen::Vector3d::UnitY()) *
       wrong.lasers[2].direction_in_cam)
          .normalized();
  ImageScaleResult result = EstimateImageScale(c.shot.image, 0, wrong, caster,
                                               ScaleMethod::kFum, options);
  EXPECT_FALSE(result.accepted);
  EXPECT_NE(result.rejection.find("disagree"), std::string::npos)
      << result.rejection;
  // With the calibration's stated uncertainty (0.05 deg, 1 mm) a laser
  // 1 degree off is still far beyond it; the same image with its true
  // calibration error only is accepted.
  Case noisy = MakeCase(Noisy(), 1.0, 8);
  const RayCaster noisy_caster(noisy.model_mesh);
  options.num_iterations = 500;
  result = EstimateImageScale(noisy.shot.image, 0, noisy.shot.calibration,
                              noisy_caster, ScaleMethod::kFum, options);
  EXPECT_TRUE(result.accepted) << result.rejection;
  LaserSetup noisy_wrong = noisy.shot.calibration;
  noisy_wrong.lasers[1].direction_in_cam =
      (Eigen::AngleAxisd(M_PI / 180.0, Eigen::Vector3d::UnitX()) *
       noisy_wrong.lasers[1].direction_in_cam)
          .normalized();
  result = EstimateImageScale(noisy.shot.image, 0, noisy_wrong, noisy_caster,
                              ScaleMethod::kFum, options);
  EXPECT_FALSE(result.accepted);
  EXPECT_NE(result.rejection.find("L1 is"), std::string::npos)
      << result.rejection;
  options.num_iterations = 50;
  // Only one spot left.
  for (size_t l = 1; l < c.shot.image.spots.size(); ++l) {
    c.shot.image.spots[l].reset();
  }
  result = EstimateImageScale(c.shot.image, 0, c.shot.calibration, caster,
                              ScaleMethod::kFum, options);
  EXPECT_FALSE(result.accepted);
  EXPECT_NE(result.rejection.find("1 laser(s) give a scale (1 detected), "
                                  "fewer than the 2 required"),
            std::string::npos)
      << result.rejection;
  ASSERT_TRUE(result.nominal);  // the one laser still gives a scale
  EXPECT_EQ(result.items[1].num_invalid, 50u);
  EXPECT_NE(result.items[1].nominal.problem.find("has no spot"),
            std::string::npos);
}

TEST(EstimateImageScale, ItemsWithoutAScaleSayWhyAndNeverGiveNaN) {
  Case c = MakeCase(Noisy(), 1.0, 6);
  const RayCaster caster(c.model_mesh);
  MonteCarloOptions options;
  options.num_iterations = 100;
  c.shot.image.spots[0]->pixel = Eigen::Vector2d(-40.0, 100.0);
  const ImageScaleResult result = EstimateImageScale(
      c.shot.image, 0, c.shot.calibration, caster, ScaleMethod::kFum, options);
  EXPECT_FALSE(result.items[0].nominal.scale);
  EXPECT_NE(result.items[0].nominal.problem.find("outside"), std::string::npos)
      << result.items[0].nominal.problem;
  EXPECT_EQ(result.items[0].monte_carlo.num_samples, 0u);
  EXPECT_EQ(result.items[0].num_invalid, 100u);
  for (const double sample : result.samples) EXPECT_TRUE(std::isfinite(sample));
  ASSERT_TRUE(result.nominal);
  EXPECT_TRUE(std::isfinite(*result.nominal));
  // Three of four lasers still measure: accepted.
  EXPECT_TRUE(result.accepted) << result.rejection;
}

// Detected spots whose rays miss the surface do not count towards the two
// lasers an image needs.
TEST(EstimateImageScale, SpotsMissingTheSurfaceDoNotCount) {
  Case c = MakeCase(ShotNoise(), 1.0, 7);
  const RayCaster caster(c.model_mesh);
  MonteCarloOptions options;
  options.num_iterations = 20;
  for (size_t l = 1; l < c.shot.image.spots.size(); ++l) {
    c.shot.image.spots[l]->pixel = Eigen::Vector2d(-5.0, -5.0);
  }
  const ImageScaleResult result = EstimateImageScale(
      c.shot.image, 0, c.shot.calibration, caster, ScaleMethod::kFum, options);
  EXPECT_FALSE(result.accepted);
  EXPECT_NE(result.rejection.find("1 laser(s) give a scale (4 detected)"),
            std::string::npos)
      << result.rejection;
}

TEST(MonteCarloOptions, CheckNamesTheField) {
  MonteCarloOptions options;
  options.num_iterations = 0;
  EXPECT_THROW(options.Check(), Error);
  options = MonteCarloOptions();
  options.max_item_sigmas = 0.0;
  EXPECT_THROW(options.Check(), Error);
}

}  // namespace
}  // namespace uw
