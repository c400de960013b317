#include "colmap_plugins/nav/image_time_source.h"

#include <cmath>
#include <fstream>
#include <iostream>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "common/util/error_testing.h"
#include "common/util/exif_time.h"
#include "sim/generate.h"
#include "sim/test_sim_config.h"
#include "tests/support/process.h"

namespace uw {
namespace {

namespace fs = std::filesystem;

TEST(TimeInFileName, ReadsTheFieldsOfAPattern) {
  EXPECT_EQ(TimeInFileName("IMG_20241008_175320_250", "IMG_%Y%m%d_%H%M%S_%f"),
            "2024-10-08T17:53:20.250");
  EXPECT_EQ(TimeInFileName("dive3-2024-10-08T17.53.20+0200-cam2",
                           "*-%Y-%m-%dT%H.%M.%S%z-*"),
            "2024-10-08T17:53:20+0200");
  EXPECT_EQ(TimeInFileName("100%_20241008175320", "100%%_%Y%m%d%H%M%S"),
            "2024-10-08T17:53:20");
  EXPECT_FALSE(TimeInFileName("GOPR0123", "IMG_%Y%m%d_%H%M%S"));
  EXPECT_FALSE(TimeInFileName("IMG_2024108_175320", "IMG_%Y%m%d_%H%M%S"));
  EXPECT_NE(
      ErrorOf([] { TimeInFileName("x", "IMG_%Y%m%d_%H%M"); }).find("has no %S"),
      std::string::npos);
  EXPECT_NE(
      ErrorOf([] { TimeInFileName("x", "%Y%m%d%H%M%S%q"); }).find("unknown %q"),
      std::string::npos);
  EXPECT_NE(
      ErrorOf([] { TimeInFileName("x", "%Y%m%d%H%M%S%S"); }).find("%S twice"),
      std::string::npos);
}

void WriteStampedPng(const fs::path& path, std::optional<double> time,
                     int zone_offset_s) {
  fs::create_directories(path.parent_path());
  std::vector<unsigned char> bytes;
  cv::imencode(".png", cv::Mat(8, 8, CV_8UC1, cv::Scalar(7)), bytes);
  if (time) bytes = WithExifCaptureTime(bytes, *time, zone_offset_s);
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()), bytes.size());
}

// Names as COLMAP's database has them (below --image_path, '/'), times in
// UTC whatever the camera's zone, the clock offset added; images without
// a time are named, not skipped.
TEST(ReadImageTimesFromImages, ExifTimesOfAFolderTree) {
  const fs::path dir = testing::FreshTestDir("uw_image_time_source");
  WriteStampedPng(dir / "cam2" / "b.png", 1728410001.5, -19800);
  WriteStampedPng(dir / "a.png", 1728410000.25, 7200);
  std::ofstream(dir / "notes.txt") << "not an image\n";
  ImageTimesFromImagesOptions options;
  options.image_path = dir.string();
  options.clock_offset_s = 0.5;
  size_t calls = 0;
  const ImageTimesFromImages read =
      ReadImageTimesFromImages(options, [&](size_t done, size_t total) {
        ++calls;
        EXPECT_EQ(total, 2u);
        EXPECT_EQ(done, calls);
      });
  EXPECT_EQ(calls, 2u);
  ASSERT_EQ(read.times.size(), 2u);
  EXPECT_EQ(read.times[0].image_name, "a.png");
  EXPECT_EQ(read.times[1].image_name, "cam2/b.png");
  EXPECT_EQ(read.times[0].time_s, 1728410000.75);
  EXPECT_EQ(read.times[1].time_s, 1728410002.0);
  EXPECT_EQ(read.zone_stated, 2);
  const std::string csv = ImageTimesCsvText(read.times, "from EXIF");
  EXPECT_EQ(csv,
            "# from EXIF\nimage_name,time\na.png,1728410000.75\n"
            "cam2/b.png,1728410002\n");

  WriteStampedPng(dir / "cam2" / "c.png", std::nullopt, 0);
  EXPECT_NE(ErrorOf([&] { ReadImageTimesFromImages(options); })
                .find(": 1 of 3 images have no EXIF capture time "
                      "(DateTimeOriginal): cam2/c.png"),
            std::string::npos);
  options.source = ImageTimeSource::kFileName;
  EXPECT_NE(ErrorOf([&] {
              ReadImageTimesFromImages(options);
            }).find("--source filename needs --filename_pattern"),
            std::string::npos);
}

// Acceptance 1 (issue 17), "EXIF times round-trip": uwsim renders a survey
// with a rig on a camera clock two hours east of UTC, its capture times in
// each PNG's EXIF; the times read back from the images are uwsim's
// image_times.csv to the microsecond.
TEST(ReadImageTimesFromImages, UwsimsExifTimesAreItsImageTimes) {
  sim::SimConfig config = sim::SmallSimConfig();
  config.survey_options.max_images = 6;
  config.lasers.every_nth_image = 0;
  config.rig.cameras.resize(1);
  config.rig.cameras[0].camera = config.camera;
  config.rig.cameras[0].time_offset_s = 0.0301;
  config.logs.clock_start = "2024-10-08T12:00:00.125+02:00";
  config.logs.exif_times = true;
  config.logs.camera_zone = "+02:00";
  const fs::path dir = testing::FreshTestDir("uw_image_time_source_uwsim");
  sim::Generate(config, dir / "sim");
  ImageTimesFromImagesOptions options;
  options.image_path = (dir / "sim" / "images").string();
  const ImageTimesFromImages read = ReadImageTimesFromImages(options);
  const std::vector<ImageTime> truth =
      ReadImageTimesCsv(dir / "sim" / "image_times.csv");
  ASSERT_EQ(read.times.size(), truth.size());
  EXPECT_EQ(read.zone_stated, static_cast<int>(truth.size()));
  std::map<std::string, double> true_times;
  for (const ImageTime& time : truth) true_times[time.image_name] = time.time_s;
  double worst = 0.0;
  for (const ImageTime& time : read.times) {
    ASSERT_EQ(true_times.count(time.image_name), 1u) << time.image_name;
    worst =
        std::max(worst, std::abs(time.time_s - true_times[time.image_name]));
  }
  std::cout << "[ figures ] " << read.times.size()
            << " images: EXIF times against image_times.csv, largest "
               "difference "
            << worst << " s\n";
  EXPECT_LT(worst, 1e-6);
  EXPECT_NEAR(truth.front().time_s, 1728381600.125, 60.0);
}

}  // namespace
}  // namespace uw
