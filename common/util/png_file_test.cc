#include "common/util/png_file.h"

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include "common/util/error_testing.h"
#include "common/util/file.h"

namespace uw {
namespace {

TEST(PngFile, WritesTheImageLosslessly) {
  cv::Mat image(3, 4, CV_8UC3, cv::Scalar(10, 20, 30));
  image.at<cv::Vec3b>(1, 2) = cv::Vec3b(255, 0, 7);
  const std::filesystem::path path =
      std::filesystem::path(testing::TempDir()) / "png_file" / "a.png";
  WritePngAtomically(image, path);
  const cv::Mat read = cv::imread(path.string(), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(read.size(), image.size());
  EXPECT_EQ(cv::norm(read, image, cv::NORM_INF), 0.0);
}

TEST(PngFile, AnEmptyImageIsAnErrorNamingTheFile) {
  ExpectErrorContaining([] { EncodePng(cv::Mat(), "out/map.png"); },
                        "out/map.png: cannot encode");
}

}  // namespace
}  // namespace uw
