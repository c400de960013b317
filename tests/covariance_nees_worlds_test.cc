// Issue 16, acceptance 2, on the other worlds (label heavy): the check of
// covariance_nees_test.cc (tests/covariance_nees.h) on the lawnmower plans
// of the vent (15 images, a chimney far above its floor), the canyon (33,
// walls below the vehicle), the breakwater (21, a rubble slope) and the
// scarp (268, a wall surveyed with a starboard camera): uwsim generate
// --render_images 0 (the tracks need no pixels), each with the seed of its
// world's first survey in the laser-scale matrix (tests/CMakeLists.txt).
#include <filesystem>
#include <iostream>
#include <string>

#include <gtest/gtest.h>

#include "colmap_plugins/scene/model_io.h"
#include "tests/covariance_nees.h"

namespace uw::testing {
namespace {

namespace fs = std::filesystem;

class CovarianceNeesOnWorlds : public ::testing::TestWithParam<std::string> {
 protected:
  fs::path SimDir() const { return fs::path(UW_PLANS_DIR) / GetParam(); }
  // The seafloor survey's density, 120 points per image (4000 points on
  // the scarp's 268 images would leave images that see one).
  int NumPoints() const {
    return 120 *
           static_cast<int>(ReadModel(SimDir() / "truth").Images().size());
  }
};

// The breakwater's, canyon's and scarp's plans are single passes (or two
// stacked lines): positions alone leave the rotation about the pass to the
// centres' few-cm scatter, the adjuster warns (track_line.h), and the
// fusion a user is told to run there takes the log's attitude too.
bool OnOneLine(const std::string& world) { return world != "vent"; }

TEST_P(CovarianceNeesOnWorlds, FusedAdjustmentsAreCalibrated) {
  const bool attitude = OnOneLine(GetParam());
  const Nees nees =
      MeanNees(SimDir(), NeesGauge::kPriors, NumPoints(), attitude);
  std::cout << NeesFigures("fused re-adjustments of the " + GetParam() +
                               " plan" +
                               (attitude ? " (positions and attitude)"
                                         : " (positions)"),
                           nees)
            << "\n";
  ExpectCalibrated(nees);
}

TEST_P(CovarianceNeesOnWorlds, PriorFreeAdjustmentsAreCalibrated) {
  const Nees nees = MeanNees(SimDir(), NeesGauge::kHeld, NumPoints());
  std::cout << NeesFigures("prior-free re-adjustments of the " + GetParam() +
                               " plan (held gauge)",
                           nees)
            << "\n";
  ExpectCalibrated(nees);
}

// The free network (minimum trace, what photogrammetry reports without
// control) against errors under the same inner constraints.
TEST_P(CovarianceNeesOnWorlds, FreeNetworkAdjustmentsAreCalibrated) {
  const Nees nees = MeanNees(SimDir(), NeesGauge::kFreeNetwork, NumPoints());
  std::cout << NeesFigures(
                   "free-network re-adjustments of the " + GetParam() + " plan",
                   nees)
            << "\n";
  ExpectCalibrated(nees);
}

INSTANTIATE_TEST_SUITE_P(Plans, CovarianceNeesOnWorlds,
                         ::testing::Values("vent", "canyon", "breakwater",
                                           "scarp"),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                           return info.param;
                         });

}  // namespace
}  // namespace uw::testing
