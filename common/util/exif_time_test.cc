#include "common/util/exif_time.h"

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "common/util/error_testing.h"

namespace uw {
namespace {

namespace fs = std::filesystem;
using Bytes = std::vector<unsigned char>;

Bytes Encoded(const std::string& extension) {
  cv::Mat image(48, 64, CV_8UC3);
  cv::randu(image, cv::Scalar::all(0), cv::Scalar::all(255));
  Bytes bytes;
  EXPECT_TRUE(cv::imencode(extension, image, bytes));
  return bytes;
}

// What uwsim writes into its images, read back to the microsecond, the
// image still decoding to the same pixels: PNG (eXIf) and JPEG (APP1).
TEST(ExifCaptureTime, WrittenTimesReadBackInJpegAndPng) {
  for (const std::string extension : {".png", ".jpg"}) {
    const Bytes plain = Encoded(extension);
    EXPECT_FALSE(ReadExifCaptureTime(plain, "plain" + extension));
    const cv::Mat pixels = cv::imdecode(plain, cv::IMREAD_UNCHANGED);
    for (const int zone : {0, 7200, -19800}) {
      for (const double t : {1728410000.25, 1728410000.123456, 951868799.0}) {
        const Bytes stamped = WithExifCaptureTime(plain, t, zone);
        const std::optional<double> read =
            ReadExifCaptureTime(stamped, "stamped" + extension);
        ASSERT_TRUE(read) << extension;
        EXPECT_NEAR(*read, t, 5e-7) << extension << " zone " << zone;
        const cv::Mat decoded = cv::imdecode(stamped, cv::IMREAD_UNCHANGED);
        ASSERT_FALSE(decoded.empty()) << extension;
        EXPECT_EQ(cv::norm(decoded, pixels, cv::NORM_INF), 0.0) << extension;
      }
    }
    const Bytes stamped = WithExifCaptureTime(plain, 1728410000.25, 0);
    EXPECT_THROW(WithExifCaptureTime(stamped, 1.0, 0), Error);
  }
}

// A camera that does not state its clock's zone (OffsetTimeOriginal, EXIF
// 2.31, is recent): its time is refused unless the zone is given.
TEST(ExifCaptureTime, ATimeWithoutAZoneNeedsTheClocksZone) {
  Bytes stamped = WithExifCaptureTime(Encoded(".png"), 1728410000.25, 7200);
  const std::string offset = "+02:00";
  const auto at =
      std::search(stamped.begin(), stamped.end(), offset.begin(), offset.end());
  ASSERT_NE(at, stamped.end());
  std::fill(at, at + offset.size(), 0);  // the tag left blank
  const std::string message =
      ErrorOf([&] { ReadExifCaptureTime(stamped, "cam/0001.png"); });
  EXPECT_NE(message.find("cam/0001.png: EXIF DateTimeOriginal '2024:10:08 "
                         "19:53:20'"),
            std::string::npos)
      << message;
  EXPECT_NE(message.find("has no time zone"), std::string::npos) << message;
  EXPECT_EQ(ReadExifCaptureTime(stamped, "cam/0001.png", 7200), 1728410000.25);
  EXPECT_THROW(
      ReadExifCaptureTime(Bytes{'G', 'I', 'F', '8', '9', 'a'}, "x.gif"), Error);
}

// A phone's JPEGs (Pixel 7 Pro, ../shared/realdata/aprilgrid_samples):
// DateTimeOriginal, SubSecTimeOriginal and OffsetTimeOriginal as written
// by a real camera. The expected Unix times are Python's
// datetime.fromisoformat("2023-04-04T16:23:11.564-04:00").timestamp().
TEST(ExifCaptureTime, ReadsAPhonesJpegs) {
  const fs::path dir = fs::path(UW_REALDATA_DIR) / "aprilgrid_samples" /
                       "powei-lin_aprilgrid_pixel7pro";
  ASSERT_TRUE(fs::is_directory(dir))
      << dir << " is missing: the tests read ../shared/realdata";
  EXPECT_NEAR(*ReadExifCaptureTime(dir / "000.jpg"), 1680639791.564, 1e-6);
  EXPECT_NEAR(*ReadExifCaptureTime(dir / "004.jpg"), 1681049472.034, 1e-6);
}

}  // namespace
}  // namespace uw
