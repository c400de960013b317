// Issue 16, acceptance 2 (label heavy): is the covariance calibrated? 400
// re-adjustments of the rendered uwsim seafloor survey of the integration
// tests, with the navigation fused (gauge: the priors, so the errors are
// absolute) and prior-free (COLMAP's held gauge); tests/covariance_nees.h.
#include <filesystem>
#include <iostream>

#include <gtest/gtest.h>

#include "tests/covariance_nees.h"

namespace uw::testing {
namespace {

namespace fs = std::filesystem;

// 33 images, 4000 points (about 120 per image).
const fs::path kSeafloorDir = fs::path(UW_SURVEY_DIR) / "sim";
constexpr int kSeafloorPoints = 4000;

TEST(CovarianceNees, FusedAdjustmentsOfTheUwsimSurveyAreCalibrated) {
  const Nees nees =
      MeanNees(kSeafloorDir, {NeesGauge::kPriors, kSeafloorPoints});
  std::cout << NeesFigures("fused re-adjustments of the uwsim survey", nees)
            << "\n";
  ExpectCalibrated(nees);
}

// Prior-free: no navigation, COLMAP's held gauge; the focal length and k1
// self-calibrated from the images alone, as bundle_adjuster does by default.
TEST(CovarianceNees, PriorFreeAdjustmentsOfTheUwsimSurveyAreCalibrated) {
  const Nees nees = MeanNees(kSeafloorDir, {NeesGauge::kHeld, kSeafloorPoints});
  std::cout << NeesFigures(
                   "prior-free re-adjustments of the uwsim survey (held gauge)",
                   nees)
            << "\n";
  ExpectCalibrated(nees);
}

}  // namespace
}  // namespace uw::testing
