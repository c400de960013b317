#include "laserscale/spot_detector_options.h"

#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "common/util/error.h"

namespace uw {
namespace {

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

}  // namespace
}  // namespace uw
