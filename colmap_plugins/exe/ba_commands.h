// uwcolmap bundle_adjuster and lcurve: navigation-fused bundle adjustment
// (colmap_plugins/ba/nav_bundle_adjustment_controller.h).
#pragma once

#include <string>

#include "colmap_plugins/ba/nav_bundle_adjustment_controller.h"
#include "common/cli/command.h"

namespace uw {

struct BundleAdjusterOptions {
  NavBundleAdjustmentControllerOptions adjustment;
  // The adjusted model (input's layout and format) and ba_report.json.
  std::string output_path;

  // The output is not the input folder, and the adjustment's rules.
  void Check() const;
};
Subcommand BundleAdjusterCommand();

struct LCurveCommandOptions {
  NavLCurveOptions lcurve;
  std::string output_path;  // lcurve.json and lcurve.png

  void Check() const { lcurve.Check(); }
};
Subcommand LCurveCommand();

}  // namespace uw
