// The method of `uwcolmap bundle_adjuster` and `uwcolmap lcurve`: the
// priors loaded for the model, the model brought into the navigation's
// frame, lambda chosen (noise levels, L-curve corner or balance, or given),
// the navigation-fused adjustment (or the plain one and a similarity to the
// navigation afterwards), and what the run did. Progress reaches the caller
// as lines of text (libraries never print); the executables print them.
#pragma once

#include <functional>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "colmap_plugins/align/sim3.h"
#include "colmap_plugins/ba/lcurve.h"
#include "colmap_plugins/ba/nav_bundle_adjuster.h"
#include "colmap_plugins/ba/nav_inputs.h"
#include "colmap_plugins/ba/noise_levels.h"
#include "colmap_plugins/scene/model.h"

namespace uw {

// Where the navigation enters.
enum class NavStrategy {
  kPrior,      // inside the adjustment (the thesis's multiobjective BA)
  kPosterior,  // a plain adjustment, then a similarity to the navigation
               // (what colmap bundle_adjuster + model_aligner do)
};
std::string NavStrategyName(NavStrategy strategy);  // "prior", "posterior"
// Throws uw::Error naming --Nav.strategy.
NavStrategy NavStrategyFromName(const std::string& name);

// How lambda = sigma_v / sigma_n is chosen (--Nav.weight).
enum class NavWeightSelection {
  kNoiseLevels,    // "auto": both noise levels estimated (noise_levels.h)
  kLCurveCorner,   // "corner": the L-curve's maximum-curvature corner
  kLCurveBalance,  // "balance": the L-curve's balance point
  kFixed,          // a number, px/m
};
struct NavWeight {
  NavWeightSelection selection = NavWeightSelection::kNoiseLevels;
  double fixed_px_per_m = 0.0;  // kFixed only
};
// "auto", "corner", "balance" or a number (px/m); throws uw::Error naming
// --Nav.weight otherwise.
NavWeight NavWeightFromText(const std::string& text);
std::string NavWeightText(const NavWeight& weight);

// Progress, one line at a time, without its newline.
using ProgressLines = std::function<void(const std::string& line)>;

struct NavBundleAdjustmentControllerOptions {
  // The model's folder: named in messages and in ba_report.json.
  std::string input_path;
  NavInputOptions priors;
  // COLMAP's BundleAdjustment.* and the --Nav.*, --Dive.*, --Rig.interpolate
  // and --num_threads options; weight_px_per_m is set from `weight`.
  NavBundleAdjustmentOptions adjuster;
  NavStrategy strategy = NavStrategy::kPrior;
  NavWeight weight;
  // Adjustments in the L-curve sweep of a corner or balance weight.
  int lcurve_steps = 21;

  // Every rule between the fields: attitudes and dive offsets need the
  // navigation, the prior sigmas (NavInputOptions::Check), the adjuster's
  // own (NavBundleAdjustmentOptions::Check).
  void Check() const;
};

struct NavBundleAdjustmentResult {
  size_t num_priors = 0;  // images of the model with a prior
  NavBundleAdjustmentReport report;
  std::optional<NoiseLevels> noise_levels;  // auto, corner, balance
  std::optional<LCurve> lcurve;             // corner, balance
  // Posterior strategy with priors: the similarity applied after the plain
  // adjustment.
  std::optional<Sim3d> world_from_adjusted_model;
  // The priors' frame (NavInputs::world_frame), world_frame.json's.
  std::optional<NavLogFrame> world_frame;
  // From the initial alignment to the end of the adjustment.
  double total_time_s = 0.0;
};

// Loads the priors of `model` (read from options.input_path), adjusts it in
// place as options say and returns what was done. Without priors it is a
// plain adjustment. Throws uw::Error for bad input (the model unchanged up
// to the alignment), an L-curve without the chosen point, or whatever the
// adjuster refuses.
NavBundleAdjustmentResult AdjustModelWithNavigation(
    const NavBundleAdjustmentControllerOptions& options, Reconstruction* model,
    const ProgressLines& progress = nullptr);

// The same with the priors already loaded (the first two progress lines,
// the model's and the priors' sizes, come from the function above).
NavBundleAdjustmentResult AdjustModelWithNavigation(
    const NavBundleAdjustmentControllerOptions& options,
    const NavInputs& inputs, Reconstruction* model,
    const ProgressLines& progress = nullptr);

// The terms' table, the dive offsets (with --Dive.offsets), the prior
// residuals per dive and the solver's line, as bundle_adjuster prints them
// after the adjustment; `model` is the adjusted one.
std::string FormatNavBundleAdjustmentSummary(
    const NavBundleAdjustmentControllerOptions& options,
    const NavBundleAdjustmentResult& result, const Reconstruction& model);

// ba_report.json (docs/formats.md): the report, the run's inputs under
// "run", the total time and the L-curve when there was one.
nlohmann::json NavBundleAdjustmentJson(
    const NavBundleAdjustmentControllerOptions& options,
    const NavBundleAdjustmentResult& result, const Reconstruction& model);

// `uwcolmap lcurve`: the sweep of lambda around the noise-level estimate.
struct NavLCurveOptions {
  std::string input_path;  // the model's folder, for messages
  NavInputOptions priors;
  NavBundleAdjustmentOptions adjuster;
  // The swept range, px/m; 0: the noise-level lambda / 30 (min) or * 30
  // (max).
  double lambda_min = 0.0;
  double lambda_max = 0.0;
  int steps = 25;

  void Check() const;  // the rules of NavBundleAdjustmentControllerOptions
};

struct NavLCurveResult {
  NoiseLevels noise_levels;
  LCurve curve;
  // What the alignment onto the priors found suspect (or accepted).
  std::vector<std::string> warnings;
};

// Loads the priors of `model` (a copy is aligned to them and swept; the
// model itself is not changed). Throws uw::Error without priors.
NavLCurveResult SweepModelLCurve(const NavLCurveOptions& options,
                                 const Reconstruction& model,
                                 const ProgressLines& progress = nullptr);

// Corner, balance point and the noise-level lambda, as lcurve prints them.
std::string FormatNavLCurveSummary(const NavLCurveResult& result);

}  // namespace uw
