#include "colmap_plugins/dense/pinhole_view.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <string>

#include <opencv2/imgproc.hpp>

#include "common/util/error.h"
#include "common/util/error_testing.h"

namespace uw {
namespace {

constexpr double kTwoPi = 6.283185307179586;

// A smooth grey pattern of COLMAP pixel coordinates (centre of the upper-left
// pixel at (0.5, 0.5)), in [0.05, 0.95]. Its wavelengths (96, 80 and 120 px)
// keep bilinear interpolation close to exact; see the tolerances below.
double Pattern(double u, double v) {
  return 0.5 + 0.2 * std::sin(kTwoPi * u / 96.0 + 0.3) +
         0.2 * std::cos(kTwoPi * v / 80.0 - 0.7) +
         0.05 * std::sin(kTwoPi * (u + v) / 120.0);
}

// Bounds of the pattern's derivatives, from its amplitudes and wavenumbers:
// |P_u| + |P_v| and |P_uu| + |P_vv|.
constexpr double kGradientSum =
    0.2 * kTwoPi / 96 + 0.2 * kTwoPi / 80 + 2 * 0.05 * kTwoPi / 120;  // 0.0340
constexpr double kCurvatureSum =
    0.2 * (kTwoPi / 96) * (kTwoPi / 96) + 0.2 * (kTwoPi / 80) * (kTwoPi / 80) +
    2 * 0.05 * (kTwoPi / 120) * (kTwoPi / 120);  // 0.00236

// The largest error of the resampled view against the pattern. Bilinear
// interpolation on a grid of spacing h errs by at most h^2/8 (|P_uu| +
// |P_vv|); cv::remap quantises sample positions to 1/32 of a source pixel,
// which moves them by up to h/64 per axis; 16-bit storage adds < 1e-5.
double InterpolationBound(double h) {
  return h * h / 8.0 * kCurvatureSum + h / 64.0 * kGradientSum + 1e-5;
}

// The camera's image of the pattern as cv::imread reads a 16-bit grey PNG.
cv::Mat SynthesiseImage(const Camera& camera) {
  cv::Mat image(static_cast<int>(camera.height), static_cast<int>(camera.width),
                CV_16U);
  for (int row = 0; row < image.rows; ++row) {
    for (int col = 0; col < image.cols; ++col) {
      image.at<uint16_t>(row, col) = static_cast<uint16_t>(
          std::lround(65535.0 * Pattern(col + 0.5, row + 0.5)));
    }
  }
  return image;
}

Camera MakeCamera(CameraModelId model_id, std::vector<double> params) {
  Camera camera;
  camera.camera_id = 7;
  camera.model_id = model_id;
  camera.width = 320;
  camera.height = 240;
  camera.params = std::move(params);
  return camera;
}

// The documented intrinsics: the camera's focal lengths, its principal point
// moved from COLMAP's to OpenCV's pixel convention, all times `scale`.
Eigen::Matrix3d ExpectedK(double fx, double fy, double cx, double cy,
                          double scale) {
  Eigen::Matrix3d K;
  K << scale * fx, 0.0, scale * cx - 0.5,  //
      0.0, scale * fy, scale * cy - 0.5,   //
      0.0, 0.0, 1.0;
  return K;
}

struct PatternErrors {
  double max_error = 0.0;  // over pixels that see well inside the image
  int num_inside = 0;
  int num_outside = 0;  // pixels that see wholly outside the image
  int num_outside_not_zero = 0;
};

// Compares the view with the pattern where the camera sees it: output pixel
// (x, y) (OpenCV convention) looks along K^-1 (x, y, 1) with the expected K,
// which the camera maps to the COLMAP pixel ImgFromCam(ray).
PatternErrors CompareWithPattern(const PinholeView& view, const Camera& camera,
                                 const Eigen::Matrix3d& expected_K) {
  PatternErrors errors;
  for (int y = 0; y < view.Height(); ++y) {
    for (int x = 0; x < view.Width(); ++x) {
      const Eigen::Vector3d ray_in_cam =
          expected_K.inverse() * Eigen::Vector3d(x, y, 1.0);
      const Eigen::Vector2d pixel = camera.ImgFromCam(ray_in_cam);
      const float grey = view.grey.at<float>(y, x);
      // Bilinear interpolation needs both neighbours inside the image.
      if (pixel.x() > 1.5 && pixel.y() > 1.5 &&
          pixel.x() < camera.width - 1.5 && pixel.y() < camera.height - 1.5) {
        ++errors.num_inside;
        errors.max_error = std::max(
            errors.max_error, std::abs(grey - Pattern(pixel.x(), pixel.y())));
      } else if (pixel.x() < -1.0 || pixel.y() < -1.0 ||
                 pixel.x() > camera.width + 1.0 ||
                 pixel.y() > camera.height + 1.0) {
        ++errors.num_outside;
        if (grey != 0.0f) {
          ++errors.num_outside_not_zero;
        }
      }
    }
  }
  return errors;
}

// The test's own premise: half a pixel of the wrong convention, or ignoring
// the distortion, changes the pattern by far more than the tolerances used
// below, so the comparisons would catch either.
TEST(MakePinholeView, PatternIsSensitiveToHalfAPixel) {
  double max_change = 0.0;
  for (double u = 0.0; u < 320.0; u += 1.0) {
    for (double v = 0.0; v < 240.0; v += 1.0) {
      max_change = std::max(
          max_change, std::abs(Pattern(u + 0.5, v + 0.5) - Pattern(u, v)));
    }
  }
  EXPECT_GT(max_change, 10.0 * InterpolationBound(1.0));
  EXPECT_GT(max_change, 4.0 * InterpolationBound(2.0));
}

TEST(MakePinholeView, SimpleRadialIsUndistortedThroughItsOwnProjection) {
  // f, cx, cy, k: barrel distortion moving the corners by ~5 px.
  const double f = 300.0, cx = 163.2, cy = 118.7;
  const Camera camera =
      MakeCamera(CameraModelId::kSimpleRadial, {f, cx, cy, -0.08});
  Rigid3d cam_from_world;
  cam_from_world.rotation =
      Eigen::Quaterniond(0.9, 0.1, -0.3, 0.2).normalized();
  cam_from_world.translation = Eigen::Vector3d(1.0, -2.0, 3.0);
  const PinholeView view = MakePinholeView(
      camera, cam_from_world, SynthesiseImage(camera), 1.0, "radial.png");

  ASSERT_EQ(view.grey.type(), CV_32F);
  EXPECT_EQ(view.Width(), 320);
  EXPECT_EQ(view.Height(), 240);
  const Eigen::Matrix3d expected_K = ExpectedK(f, f, cx, cy, 1.0);
  EXPECT_NEAR((view.K - expected_K).norm(), 0.0, 1e-12) << view.K;
  EXPECT_NEAR(
      (view.cam_from_world.RotationMatrix() - cam_from_world.RotationMatrix())
          .norm(),
      0.0, 1e-15);
  EXPECT_EQ(view.cam_from_world.translation, cam_from_world.translation);

  // Bound 0.00028 (curvature) + 0.00053 (position quantisation) = 0.00082.
  const PatternErrors errors = CompareWithPattern(view, camera, expected_K);
  EXPECT_GT(errors.num_inside, 300 * 220);
  EXPECT_LT(errors.max_error, InterpolationBound(1.0));

  // Without the distortion the view would be off by far more.
  double undistorted_change = 0.0;
  for (int y = 0; y < 240; y += 4) {
    for (int x = 0; x < 320; x += 4) {
      undistorted_change = std::max(
          undistorted_change,
          std::abs(Pattern(x + 0.5, y + 0.5) - view.grey.at<float>(y, x)));
    }
  }
  EXPECT_GT(undistorted_change, 0.05);
}

TEST(MakePinholeView, OpenCVIsUndistortedAndOutsideIsZero) {
  // fx, fy, cx, cy, k1, k2, p1, p2: pincushion, so that the pinhole's corners
  // see beyond the image.
  const double fx = 310.0, fy = 305.0, cx = 158.3, cy = 122.9;
  const Camera camera = MakeCamera(
      CameraModelId::kOpenCV, {fx, fy, cx, cy, 0.12, 0.02, 0.001, -0.0015});
  const PinholeView view = MakePinholeView(
      camera, Rigid3d(), SynthesiseImage(camera), 1.0, "opencv.png");
  const Eigen::Matrix3d expected_K = ExpectedK(fx, fy, cx, cy, 1.0);
  EXPECT_NEAR((view.K - expected_K).norm(), 0.0, 1e-12) << view.K;

  const PatternErrors errors = CompareWithPattern(view, camera, expected_K);
  EXPECT_GT(errors.num_inside, 250 * 180);
  EXPECT_LT(errors.max_error, InterpolationBound(1.0));
  EXPECT_GT(errors.num_outside, 100);
  EXPECT_EQ(errors.num_outside_not_zero, 0);
}

TEST(MakePinholeView, PinholeAtFullScaleReproducesTheImage) {
  const Camera camera =
      MakeCamera(CameraModelId::kPinhole, {290.0, 295.0, 161.0, 119.5});
  const cv::Mat image = SynthesiseImage(camera);
  const PinholeView view =
      MakePinholeView(camera, Rigid3d(), image, 1.0, "pinhole.png");
  cv::Mat expected;
  image.convertTo(expected, CV_32F, 1.0 / 65535.0);
  ASSERT_EQ(view.grey.size(), expected.size());
  // Every output pixel samples its own source pixel: a remap with zero
  // fractional weights copies it.
  EXPECT_LE(cv::norm(view.grey, expected, cv::NORM_INF), 1e-7);
  EXPECT_NEAR((view.K - ExpectedK(290.0, 295.0, 161.0, 119.5, 1.0)).norm(), 0.0,
              1e-12);
}

TEST(MakePinholeView, ColourAndEightBitImagesBecomeGreyInZeroToOne) {
  const Camera camera =
      MakeCamera(CameraModelId::kPinhole, {290.0, 295.0, 161.0, 119.5});
  cv::Mat bgr(240, 320, CV_8UC3);
  for (int row = 0; row < bgr.rows; ++row) {
    for (int col = 0; col < bgr.cols; ++col) {
      bgr.at<cv::Vec3b>(row, col) =
          cv::Vec3b(static_cast<uint8_t>((col * 7 + row) % 256),
                    static_cast<uint8_t>((row * 3) % 256),
                    static_cast<uint8_t>((col + 2 * row) % 256));
    }
  }
  cv::Mat grey_8u;
  cv::cvtColor(bgr, grey_8u, cv::COLOR_BGR2GRAY);
  cv::Mat expected;
  grey_8u.convertTo(expected, CV_32F, 1.0 / 255.0);

  const PinholeView from_bgr =
      MakePinholeView(camera, Rigid3d(), bgr, 1.0, "bgr.png");
  EXPECT_LE(cv::norm(from_bgr.grey, expected, cv::NORM_INF), 1e-7);

  cv::Mat bgra;
  cv::cvtColor(bgr, bgra, cv::COLOR_BGR2BGRA);
  const PinholeView from_bgra =
      MakePinholeView(camera, Rigid3d(), bgra, 1.0, "bgra.png");
  EXPECT_LE(cv::norm(from_bgra.grey, expected, cv::NORM_INF), 1e-7);

  const PinholeView from_grey =
      MakePinholeView(camera, Rigid3d(), grey_8u, 1.0, "grey.png");
  EXPECT_LE(cv::norm(from_grey.grey, expected, cv::NORM_INF), 1e-7);
}

TEST(MakePinholeView, HalfScaleHalvesSizeAndIntrinsics) {
  const double fx = 310.0, fy = 305.0, cx = 158.3, cy = 122.9;
  const Camera camera = MakeCamera(
      CameraModelId::kOpenCV, {fx, fy, cx, cy, -0.05, 0.01, 0.0005, 0.001});
  const PinholeView view = MakePinholeView(
      camera, Rigid3d(), SynthesiseImage(camera), 0.5, "half.png");
  EXPECT_EQ(view.Width(), 160);
  EXPECT_EQ(view.Height(), 120);
  // COLMAP's principal point scales with the image; OpenCV's is 0.5 px less.
  const Eigen::Matrix3d expected_K = ExpectedK(fx, fy, cx, cy, 0.5);
  EXPECT_NEAR((view.K - expected_K).norm(), 0.0, 1e-12) << view.K;

  // Source grid spacing 2 px of the full image: bound 0.0012 (curvature) +
  // 0.0011 (position quantisation) + 0.0003 (2x2 area averaging, A k^2 / 8
  // per term) = 0.0026.
  const PatternErrors errors = CompareWithPattern(view, camera, expected_K);
  EXPECT_GT(errors.num_inside, 150 * 110);
  EXPECT_LT(errors.max_error, InterpolationBound(2.0) + kCurvatureSum / 8.0);
}

TEST(MakePinholeView, OtherScalesRoundTheSize) {
  const Camera camera =
      MakeCamera(CameraModelId::kPinhole, {290.0, 295.0, 161.0, 119.5});
  const cv::Mat image = SynthesiseImage(camera);
  // 0.3 * 320 = 96, 0.3 * 240 = 72; 0.123 * 320 = 39.36, 0.123 * 240 = 29.52.
  const PinholeView small =
      MakePinholeView(camera, Rigid3d(), image, 0.3, "small.png");
  EXPECT_EQ(small.Width(), 96);
  EXPECT_EQ(small.Height(), 72);
  EXPECT_NEAR((small.K - ExpectedK(290.0, 295.0, 161.0, 119.5, 0.3)).norm(),
              0.0, 1e-12);
  const PinholeView odd =
      MakePinholeView(camera, Rigid3d(), image, 0.123, "odd.png");
  EXPECT_EQ(odd.Width(), 39);
  EXPECT_EQ(odd.Height(), 30);
  // Each axis scales by its own rounded ratio.
  EXPECT_NEAR(odd.K(0, 0), 290.0 * 39.0 / 320.0, 1e-12);
  EXPECT_NEAR(odd.K(1, 1), 295.0 * 30.0 / 240.0, 1e-12);
  EXPECT_NEAR(odd.K(0, 2), 161.0 * 39.0 / 320.0 - 0.5, 1e-12);
  EXPECT_NEAR(odd.K(1, 2), 119.5 * 30.0 / 240.0 - 0.5, 1e-12);
}

TEST(PinholeView, PixelAndCamAreInverse) {
  PinholeView view;
  view.K << 300.0, 0.0, 159.5, 0.0, 310.0, 120.25, 0.0, 0.0, 1.0;
  const Eigen::Vector3d point_in_cam = view.CamFromPixel(12.5, 200.0, 4.0);
  EXPECT_DOUBLE_EQ(point_in_cam.z(), 4.0);
  EXPECT_NEAR(point_in_cam.x(), 4.0 * (12.5 - 159.5) / 300.0, 1e-14);
  EXPECT_NEAR(point_in_cam.y(), 4.0 * (200.0 - 120.25) / 310.0, 1e-14);
  const Eigen::Vector2d pixel = view.PixelFromCam(point_in_cam);
  EXPECT_NEAR(pixel.x(), 12.5, 1e-12);
  EXPECT_NEAR(pixel.y(), 200.0, 1e-12);
}

TEST(MakePinholeView, BadInputsThrowNamingTheImage) {
  const Camera camera =
      MakeCamera(CameraModelId::kPinhole, {290.0, 295.0, 161.0, 119.5});
  const cv::Mat image = SynthesiseImage(camera);
  ExpectErrorContaining(
      [&] {
        MakePinholeView(camera, Rigid3d(), cv::Mat(240, 321, CV_8U), 1.0,
                        "dive3/img_0042.png");
      },
      "dive3/img_0042.png");
  ExpectErrorContaining(
      [&] {
        MakePinholeView(camera, Rigid3d(), cv::Mat(320, 240, CV_8U), 1.0,
                        "dive3/img_0042.png");
      },
      "320x240");
  ExpectErrorContaining(
      [&] {
        MakePinholeView(camera, Rigid3d(), cv::Mat(), 1.0, "missing.png");
      },
      "missing.png");
  for (const double scale :
       {0.0, -0.5, 1.5, std::numeric_limits<double>::quiet_NaN()}) {
    ExpectErrorContaining(
        [&] {
          MakePinholeView(camera, Rigid3d(), image, scale, "img_0007.png");
        },
        "img_0007.png");
  }
}

}  // namespace
}  // namespace uw
