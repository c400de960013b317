#include "laserscale/spot_detector_options.h"

#include <cmath>

#include "common/util/error.h"

namespace uw {

void SpotDetectorOptions::Check() const {
  const auto fail = [](const char* field, double value, const char* rule) {
    throw ErrorAt("spot detector options: ", field, " = ", value, ": ", rule);
  };
  if (!(min_range_m > 0.0)) fail("min_range_m", min_range_m, "must be > 0");
  if (!(max_range_m > min_range_m && std::isfinite(max_range_m))) {
    fail("max_range_m", max_range_m, "must be finite and > min_range_m");
  }
  if (roi_margin_px < 0) fail("roi_margin_px", roi_margin_px, "must be >= 0");
  if (aux_search_px < 0) fail("aux_search_px", aux_search_px, "must be >= 0");
  if (!(min_alignment_ncc >= -1.0 && min_alignment_ncc <= 1.0)) {
    fail("min_alignment_ncc", min_alignment_ncc, "must be in [-1, 1]");
  }
  if (ecc_iterations < 1)
    fail("ecc_iterations", ecc_iterations, "must be >= 1");
  if (!(lowpass_sigma_px >= 0.0 && lowpass_sigma_px <= 10.0)) {
    fail("lowpass_sigma_px", lowpass_sigma_px, "must be in [0, 10]");
  }
  if (!(hue_tolerance_deg > 0.0 && hue_tolerance_deg <= 180.0)) {
    fail("hue_tolerance_deg", hue_tolerance_deg, "must be in (0, 180]");
  }
  if (!(min_saturation >= 0.0 && min_saturation <= 1.0)) {
    fail("min_saturation", min_saturation, "must be in [0, 1]");
  }
  if (!(value_threshold_sigmas >= 0.0 &&
        std::isfinite(value_threshold_sigmas))) {
    fail("value_threshold_sigmas", value_threshold_sigmas, "must be >= 0");
  }
  if (!(min_value >= 0.0 && min_value < 255.0)) {
    fail("min_value", min_value, "must be in [0, 255)");
  }
  if (opening_radius_px < 0 || opening_radius_px > 10) {
    fail("opening_radius_px", opening_radius_px, "must be in [0, 10]");
  }
  if (min_area_px < 1) fail("min_area_px", min_area_px, "must be >= 1");
  if (max_area_px < min_area_px) {
    fail("max_area_px", max_area_px, "must be >= min_area_px");
  }
  if (!((max_colour_angle_deg > 0.0 && max_colour_angle_deg < 90.0) ||
        max_colour_angle_deg == 180.0)) {
    fail("max_colour_angle_deg", max_colour_angle_deg,
         "must be in (0, 90), or 180 (no colour test)");
  }
  if (!(colour_noise_sigmas >= 0.0 && std::isfinite(colour_noise_sigmas))) {
    fail("colour_noise_sigmas", colour_noise_sigmas, "must be >= 0");
  }
  if (fit_margin_px < 0 || fit_margin_px > 20) {
    fail("fit_margin_px", fit_margin_px, "must be in [0, 20]");
  }
  if (!(saturation_level > 0.0 && saturation_level <= 255.0)) {
    fail("saturation_level", saturation_level, "must be in (0, 255]");
  }
  if (!(top_fraction > 0.0 && top_fraction < 1.0)) {
    fail("top_fraction", top_fraction, "must be in (0, 1)");
  }
  if (!(confidence > 0.0 && confidence < 1.0)) {
    fail("confidence", confidence, "must be in (0, 1)");
  }
  if (monte_carlo_iterations < 0) {
    fail("monte_carlo_iterations", monte_carlo_iterations, "must be >= 0");
  }
  if (!(min_detection_rate >= 0.0 && min_detection_rate <= 1.0)) {
    fail("min_detection_rate", min_detection_rate, "must be in [0, 1]");
  }
  if (!(noise_sigma < 255.0) || std::isnan(noise_sigma)) {
    fail("noise_sigma", noise_sigma, "must be < 255 (< 0: estimate)");
  }
}

}  // namespace uw
