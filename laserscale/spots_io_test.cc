#include "laserscale/spots_io.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include <gtest/gtest.h>

#include "common/util/error.h"

namespace uw {
namespace {

std::vector<ImageSpots> TwoImages() {
  DetectedSpot good;
  good.laser = "L1";
  good.detected = true;
  good.stable = true;
  good.detection_rate = 0.97;
  good.pixel = {312.25, 100.0 / 3.0};
  good.covariance << 0.0421, -0.0113, -0.0113, 0.0618;
  good.iterations = {{good.pixel, good.covariance}};
  DetectedSpot unstable = good;
  unstable.laser = "L2";
  unstable.stable = false;
  unstable.detection_rate = 0.43;
  unstable.problem = "unstable: detected in 43 % of iterations";
  DetectedSpot missing;
  missing.laser = "L3";
  missing.problem = "not detected";
  ImageSpots first{"L00002.png", "C", {good, unstable, missing}};
  ImageSpots second{"cam1/L00005.png", "C", {}};
  return {first, second};
}

std::string ReplaceFirst(std::string text, const std::string& from,
                         const std::string& to) {
  const size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

void ExpectError(const std::string& text, const std::string& part) {
  try {
    ParseSpotsJson(text, "spots.json");
    ADD_FAILURE() << "no error, expected \"" << part << "\"";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find(part), std::string::npos)
        << error.what();
  }
}

TEST(SpotsJson, RoundTripKeepsEveryBitButTheIterations) {
  const std::vector<ImageSpots> images = TwoImages();
  const std::string text = SpotsJsonText(images);
  const std::vector<ImageSpots> read = ParseSpotsJson(text, "test");
  ASSERT_EQ(read.size(), 2u);
  EXPECT_EQ(read[1].name, "cam1/L00005.png");
  EXPECT_TRUE(read[1].spots.empty());
  EXPECT_EQ(read[0].name, "L00002.png");
  EXPECT_EQ(read[0].setup, "C");
  ASSERT_EQ(read[0].spots.size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    const DetectedSpot& a = images[0].spots[i];
    const DetectedSpot& b = read[0].spots[i];
    EXPECT_EQ(a.laser, b.laser);
    EXPECT_EQ(a.detected, b.detected);
    EXPECT_EQ(a.stable, b.stable);
    EXPECT_EQ(a.detection_rate, b.detection_rate);
    EXPECT_EQ(a.pixel, b.pixel);
    EXPECT_EQ(a.covariance, b.covariance);
    EXPECT_EQ(a.problem, b.problem);
    EXPECT_TRUE(b.iterations.empty());
  }
  EXPECT_EQ(SpotsJsonText(read), text);

  const std::filesystem::path path =
      std::filesystem::path(::testing::TempDir()) / "spots_io_test.json";
  std::ofstream(path) << text;
  EXPECT_EQ(SpotsJsonText(ReadSpotsJson(path)), text);
  std::filesystem::remove(path);
}

TEST(SpotsJson, ReadingRejectsBadFilesNamingImageAndLaser) {
  const std::string text = SpotsJsonText(TwoImages());
  ExpectError("{", "spots.json: ");
  ExpectError(ReplaceFirst(text, "uwmetric-laser-spots", "uwmetric-lasers"),
              "expected format \"uwmetric-laser-spots\"");
  ExpectError(ReplaceFirst(text, "\"images\"", "\"imgs\""),
              "missing key \"images\"");
  ExpectError(
      ReplaceFirst(text, "\"setup\": \"C\"", "\"setup\": \"C\", \"camera\": 1"),
      "images[0] \"L00002.png\": unknown key \"camera\"");
  ExpectError(ReplaceFirst(text, "\"stable\": true", "\"stabel\": true"),
              "images[0] \"L00002.png\".spots[0]: unknown key \"stabel\"");
  ExpectError(ReplaceFirst(text, "\"detected\": true", "\"detected\": 1"),
              "spots[0].detected");
  ExpectError(ReplaceFirst(text, "\"laser\": \"L1\"", "\"laser\": 1"),
              "spots[0].laser");
  ExpectError(ReplaceFirst(text, "0.97", "\"high\""),
              "spots[0].detection_rate");
  ExpectError(ReplaceFirst(text, "0.97", "1.5"),
              "spots[0] (laser L1): detection_rate must be in [0, 1]");
  ExpectError(ReplaceFirst(text, "312.25", "null"),
              "spots[0] (laser L1).pixel: expected an array of 2 numbers");
  // nlohmann::json refuses numbers beyond double's range while parsing.
  ExpectError(ReplaceFirst(text, "312.25", "1e999"),
              "spots.json: [json.exception.out_of_range.406] number overflow");
  ExpectError(ReplaceFirst(text, "0.0421", "-0.0421"),
              "images[0] \"L00002.png\".spots[0] (laser L1): covariance not "
              "positive semi-definite");
  ExpectError(ReplaceFirst(text, "-0.0113", "0.0113"),
              "(laser L1): covariance not symmetric");
  ExpectError(ReplaceFirst(text, "\"laser\": \"L2\"", "\"laser\": \"L1\""),
              "laser L1 listed twice");
  ExpectError(ReplaceFirst(text, "cam1/L00005.png", "L00002.png"),
              "images[1] \"L00002.png\": image listed twice");
  ExpectError(ReplaceFirst(text, "\"detected\": true", "\"detected\": false"),
              "(laser L1): stable but not detected");
  EXPECT_THROW(ReadSpotsJson("/nonexistent/spots.json"), Error);
}

TEST(SpotsJson, WritingRejectsNonFiniteAndNonPsd) {
  std::vector<ImageSpots> images = TwoImages();
  images[0].spots[1].pixel.x() = std::numeric_limits<double>::quiet_NaN();
  try {
    SpotsJsonText(images);
    ADD_FAILURE() << "no error";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what())
                  .find("image \"L00002.png\", laser L2: pixel not finite"),
              std::string::npos)
        << error.what();
  }
  images = TwoImages();
  images[0].spots[0].covariance(1, 1) = -1.0;
  EXPECT_THROW(SpotsJsonText(images), Error);
}

}  // namespace
}  // namespace uw
