#include "laserscale/spot_detector.h"

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Geometry>
#include <opencv2/imgproc.hpp>

#include "common/mesh/test_meshes.h"
#include "common/util/error.h"
#include "common/util/random.h"
#include "sim/laser.h"
#include "sim/procedural_texture.h"
#include "sim/renderer.h"

namespace uw {
namespace {

constexpr double kRadius95 = 2.4477;  // sqrt(-2 ln 0.05)

// ---------------------------------------------------------------------------
// Synthetic images with one spot drawn at a known sub-pixel position: the
// detector's maths without the renderer.

Camera PinholeCamera(int width, int height, double focal) {
  Camera camera;
  camera.camera_id = 1;
  camera.model_id = CameraModelId::kPinhole;
  camera.width = width;
  camera.height = height;
  camera.params = {focal, focal, width / 2.0, height / 2.0};
  return camera;
}

// One red laser 10 cm right of the camera, parallel to its axis: with the
// 320x240 camera below its beam's image runs along y = 120 from x = 200
// (1 m) to x = 166.7 (6 m).
LaserSetup OneLaser() {
  LaserSetup setup;
  setup.name = "test";
  Laser laser;
  laser.name = "L";
  laser.origin_in_cam = {0.1, 0.0, 0.0};
  laser.colour = {1.0, 0.15, 0.1};
  setup.lasers = {laser};
  return setup;
}

// A textured background: smooth random blobs, 20-120 levels, greenish.
cv::Mat Texture(int width, int height, uint64_t seed) {
  cv::Mat noise(height / 4, width / 4, CV_32F);
  SplitMix64Stream random(seed);
  for (int r = 0; r < noise.rows; ++r) {
    for (int c = 0; c < noise.cols; ++c) {
      noise.at<float>(r, c) = static_cast<float>(random.Uniform());
    }
  }
  cv::Mat smooth;
  cv::resize(noise, smooth, cv::Size(width, height), 0, 0, cv::INTER_CUBIC);
  cv::Mat texture(height, width, CV_32FC3);
  for (int r = 0; r < height; ++r) {
    for (int c = 0; c < width; ++c) {
      const float v =
          20.0f + 100.0f * std::clamp(smooth.at<float>(r, c), 0.f, 1.f);
      texture.at<cv::Vec3f>(r, c) = cv::Vec3f(0.8f * v, v, 0.4f * v);
    }
  }
  return texture;
}

// `background` (CV_32FC3) plus a red elliptical Gaussian spot at `centre`
// (COLMAP convention) with peak `amplitude` and covariance `shape`, plus
// noise of `sigma`, clipped and rounded to 8 bits.
cv::Mat WithSpot(const cv::Mat& background, const Eigen::Vector2d& centre,
                 double amplitude, const Eigen::Matrix2d& shape, double sigma,
                 uint64_t seed) {
  const Eigen::Matrix2d precision = shape.inverse();
  SplitMix64Stream random(seed);
  cv::Mat out(background.size(), CV_8UC3);
  for (int r = 0; r < background.rows; ++r) {
    for (int c = 0; c < background.cols; ++c) {
      const Eigen::Vector2d d = Eigen::Vector2d(c + 0.5, r + 0.5) - centre;
      const double g = amplitude * std::exp(-0.5 * d.dot(precision * d));
      const cv::Vec3f& b = background.at<cv::Vec3f>(r, c);
      const double bgr[3] = {b[0] + 0.1 * g, b[1] + 0.15 * g, b[2] + g};
      for (int k = 0; k < 3; ++k) {
        out.at<cv::Vec3b>(r, c)[k] = cv::saturate_cast<uint8_t>(
            std::lround(bgr[k] + sigma * random.Gaussian()));
      }
    }
  }
  return out;
}

cv::Mat Flat(int width, int height) {
  return cv::Mat(height, width, CV_32FC3, cv::Scalar(40, 60, 30));
}

TEST(DetectSpots, FitsASyntheticSpotToAHundredthOfAPixel) {
  const Camera camera = PinholeCamera(320, 240, 400.0);
  Eigen::Matrix2d shape;
  shape << 3.0, 0.8, 0.8, 2.0;
  const Eigen::Vector2d centre(185.37, 120.71);
  SpotDetectorOptions options;
  options.monte_carlo_iterations = 0;
  const std::vector<DetectedSpot> spots =
      DetectSpots(WithSpot(Flat(320, 240), centre, 120.0, shape, 0.0, 1),
                  cv::Mat(), camera, OneLaser(), options, 1);
  ASSERT_EQ(spots.size(), 1u);
  ASSERT_TRUE(spots[0].detected) << spots[0].problem;
  EXPECT_TRUE(spots[0].stable);
  EXPECT_EQ(spots[0].laser, "L");
  EXPECT_LT((spots[0].pixel - centre).norm(), 0.01);
  // Σc = Σb 2 ln(1.25) / (-2 ln 0.05) (§5.2 step 12); Σb is the spot's
  // shape widened by the low-pass (σ = 1 px).
  const Eigen::Matrix2d expected =
      (shape + Eigen::Matrix2d::Identity()) * 0.44629 / 5.99146;
  EXPECT_LT((spots[0].covariance - expected).norm(), 0.02 * expected.norm())
      << spots[0].covariance;
}

// A spot clipped at 255 over half its width: the clipped pixels bound the
// fit from below instead of being lost, so the centre stays put.
TEST(DetectSpots, SaturatedSpotKeepsItsCentre) {
  const Camera camera = PinholeCamera(320, 240, 400.0);
  Eigen::Matrix2d shape;
  shape << 6.0, -1.0, -1.0, 4.0;
  SpotDetectorOptions options;
  options.monte_carlo_iterations = 0;
  for (const Eigen::Vector2d& centre :
       {Eigen::Vector2d(178.8, 121.3), Eigen::Vector2d(190.21, 118.55)}) {
    const std::vector<DetectedSpot> spots =
        DetectSpots(WithSpot(Flat(320, 240), centre, 900.0, shape, 1.0, 2),
                    cv::Mat(), camera, OneLaser(), options, 1);
    ASSERT_TRUE(spots[0].detected) << spots[0].problem;
    EXPECT_LT((spots[0].pixel - centre).norm(), 0.1) << spots[0].pixel;
  }
}

// Texture removal with a synthetic aux: the same texture moved by a few
// pixels, 15 % brighter, with the laser off. The spot sits on a texture
// gradient that biases the fit without the aux.
TEST(DetectSpots, AuxRemovesTheTexture) {
  const Camera camera = PinholeCamera(320, 240, 400.0);
  const cv::Mat texture = Texture(320, 240, 5);
  const cv::Mat moved_texture = [&] {
    const cv::Mat shift = (cv::Mat_<double>(2, 3) << 1, 0, 4.3, 0, 1, -2.6);
    cv::Mat moved;
    cv::warpAffine(texture, moved, shift, texture.size(), cv::INTER_LINEAR,
                   cv::BORDER_REFLECT);
    return cv::Mat(1.15 * moved);
  }();
  Eigen::Matrix2d shape;
  shape << 2.5, 0.0, 0.0, 2.5;
  SpotDetectorOptions options;
  options.noise_sigma = 1.0;
  options.monte_carlo_iterations = 20;
  int better = 0;
  for (int i = 0; i < 5; ++i) {
    const Eigen::Vector2d centre(172.3 + 5.1 * i, 120.4 - 0.3 * i);
    const cv::Mat image = WithSpot(texture, centre, 40.0, shape, 1.0, 10 + i);
    const cv::Mat aux =
        WithSpot(moved_texture, centre, 0.0, shape, 1.0, 20 + i);
    const DetectedSpot with_aux =
        DetectSpots(image, aux, camera, OneLaser(), options, 1)[0];
    ASSERT_TRUE(with_aux.stable) << with_aux.problem;
    const double error = (with_aux.pixel - centre).norm();
    EXPECT_LT(error, 0.15) << "spot " << i;
    SpotDetectorOptions no_removal = options;
    no_removal.texture_removal = false;
    const DetectedSpot without =
        DetectSpots(image, aux, camera, OneLaser(), no_removal, 1)[0];
    if (!without.stable || (without.pixel - centre).norm() > error) ++better;
  }
  EXPECT_GE(better, 4);
}

// ---------------------------------------------------------------------------
// Bad input.

TEST(SpotDetectorOptions, CheckNamesTheField) {
  const auto expect_error = [](void (*change)(SpotDetectorOptions*),
                               const std::string& field) {
    SpotDetectorOptions options;
    change(&options);
    try {
      options.Check();
      ADD_FAILURE() << "no error for " << field;
    } catch (const Error& error) {
      EXPECT_NE(std::string(error.what()).find(field), std::string::npos)
          << error.what();
    }
  };
  EXPECT_NO_THROW(SpotDetectorOptions().Check());
  expect_error([](SpotDetectorOptions* o) { o->min_range_m = 0.0; },
               "min_range_m = 0");
  expect_error([](SpotDetectorOptions* o) { o->max_range_m = 0.5; },
               "max_range_m");
  expect_error([](SpotDetectorOptions* o) { o->roi_margin_px = -1; },
               "roi_margin_px");
  expect_error([](SpotDetectorOptions* o) { o->lowpass_sigma_px = NAN; },
               "lowpass_sigma_px");
  expect_error([](SpotDetectorOptions* o) { o->hue_tolerance_deg = 0.0; },
               "hue_tolerance_deg");
  expect_error([](SpotDetectorOptions* o) { o->max_area_px = 1; },
               "max_area_px");
  expect_error([](SpotDetectorOptions* o) { o->top_fraction = 1.0; },
               "top_fraction");
  expect_error([](SpotDetectorOptions* o) { o->confidence = 0.0; },
               "confidence");
  expect_error([](SpotDetectorOptions* o) { o->monte_carlo_iterations = -1; },
               "monte_carlo_iterations");
  expect_error([](SpotDetectorOptions* o) { o->min_detection_rate = 1.5; },
               "min_detection_rate");
  expect_error([](SpotDetectorOptions* o) { o->noise_sigma = NAN; },
               "noise_sigma");
}

TEST(DetectSpots, BadInputIsAnErrorOrAProblemNeverNaN) {
  const Camera camera = PinholeCamera(320, 240, 400.0);
  const cv::Mat image = WithSpot(Flat(320, 240), {185.0, 120.0}, 100.0,
                                 Eigen::Matrix2d::Identity() * 3.0, 1.0, 1);
  const SpotDetectorOptions options;
  const auto expect_error = [&](const cv::Mat& main, const cv::Mat& aux,
                                const Camera& cam, const std::string& part) {
    try {
      DetectSpots(main, aux, cam, OneLaser(), options, 1);
      ADD_FAILURE() << "no error, expected " << part;
    } catch (const Error& error) {
      EXPECT_NE(std::string(error.what()).find(part), std::string::npos)
          << error.what();
    }
  };
  expect_error(cv::Mat(), cv::Mat(), camera, "DetectSpots: empty image");
  cv::Mat grey;
  cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
  expect_error(grey, cv::Mat(), camera, "expected an 8-bit BGR image");
  cv::Mat wide;
  image.convertTo(wide, CV_16UC3);
  expect_error(wide, cv::Mat(), camera, "expected an 8-bit BGR image");
  expect_error(image, cv::Mat(), PinholeCamera(640, 480, 400.0),
               "the image is 320x240, its camera 640x480");
  cv::Mat small;
  cv::resize(image, small, cv::Size(160, 120));
  expect_error(image, small, camera,
               "the auxiliary image is 160x120, the image 320x240");
  expect_error(image, grey, camera, "expected an 8-bit BGR auxiliary image");
  LaserSetup no_name = OneLaser();
  no_name.lasers[0].name.clear();
  EXPECT_THROW(DetectSpots(image, cv::Mat(), camera, no_name, options, 1),
               Error);
  EXPECT_THROW(DetectBrightestPixel(grey, camera, OneLaser(), options), Error);

  // Beams that never reach the image: a problem per spot, no NaN.
  LaserSetup outside = OneLaser();
  Laser far = outside.lasers[0];
  far.name = "far";
  far.origin_in_cam = {5.0, 0.0, 0.0};  // 5 m to the side, parallel
  outside.lasers.push_back(far);
  Laser oblique = outside.lasers[0];
  oblique.name = "oblique";
  oblique.direction_in_cam = Eigen::Vector3d(-1.0, 0.0, 0.2).normalized();
  outside.lasers.push_back(oblique);
  for (const auto& spots :
       {DetectSpots(image, cv::Mat(), camera, outside, options, 1),
        DetectBrightestPixel(image, camera, outside, options)}) {
    ASSERT_EQ(spots.size(), 3u);
    EXPECT_TRUE(spots[0].stable) << spots[0].problem;
    for (size_t l = 1; l < 3; ++l) {
      EXPECT_FALSE(spots[l].detected);
      EXPECT_FALSE(spots[l].stable);
      EXPECT_EQ(spots[l].problem.rfind("outside the image", 0), 0u)
          << spots[l].problem;
    }
    for (const DetectedSpot& spot : spots) {
      EXPECT_TRUE(spot.pixel.allFinite());
      EXPECT_TRUE(spot.covariance.allFinite());
      EXPECT_TRUE(std::isfinite(spot.detection_rate));
    }
  }

  // No spot at all: "not detected", zeros, no NaN.
  const DetectedSpot nothing =
      DetectSpots(WithSpot(Flat(320, 240), {0, 0}, 0.0,
                           Eigen::Matrix2d::Identity(), 1.0, 3),
                  cv::Mat(), camera, OneLaser(), options, 1)[0];
  EXPECT_FALSE(nothing.detected);
  EXPECT_EQ(nothing.problem, "not detected");
  EXPECT_EQ(nothing.pixel, Eigen::Vector2d::Zero());
  EXPECT_EQ(nothing.detection_rate, 0.0);
}

// ---------------------------------------------------------------------------
// The Monte Carlo.

TEST(DetectSpots, MergedSpotIsTheMomentsOfTheIterations) {
  const Camera camera = PinholeCamera(320, 240, 400.0);
  Eigen::Matrix2d shape;
  shape << 2.0, 0.5, 0.5, 3.0;
  SpotDetectorOptions options;
  options.noise_sigma = 6.0;
  options.monte_carlo_iterations = 60;
  const cv::Mat image =
      WithSpot(Flat(320, 240), {181.6, 119.2}, 45.0, shape, 2.0, 4);
  const DetectedSpot spot =
      DetectSpots(image, cv::Mat(), camera, OneLaser(), options, 7)[0];
  ASSERT_TRUE(spot.stable) << spot.problem;
  ASSERT_EQ(spot.iterations.size(),
            static_cast<size_t>(std::lround(60 * spot.detection_rate)));
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& [centre, cov] : spot.iterations) mean += centre;
  mean /= spot.iterations.size();
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();
  for (const auto& [centre, cov] : spot.iterations) {
    covariance += cov + (centre - mean) * (centre - mean).transpose();
  }
  covariance /= spot.iterations.size();
  EXPECT_LT((spot.pixel - mean).norm(), 1e-12);
  EXPECT_LT((spot.covariance - covariance).norm(), 1e-12);
  // The noise spreads the centres: the merged covariance exceeds the mean
  // of the iterations' shape covariances.
  Eigen::Matrix2d shape_part = Eigen::Matrix2d::Zero();
  for (const auto& [centre, cov] : spot.iterations) shape_part += cov;
  shape_part /= spot.iterations.size();
  EXPECT_GT(spot.covariance.trace(), shape_part.trace() + 1e-4);
}

TEST(DetectSpots, SameResultForAnySeedDeterministicThreadCount) {
  const Camera camera = PinholeCamera(320, 240, 400.0);
  const cv::Mat texture = Texture(320, 240, 9);
  const cv::Mat image = WithSpot(texture, {188.2, 121.9}, 30.0,
                                 Eigen::Matrix2d::Identity() * 2.0, 2.0, 5);
  const cv::Mat aux = WithSpot(texture, {188.2, 121.9}, 0.0,
                               Eigen::Matrix2d::Identity(), 2.0, 6);
  SpotDetectorOptions options;
  options.monte_carlo_iterations = 40;
  options.num_threads = 1;
  const DetectedSpot one =
      DetectSpots(image, aux, camera, OneLaser(), options, 11)[0];
  options.num_threads = 3;
  const DetectedSpot three =
      DetectSpots(image, aux, camera, OneLaser(), options, 11)[0];
  ASSERT_TRUE(one.detected);
  EXPECT_EQ(one.pixel, three.pixel);
  EXPECT_EQ(one.covariance, three.covariance);
  EXPECT_EQ(one.detection_rate, three.detection_rate);
  const DetectedSpot other_seed =
      DetectSpots(image, aux, camera, OneLaser(), options, 12)[0];
  EXPECT_NE(one.pixel, other_seed.pixel);
  EXPECT_LT((one.pixel - other_seed.pixel).norm(), 0.2);
}

// A spot at the noise level is found in some iterations only: unstable,
// with the rate in its problem, and not counted as confident.
TEST(DetectSpots, FaintSpotIsUnstable) {
  const Camera camera = PinholeCamera(320, 240, 400.0);
  SpotDetectorOptions options;
  options.monte_carlo_iterations = 100;
  int unstable = 0;
  for (uint64_t seed = 0; seed < 6; ++seed) {
    const cv::Mat image =
        WithSpot(Flat(320, 240), {183.0, 120.5}, 4.5,
                 Eigen::Matrix2d::Identity() * 2.0, 2.0, seed);
    const DetectedSpot spot =
        DetectSpots(image, cv::Mat(), camera, OneLaser(), options, seed)[0];
    EXPECT_TRUE(spot.pixel.allFinite());
    if (spot.detected && !spot.stable) {
      ++unstable;
      EXPECT_LT(spot.detection_rate, options.min_detection_rate);
      EXPECT_EQ(spot.problem.rfind("unstable: detected in ", 0), 0u)
          << spot.problem;
    }
  }
  EXPECT_GE(unstable, 1);
}

// The optional hue test: a laser whose set-up colour is green is not found
// in red spots.
TEST(DetectSpots, HueTestRejectsOtherColours) {
  const Camera camera = PinholeCamera(320, 240, 400.0);
  const cv::Mat image = WithSpot(Flat(320, 240), {185.0, 120.0}, 100.0,
                                 Eigen::Matrix2d::Identity() * 3.0, 1.0, 1);
  SpotDetectorOptions options;
  options.hue_tolerance_deg = 30.0;
  options.min_saturation = 0.3;
  options.monte_carlo_iterations = 10;
  EXPECT_TRUE(
      DetectSpots(image, cv::Mat(), camera, OneLaser(), options, 1)[0].stable);
  LaserSetup green = OneLaser();
  green.lasers[0].colour = {0.1, 1.0, 0.2};
  EXPECT_FALSE(
      DetectSpots(image, cv::Mat(), camera, green, options, 1)[0].detected);
}

TEST(DetectBrightestPixel, IsTheCentreOfTheBrightestPixels) {
  const Camera camera = PinholeCamera(320, 240, 400.0);
  cv::Mat image = WithSpot(Flat(320, 240), {0, 0}, 0.0,
                           Eigen::Matrix2d::Identity(), 0.0, 1);
  image.at<cv::Vec3b>(120, 180) = cv::Vec3b(10, 20, 200);
  image.at<cv::Vec3b>(120, 181) = cv::Vec3b(10, 20, 200);
  image.at<cv::Vec3b>(119, 190) = cv::Vec3b(10, 20, 150);
  const DetectedSpot spot =
      DetectBrightestPixel(image, camera, OneLaser(), SpotDetectorOptions())[0];
  ASSERT_TRUE(spot.stable);
  EXPECT_EQ(spot.pixel, Eigen::Vector2d(181.0, 120.5));
  EXPECT_EQ(spot.covariance, Eigen::Matrix2d::Identity() / 12.0);
}

TEST(DrawSpotOverlay, MarksSpotsAndAddsMagnifiedCrops) {
  const Camera camera = PinholeCamera(320, 240, 400.0);
  const cv::Mat image = WithSpot(Flat(320, 240), {185.0, 120.0}, 100.0,
                                 Eigen::Matrix2d::Identity() * 3.0, 1.0, 1);
  SpotDetectorOptions options;
  options.monte_carlo_iterations = 10;
  std::vector<DetectedSpot> spots =
      DetectSpots(image, cv::Mat(), camera, OneLaser(), options, 1);
  DetectedSpot missing;
  missing.laser = "L9";
  missing.problem = "not detected";
  spots.push_back(missing);
  const cv::Mat overlay = DrawSpotOverlay(image, spots);
  // The image above one row of 192-px tiles.
  ASSERT_EQ(overlay.cols, 320);
  ASSERT_EQ(overlay.rows, 240 + 192);
  EXPECT_GT(cv::norm(overlay(cv::Rect(0, 0, 320, 240)), image, cv::NORM_L1),
            0.0);
  // The tile magnifies the 24x24 pixels around the spot 8 times: unmarked
  // parts are the source pixels, and the marks change others.
  const cv::Mat tile = overlay(cv::Rect(0, 240, 192, 192));
  const int x0 = static_cast<int>(std::floor(spots[0].pixel.x())) - 12;
  const int y0 = static_cast<int>(std::floor(spots[0].pixel.y())) - 12;
  cv::Mat magnified;
  cv::resize(image(cv::Rect(x0, y0, 24, 24)), magnified, cv::Size(192, 192), 0,
             0, cv::INTER_NEAREST);
  EXPECT_EQ(tile.at<cv::Vec3b>(2, 2), magnified.at<cv::Vec3b>(2, 2));
  EXPECT_EQ(tile.at<cv::Vec3b>(189, 189), magnified.at<cv::Vec3b>(189, 189));
  EXPECT_GT(cv::norm(tile, magnified, cv::NORM_L1), 1000.0);
  EXPECT_THROW(DrawSpotOverlay(cv::Mat(), spots), Error);
}

// ---------------------------------------------------------------------------
// Acceptance on uwsim laser images (ch4 spec §14.3, issue 5).

Camera SimCamera() {
  // The middle 512x384 of uwsim's default 1024x768 camera, without its mild
  // distortion (which makes the renderer's set-up slow): the spots have
  // their full-resolution size and all four lasers stay in view at 1-6 m.
  return PinholeCamera(512, 384, 850.0);
}

Eigen::Vector3d RandomDirection(SplitMix64Stream* random) {
  const double z = random->Uniform(-1.0, 1.0);
  const double angle = random->Uniform(0.0, 2.0 * M_PI);
  const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
  return {r * std::cos(angle), r * std::sin(angle), z};
}

struct SceneOptions {
  double range_m = 2.5;         // of the textured plane, along the axis
  double peak_level = 60.0;     // uwsim's beam optics
  std::string aux = "shifted";  // or "absent" (lasers off in the aux)
  int jpeg_quality = 0;
  double noise_sigma = 2.0;
};

struct Shot {
  cv::Mat image;
  cv::Mat aux;
  std::vector<sim::LaserSpotTruth> truth;
};

// A laser image of set-up C on a procedurally textured plane tilted up to
// 30 degrees, and its auxiliary image after uwsim's small camera motion
// (5 cm, 0.5 degrees, gain x1.15), rendered with uwsim's default water,
// lamp and sensor but one sample per pixel.
Shot RenderShot(const SceneOptions& scene, uint64_t seed) {
  SplitMix64Stream random(SplitMix64(seed));
  const double tilt = random.Uniform(0.0, 30.0) * M_PI / 180.0;
  const Eigen::Vector3d axis =
      RandomDirection(&random).cross(Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector3d normal =
      Eigen::AngleAxisd(tilt, axis) * Eigen::Vector3d(0, 0, -1);
  const Eigen::Vector3d u = normal.cross(Eigen::Vector3d::UnitX()).normalized();
  const Eigen::Vector3d v = normal.cross(u);
  TriangleMesh mesh;
  AddGrid(Eigen::Vector3d(0, 0, scene.range_m) - 10.0 * u - 10.0 * v, 20.0 * v,
          20.0 * u, 4, 4, &mesh);
  const RayCaster caster(mesh);
  const sim::ProceduralTexture texture(sim::ProceduralTextureOptions(), seed);
  sim::RenderOptions options;
  options.sensor.noise_sigma = scene.noise_sigma;
  options.sensor.jpeg_quality = scene.jpeg_quality;
  // One sample per pixel: the spots (>= 2 px wide) need no more, and the
  // test renders 84 images.
  options.sensor.supersampling = 1;
  const Camera camera = SimCamera();
  const sim::Renderer renderer(caster, texture, camera, options);
  sim::FrameOptions frame;
  frame.lasers = sim::TrueLaserSetup(sim::LaserOptions()).lasers;
  frame.optics.peak_level = scene.peak_level;
  Shot shot;
  shot.image = renderer.Render(Rigid3d(), seed, 0, frame).image;
  for (const Laser& laser : frame.lasers) {
    shot.truth.push_back(sim::TrueLaserSpot(caster, camera, Rigid3d(), laser));
  }
  Rigid3d aux_from_cam;
  aux_from_cam.rotation = Eigen::Quaterniond(
      Eigen::AngleAxisd(0.5 * M_PI / 180.0, RandomDirection(&random)));
  aux_from_cam.translation = 0.05 * RandomDirection(&random);
  sim::FrameOptions aux_frame;
  aux_frame.gain_factor = 1.15;
  if (scene.aux == "shifted") {
    aux_frame.lasers = frame.lasers;
    aux_frame.optics = frame.optics;
  }
  shot.aux = renderer.Render(aux_from_cam, seed, 1, aux_frame).image;
  return shot;
}

// Per method: of the visible spots, how many were stable, within 1 px of
// the truth, and covered by their 95 % ellipse.
struct Tally {
  int visible = 0;
  int stable = 0;
  int within_1px = 0;
  int covered_95 = 0;
  double rate_sum = 0.0;

  void Add(const DetectedSpot& spot, const sim::LaserSpotTruth& truth) {
    if (!truth.visible) return;
    ++visible;
    rate_sum += spot.detection_rate;
    if (!spot.stable) return;
    ++stable;
    const Eigen::Vector2d error = spot.pixel - truth.pixel;
    if (error.norm() <= 1.0) ++within_1px;
    if (error.dot(spot.covariance.inverse() * error) <= kRadius95 * kRadius95) {
      ++covered_95;
    }
  }
  void Add(const Tally& other) {
    visible += other.visible;
    stable += other.stable;
    within_1px += other.within_1px;
    covered_95 += other.covered_95;
    rate_sum += other.rate_sum;
  }
  double StableFraction() const { return double(stable) / visible; }
  double Within1pxOfStable() const { return double(within_1px) / stable; }
  double FoundWithin1px() const { return double(within_1px) / visible; }
  double Coverage() const { return double(covered_95) / stable; }
  double MeanRate() const { return rate_sum / visible; }
};

struct Case {
  std::string name;
  SceneOptions scene;
  std::vector<double> ranges_m;
  bool attenuated_on_texture = false;
};

TEST(DetectSpots, AcceptanceOnUwsimLaserImages) {
  SceneOptions absent;
  absent.aux = "absent";
  SceneOptions faint;
  faint.peak_level = 8.0;
  SceneOptions faint_absent = faint;
  faint_absent.aux = "absent";
  SceneOptions saturated;
  saturated.peak_level = 600.0;
  SceneOptions jpeg;
  jpeg.jpeg_quality = 75;
  SceneOptions noisy = absent;
  noisy.noise_sigma = 6.0;
  const std::vector<Case> cases = {
      {"aux shifted, 1.5-6 m", SceneOptions(), {1.5, 2.5, 4.0, 6.0}},
      {"aux absent, 1.5-6 m", absent, {1.5, 2.5, 4.0, 6.0}},
      {"attenuated x7.5, shifted", faint, {2.5, 3.5, 4.5}, true},
      {"attenuated x7.5, absent", faint_absent, {2.5, 3.5, 4.5}, true},
      {"saturated x10, shifted", saturated, {1.5, 2.0, 3.0}},
      {"JPEG q75, shifted", jpeg, {2.0, 3.0, 4.5}},
      {"noise 6, absent", noisy, {2.0, 3.0, 4.5}},
  };
  const Camera camera = SimCamera();
  sim::LaserOptions laser_options;
  const LaserSetup calibrated = sim::CalibratedLaserSetup(
      sim::TrueLaserSetup(laser_options), laser_options, 3);
  const SpotDetectorOptions options;
  SpotDetectorOptions no_removal = options;
  no_removal.texture_removal = false;

  Tally all;
  std::printf(
      "[ figures ] %-26s %5s | full: %6s %6s %6s %6s | no texture removal: "
      "%6s %6s | brightest px: %6s\n",
      "case", "spots", "stable", "<=1px", "cov95", "rate", "stable", "<=1px",
      "<=1px");
  uint64_t seed = 100;
  for (const Case& c : cases) {
    Tally full;
    Tally raw;
    Tally brightest;
    for (const double range : c.ranges_m) {
      for (int repeat = 0; repeat < 2; ++repeat, ++seed) {
        SceneOptions scene = c.scene;
        scene.range_m = range;
        const Shot shot = RenderShot(scene, seed);
        const std::vector<DetectedSpot> spots = DetectSpots(
            shot.image, shot.aux, camera, calibrated, options, seed);
        const std::vector<DetectedSpot> raw_spots = DetectSpots(
            shot.image, shot.aux, camera, calibrated, no_removal, seed);
        const std::vector<DetectedSpot> bright_spots =
            DetectBrightestPixel(shot.image, camera, calibrated, options);
        for (size_t l = 0; l < shot.truth.size(); ++l) {
          full.Add(spots[l], shot.truth[l]);
          raw.Add(raw_spots[l], shot.truth[l]);
          brightest.Add(bright_spots[l], shot.truth[l]);
        }
      }
    }
    std::printf(
        "[ figures ] %-26s %5d | full: %6.3f %6.3f %6.3f %6.3f | no texture "
        "removal: %6.3f %6.3f | brightest px: %6.3f\n",
        c.name.c_str(), full.visible, full.StableFraction(),
        full.Within1pxOfStable(), full.Coverage(), full.MeanRate(),
        raw.StableFraction(), raw.Within1pxOfStable(),
        brightest.Within1pxOfStable());
    if (c.attenuated_on_texture) {
      // Found within 1 px, of all visible spots: detection and accuracy.
      EXPECT_GE(full.FoundWithin1px(), raw.FoundWithin1px()) << c.name;
      EXPECT_GE(full.FoundWithin1px(), brightest.FoundWithin1px()) << c.name;
    }
    all.Add(full);
  }
  std::printf(
      "[ figures ] all: %d visible spots, %.3f stable, of which %.3f within "
      "1 px and %.3f inside their 95 %% ellipse\n",
      all.visible, all.StableFraction(), all.Within1pxOfStable(),
      all.Coverage());
  EXPECT_GE(all.Within1pxOfStable(), 0.90);
  EXPECT_GE(all.Coverage(), 0.90);
}

}  // namespace
}  // namespace uw
