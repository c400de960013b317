#include "experiments/views_experiment_io.h"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "common/util/error.h"
#include "common/util/error_testing.h"

namespace uw {
namespace {

TEST(ParseShotNoise, TwoToFourSigmas) {
  const ShotNoise two = ParseShotNoise("0.5:0.25");
  EXPECT_EQ(two.feature_px, 0.5);
  EXPECT_EQ(two.spot_px, 0.25);
  EXPECT_EQ(two.direction_deg, 0.0);
  EXPECT_EQ(two.origin_m, 0.0);
  const ShotNoise four = ParseShotNoise("1:2:0.1:0.002");
  EXPECT_EQ(four.direction_deg, 0.1);
  EXPECT_EQ(four.origin_m, 0.002);
  EXPECT_EQ(ShotNoiseText(two), "0.5:0.25");
  EXPECT_EQ(ShotNoiseText(four), "1:2:0.1:0.002");
  EXPECT_EQ(ShotNoiseText(ShotNoise()), "0:0");
  EXPECT_EQ(ShotNoiseText(ParseShotNoise("1:2:0.5")), "1:2:0.5");
}

TEST(ParseShotNoise, NamesTheFlag) {
  EXPECT_EQ(ErrorOf([] { ParseShotNoise("0.5"); }),
            "--noise: expected feature_px:spot_px[:direction_deg"
            "[:origin_m]], got '0.5'");
  EXPECT_EQ(ErrorOf([] { ParseShotNoise("1:2:3:4:5"); }),
            "--noise: expected feature_px:spot_px[:direction_deg"
            "[:origin_m]], got '1:2:3:4:5'");
  EXPECT_EQ(ErrorOf([] { ParseShotNoise("0.5:x"); }),
            "--noise: 'x' is not a number");
  EXPECT_EQ(ErrorOf([] { ParseShotNoise("0.5:1a"); }),
            "--noise: '1a' is not a number");
  EXPECT_EQ(ErrorOf([] { ParseShotNoise("-1:0"); }),
            "noise: standard deviations must be finite and >= 0");
}

TEST(ViewsExperimentCsv, OneLinePerRowAndPerImage) {
  ViewsExperimentRow row;
  row.setup = "A";
  row.distance_m = 2.0;
  row.noise = ParseShotNoise("0.5:0.25");
  row.method = ScaleMethod::kPcm;
  row.num_views = 289;
  row.num_unlocalized = 1;
  row.items = {576, 2, 0.001, 0.0025, 0.01};
  row.images = {288, 0, -0.0005, 0.002, 0.008};
  row.image_errors = {{-40.0, 5.0, 0.00125},
                      {0.0, 0.0, std::numeric_limits<double>::quiet_NaN()}};
  EXPECT_EQ(
      AccuracyCsvText({row}),
      "setup,distance_m,feature_px,spot_px,direction_deg,origin_m,"
      "method,num_views,num_unlocalized,items_n,items_invalid,"
      "items_mean_pct,items_std_pct,items_max_abs_pct,images_n,"
      "images_invalid,images_mean_pct,images_std_pct,"
      "images_max_abs_pct\n"
      "A,2,0.5,0.25,0,0,pcm,289,1,576,2,0.1,0.25,1,288,0,-0.05,0.2,0.8\n");
  EXPECT_EQ(ViewsCsvText({row}),
            "setup,distance_m,feature_px,spot_px,method,pitch_deg,roll_deg,"
            "scale_error_pct\n"
            "A,2,0.5,0.25,pcm,-40,5,0.125\n"
            "A,2,0.5,0.25,pcm,0,0,\n");
}

}  // namespace
}  // namespace uw
