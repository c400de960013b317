#include "laserscale/aux_alignment.h"

#include <gtest/gtest.h>
#include <Eigen/Core>
#include <opencv2/imgproc.hpp>

#include "laserscale/spot_detector.h"
#include "laserscale/spot_detector_testing.h"

namespace uw {
namespace {

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

// An aux whose levels are a gain and offset of the image's: matching maps
// them back.
TEST(MatchHistogram, UndoesAGainAndOffset) {
  cv::Mat main(40, 40, CV_32F);
  for (int r = 0; r < main.rows; ++r) {
    for (int c = 0; c < main.cols; ++c) {
      main.at<float>(r, c) = static_cast<float>(20 + (r * 40 + c) % 150);
    }
  }
  cv::Mat aux = 0.8 * main + 10.0;
  const cv::Mat mask(main.size(), CV_8U, cv::Scalar(255));
  lsd::MatchHistogram(main, mask, &aux);
  EXPECT_LT(cv::norm(aux, main, cv::NORM_INF), 1.0);
}

// The aux is the image's texture moved by the camera: the alignment finds
// the motion, and the aligned aux shows what the image shows.
TEST(AlignAux, FindsTheCameraMotion) {
  const Camera camera = PinholeCamera(320, 240, 400.0);
  const cv::Mat texture = Texture(320, 240, 5);
  const Eigen::Vector2d motion(4.3, -2.6);
  const cv::Mat shift =
      (cv::Mat_<double>(2, 3) << 1, 0, motion.x(), 0, 1, motion.y());
  cv::Mat moved;
  cv::warpAffine(texture, moved, shift, texture.size(), cv::INTER_LINEAR,
                 cv::BORDER_REFLECT);
  const Eigen::Matrix2d shape = Eigen::Matrix2d::Identity();
  const cv::Mat image = WithSpot(texture, {180.0, 120.0}, 0.0, shape, 0.0, 1);
  const cv::Mat aux = WithSpot(moved, {180.0, 120.0}, 0.0, shape, 0.0, 1);
  const SpotDetectorOptions options;
  std::vector<lsd::Roi> rois =
      lsd::PredictRois(image, camera, OneLaser(), options);
  lsd::Roi& roi = rois[0];
  lsd::AlignAux(image, aux, options, &roi);
  ASSERT_TRUE(roi.texture_note.empty()) << roi.texture_note;
  // The aux's pixel p shows what the image shows at p - motion.
  const Eigen::Vector2d p(40.0, 24.0);
  EXPECT_LT((lsd::AuxView(roi, p) - (p - motion)).norm(), 0.1)
      << lsd::AuxView(roi, p).transpose();
  cv::Mat difference = cv::abs(roi.main - roi.aux);
  cv::Mat inner;
  cv::erode(roi.valid, inner, cv::Mat(), cv::Point(-1, -1), 3);
  EXPECT_LT(cv::mean(difference, inner)[1], 1.5);
}

}  // namespace
}  // namespace uw
