// uwcolmap bundle_adjuster and lcurve: navigation-fused bundle adjustment
// (colmap_plugins/ba/nav_bundle_adjustment_controller.h).
#pragma once

#include <string>

#include "colmap_plugins/ba/bundle_covariance.h"
#include "colmap_plugins/ba/nav_bundle_adjustment_controller.h"
#include "common/cli/command.h"

namespace uw {

struct BundleAdjusterOptions {
  NavBundleAdjustmentControllerOptions adjustment;
  // The adjusted model (input's layout and format) and ba_report.json.
  std::string output_path;
  // --BA.covariance: also the covariance of the adjusted model, in
  // output_path/covariance (covariance_estimator's files).
  bool covariance = false;
  BundleCovarianceOptions covariance_options;

  // The output is not the input folder, and the adjustment's rules.
  void Check() const;
};
Subcommand BundleAdjusterCommand();

// `uwcolmap covariance_estimator`: the covariance of a model under the
// adjustment bundle_adjuster would solve with the same flags.
struct CovarianceEstimatorOptions {
  std::string input_path;
  NavInputOptions priors;
  NavBundleAdjustmentOptions adjuster;
  BundleCovarianceOptions covariance;
  std::string output_path;  // a new or empty folder for the five files

  void Check() const;
};
Subcommand CovarianceEstimatorCommand();

struct LCurveCommandOptions {
  NavLCurveOptions lcurve;
  std::string output_path;  // lcurve.json and the figures

  void Check() const { lcurve.Check(); }
};
Subcommand LCurveCommand();

}  // namespace uw
