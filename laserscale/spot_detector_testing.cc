#include "laserscale/spot_detector_testing.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "common/util/random.h"

namespace uw {

Camera PinholeCamera(int width, int height, double focal) {
  Camera camera;
  camera.camera_id = 1;
  camera.model_id = CameraModelId::kPinhole;
  camera.width = width;
  camera.height = height;
  camera.params = {focal, focal, width / 2.0, height / 2.0};
  return camera;
}

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

}  // namespace uw
