#include "colmap_plugins/ba/nav_bundle_adjustment_controller.h"

#include <chrono>
#include <map>
#include <set>
#include <sstream>

#include <fmt/format.h>

#include "colmap_plugins/ba/ba_report.h"
#include "colmap_plugins/ba/prior_alignment.h"
#include "colmap_plugins/ba/scale_transfer.h"
#include "colmap_plugins/ba/track_line.h"
#include "common/util/error.h"

namespace uw {
namespace {

// The flag of NavInputOptions::plausibility.accept_implausible.
constexpr char kAcceptFlag[] = "--Nav.accept_implausible";

void Emit(const ProgressLines& progress, const std::string& line) {
  if (progress) progress(line);
}

// Attitudes with covariances and dives are in no COLMAP database.
void CheckNavAdjustment(const NavInputOptions& priors,
                        const NavBundleAdjustmentOptions& adjuster) {
  if ((adjuster.use_attitude || adjuster.dive_offsets) &&
      !priors.HasNavigation()) {
    throw ErrorAt(
        "--Nav.use_attitude and --Dive.offsets need --nav (a "
        "database stores neither attitudes with covariances nor "
        "dives)");
  }
  priors.Check();
  adjuster.Check();
}

// The noise levels behind --Nav.weight auto, with their two lines.
NoiseLevels EstimateAndReportNoiseLevels(
    const NavBundleAdjustmentOptions& adjuster, const NavInputs& inputs,
    const Reconstruction& model, const ProgressLines& progress) {
  Emit(progress,
       "Noise levels: images-only adjustment, then its similarity to the "
       "navigation");
  const NoiseLevels levels =
      EstimateNoiseLevels(adjuster, inputs.priors, model, inputs.image_times);
  if (levels.difference_nav_scale > 0.0) {
    Emit(progress,
         fmt::format("  navigation residuals x{:g} of the stated sigmas; "
                     "from image to image x{:g} (over 2 images x{:g})",
                     levels.fit_nav_scale, levels.difference_nav_scale,
                     levels.difference_lag2_nav_scale));
  }
  Emit(progress,
       fmt::format("  sigma_v = {:g} px ({:g} dof), sigma_n = {:g} m ({:g} "
                   "dof; stated {:g} m, x{:g}): lambda = {:g} px/m",
                   levels.pixel_sigma, levels.reprojection_dof,
                   levels.nav_sigma_m, levels.navigation_dof,
                   levels.stated_nav_sigma_m, levels.nav_scale,
                   levels.weight_px_per_m));
  return levels;
}

// The L-curve over lambda / 30 .. lambda * 30 around the noise-level
// estimate (or the given bounds), a line per adjustment.
LCurve SweepAroundEstimate(const NavBundleAdjustmentOptions& adjuster,
                           const NavInputs& inputs, const Reconstruction& model,
                           const NoiseLevels& levels, int steps,
                           double lambda_min, double lambda_max,
                           const ProgressLines& progress) {
  const double low =
      lambda_min > 0.0 ? lambda_min : levels.weight_px_per_m / 30.0;
  const double high =
      lambda_max > 0.0 ? lambda_max : levels.weight_px_per_m * 30.0;
  Emit(progress, fmt::format("L-curve: {} adjustments, lambda from {:g} to "
                             "{:g} px/m",
                             steps, low, high));
  LCurve curve = SweepLCurve(
      adjuster, inputs.priors, inputs.rig ? &*inputs.rig : nullptr,
      inputs.image_times, model, LogSpacedWeights(low, high, steps),
      [&progress](size_t i, size_t n, const LCurvePoint& point) {
        Emit(progress,
             fmt::format("  [{}/{}] lambda {:g} px/m: reprojection MS {:g} "
                         "px^2, navigation MS {:g} m^2",
                         i, n, point.weight_px_per_m, point.reprojection_ms_px2,
                         point.navigation_ms_m2));
      });
  curve.noise_weight_px_per_m = levels.weight_px_per_m;
  return curve;
}

nlohmann::json NoiseLevelsJson(const NoiseLevels& levels) {
  return {{"pixel_sigma_px", levels.pixel_sigma},
          {"reprojection_dof", levels.reprojection_dof},
          {"nav_sigma_m", levels.nav_sigma_m},
          {"stated_nav_sigma_m", levels.stated_nav_sigma_m},
          {"nav_scale", levels.nav_scale},
          {"fit_nav_scale", levels.fit_nav_scale},
          {"difference_nav_scale", levels.difference_nav_scale},
          {"difference_lag2_nav_scale", levels.difference_lag2_nav_scale},
          {"navigation_dof", levels.navigation_dof},
          {"weight_px_per_m", levels.weight_px_per_m}};
}

// Eigen's own layout of a vector (space-separated, padded to one width), as
// the offsets have always been printed.
std::string RowText(const Eigen::Vector3d& vector) {
  std::ostringstream text;
  text << vector.transpose();
  return text.str();
}

}  // namespace

std::string NavStrategyName(NavStrategy strategy) {
  return strategy == NavStrategy::kPrior ? "prior" : "posterior";
}

NavStrategy NavStrategyFromName(const std::string& name) {
  if (name == "prior") return NavStrategy::kPrior;
  if (name == "posterior") return NavStrategy::kPosterior;
  throw ErrorAt("--Nav.strategy ", name, ": prior or posterior");
}

NavWeight NavWeightFromText(const std::string& text) {
  NavWeight weight;
  if (text == "auto") return weight;
  if (text == "corner" || text == "balance") {
    weight.selection = text == "corner" ? NavWeightSelection::kLCurveCorner
                                        : NavWeightSelection::kLCurveBalance;
    return weight;
  }
  try {
    weight.fixed_px_per_m = std::stod(text);
  } catch (const std::exception&) {
    throw ErrorAt("--Nav.weight ", text,
                  ": a number (px/m), auto, corner or balance");
  }
  weight.selection = NavWeightSelection::kFixed;
  return weight;
}

std::string NavWeightText(const NavWeight& weight) {
  switch (weight.selection) {
    case NavWeightSelection::kNoiseLevels:
      return "auto";
    case NavWeightSelection::kLCurveCorner:
      return "corner";
    case NavWeightSelection::kLCurveBalance:
      return "balance";
    case NavWeightSelection::kFixed:
      break;
  }
  return fmt::format("{:g}", weight.fixed_px_per_m);
}

void NavBundleAdjustmentControllerOptions::Check() const {
  CheckNavAdjustment(priors, adjuster);
}

void NavLCurveOptions::Check() const { CheckNavAdjustment(priors, adjuster); }

NavBundleAdjustmentResult AdjustModelWithNavigation(
    const NavBundleAdjustmentControllerOptions& options, Reconstruction* model,
    const ProgressLines& progress) {
  options.Check();
  const NavInputs inputs =
      LoadNavInputs(options.priors, *model, options.input_path);
  const bool has_rotations =
      std::any_of(inputs.priors.begin(), inputs.priors.end(),
                  [](const ImagePosePrior& prior) {
                    return prior.cam_from_world_rotation.has_value();
                  });
  if (options.adjuster.use_attitude && !inputs.priors.empty() &&
      !has_rotations) {
    throw ErrorAt("--Nav.use_attitude 1: ", options.priors.PriorsName(),
                  " gives no camera rotations",
                  options.priors.HasNavigation()
                      ? " (a log needs roll, pitch and yaw or heading "
                        "columns, with their sigmas)"
                      : " with a covariance");
  }
  Emit(progress,
       fmt::format("Model: {}, {} images, {} points", options.input_path,
                   model->Images().size(), model->Points3D().size()));
  if (options.priors.HasPriorSource()) {
    Emit(progress,
         fmt::format("Priors: {} images ({} rows of images not in the "
                     "model, left out)",
                     inputs.priors.size(), inputs.num_priors_without_image));
    if (inputs.world_frame) {
      Emit(progress, "World frame: " + WorldFrameText(*inputs.world_frame));
    }
  }
  return AdjustModelWithNavigation(options, inputs, model, progress);
}

namespace {

// Dives none of whose images share a point that 3 images see with the
// largest linked group, which holds other dives: only points 2 images see
// can tie them to the rest, so such a dive's offset is weakly measured or
// its prior's alone (zero, +- --Dive.offset_sigma), and whatever bias its
// navigation has that the images miss stays in the model. Seen on the
// seafloor: a third dive 10 % overlapping, offset 0 +- 10 m where the bias
// was 1.2 m; on the scarp, a third dive tied by 2-view points, its offset
// 6 cm from the truth.
std::vector<std::string> DivesApartWarnings(
    const Reconstruction& model, const std::vector<ImagePosePrior>& priors) {
  const std::vector<image_t> apart = ImagesWithoutScaleTransfer(model);
  const std::set<image_t> apart_set(apart.begin(), apart.end());
  std::map<int, std::pair<int, int>> linked_and_apart;  // by dive
  for (const ImagePosePrior& prior : priors) {
    auto& counts = linked_and_apart[prior.dive];
    ++(apart_set.count(prior.image_id) ? counts.second : counts.first);
  }
  std::vector<std::string> warnings;
  for (const auto& [dive, counts] : linked_and_apart) {
    if (counts.first > 0 || linked_and_apart.size() < 2) continue;
    warnings.push_back(fmt::format(
        "dive {}: none of its {} images shares a point that 3 images see "
        "with the largest linked group of images, so the images tie it to "
        "the other dives at most through points that 2 images see: its "
        "offset is weakly measured, or only its prior (0 +- "
        "--Dive.offset_sigma), as its sigma shows, and what of its "
        "navigation's bias the images do not measure stays in the model. "
        "Track more points where the dives overlap",
        dive, counts.second));
  }
  return warnings;
}

}  // namespace

NavBundleAdjustmentResult AdjustModelWithNavigation(
    const NavBundleAdjustmentControllerOptions& options,
    const NavInputs& inputs, Reconstruction* model,
    const ProgressLines& progress) {
  options.Check();
  const SoftRig* rig = inputs.rig ? &*inputs.rig : nullptr;
  NavBundleAdjustmentResult result;
  result.num_priors = inputs.priors.size();
  result.world_frame = inputs.world_frame;
  std::vector<std::string> alignment_warnings = inputs.warnings;
  const auto start = std::chrono::steady_clock::now();
  if (options.strategy == NavStrategy::kPrior && !inputs.priors.empty()) {
    // A model from SfM has its own frame and scale; the adjustment only
    // refines locally.
    AlignToPriorsPlausibly(inputs.priors, options.priors.plausibility,
                           options.priors.PriorsName(), kAcceptFlag,
                           options.adjuster, model, &alignment_warnings);
    NavBundleAdjustmentOptions adjuster = options.adjuster;
    const NavWeightSelection selection = options.weight.selection;
    if (selection == NavWeightSelection::kFixed) {
      adjuster.weight_px_per_m = options.weight.fixed_px_per_m;
    } else {
      result.noise_levels =
          EstimateAndReportNoiseLevels(adjuster, inputs, *model, progress);
      adjuster.weight_px_per_m = result.noise_levels->weight_px_per_m;
    }
    if (selection == NavWeightSelection::kLCurveCorner ||
        selection == NavWeightSelection::kLCurveBalance) {
      result.lcurve =
          SweepAroundEstimate(adjuster, inputs, *model, *result.noise_levels,
                              options.lcurve_steps, 0.0, 0.0, progress);
      const std::string name = NavWeightText(options.weight);
      const std::optional<double> chosen =
          selection == NavWeightSelection::kLCurveCorner
              ? result.lcurve->corner_weight_px_per_m
              : result.lcurve->balance_weight_px_per_m;
      if (!chosen) {
        throw ErrorAt("the L-curve has no ", name,
                      " in the swept range; use --Nav.weight auto or a "
                      "number");
      }
      adjuster.weight_px_per_m = *chosen;
      Emit(progress,
           fmt::format("L-curve: lambda = {:g} px/m ({})", *chosen, name));
    }
    result.report = AdjustWithNavigation(adjuster, inputs.priors, rig,
                                         inputs.image_times, model);
    if (result.noise_levels) {
      for (const std::string& warning : result.noise_levels->warnings) {
        result.report.warnings.push_back(
            "the images-only adjustment behind --Nav.weight's noise levels: " +
            warning);
      }
    }
  } else {
    result.report = AdjustWithNavigation(options.adjuster, {}, rig,
                                         inputs.image_times, model);
    if (!inputs.priors.empty()) {
      result.world_from_adjusted_model =
          AlignToPriorsPlausibly(inputs.priors, options.priors.plausibility,
                                 options.priors.PriorsName(), kAcceptFlag,
                                 options.adjuster, model, &alignment_warnings)
              .b_from_a;
    }
  }
  result.report.warnings.insert(result.report.warnings.end(),
                                alignment_warnings.begin(),
                                alignment_warnings.end());
  const bool attitude_priors =
      options.strategy == NavStrategy::kPrior && options.adjuster.use_attitude;
  if (const auto warning =
          TrackLineWarning(*model, inputs.priors, attitude_priors)) {
    result.report.warnings.push_back(*warning);
  }
  if (const auto warning =
          ScaleTransferWarning(*model, !inputs.priors.empty())) {
    result.report.warnings.push_back(*warning);
  }
  if (options.strategy == NavStrategy::kPrior &&
      options.adjuster.dive_offsets) {
    for (const std::string& warning :
         DivesApartWarnings(*model, inputs.priors)) {
      result.report.warnings.push_back(warning);
    }
  }
  result.total_time_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
  return result;
}

std::string FormatNavBundleAdjustmentSummary(
    const NavBundleAdjustmentControllerOptions& options,
    const NavBundleAdjustmentResult& result, const Reconstruction& model) {
  const NavBundleAdjustmentReport& report = result.report;
  std::string text = fmt::format("{:<22}{:<10}{:<16}final MS\n", "term",
                                 "blocks", "initial MS");
  for (const auto& [name, term] : report.final_terms) {
    const auto initial = report.initial_terms.find(name);
    text += fmt::format(
        "{:<22}{:<10}{:<16g}{:g}\n", name, term.num_residual_blocks,
        initial != report.initial_terms.end() ? initial->second.mean_squared
                                              : 0.0,
        term.mean_squared);
  }
  if (options.adjuster.dive_offsets) {
    for (const DiveOffsetEstimate& offset : report.dive_offsets) {
      text += fmt::format("Dive {} offset: {} m", offset.dive,
                          RowText(offset.offset_in_world));
      if (offset.covariance) {
        text += fmt::format(" +- {} m (1 sigma)",
                            RowText(offset.covariance->diagonal().cwiseSqrt()));
      }
      text += fmt::format(" over {} images\n", offset.num_images);
    }
  }
  if (!report.prior_residuals.empty()) {
    const nlohmann::json json = BaReportJson(report, model, {});
    for (const nlohmann::json& dive : json["prior_residuals_by_dive"]) {
      text += fmt::format(
          "Dive {}: {} priors, camera minus prior: mean {} m, RMS {} m\n",
          dive["dive"].dump(), dive["num_images"].dump(),
          dive["mean_error_m"].dump(), dive["rms_error_m"].dump());
    }
  }
  text +=
      fmt::format("{} iterations{}, {}, {:g} s solve, {:g} s in all\n",
                  report.num_iterations,
                  report.num_continuations > 0
                      ? fmt::format(" ({} solves: continued past the limit)",
                                    report.num_continuations + 1)
                      : std::string(),
                  report.termination, report.solve_time_s, result.total_time_s);
  return text;
}

nlohmann::json NavBundleAdjustmentJson(
    const NavBundleAdjustmentControllerOptions& options,
    const NavBundleAdjustmentResult& result, const Reconstruction& model) {
  const PosePriorImportOptions& nav = options.priors.nav;
  nlohmann::json context = {
      {"input_path", options.input_path},
      {"strategy", result.num_priors == 0 ? std::string("none (no priors)")
                                          : NavStrategyName(options.strategy)},
      {"nav", nav.nav_path.string()},
      {"database_path", options.priors.database_path},
      {"camera_on_vehicle", DescribeNavToCamera(nav.nav_to_camera)},
      {"rig_config", nav.rig_config_path.string()},
      {"world_frame",
       result.world_frame ? WorldFrameText(*result.world_frame) : ""}};
  if (result.noise_levels) {
    context["noise_levels"] = NoiseLevelsJson(*result.noise_levels);
  }
  if (result.world_from_adjusted_model) {
    context["posterior_similarity"] = ToJson(*result.world_from_adjusted_model);
  }
  nlohmann::json json = BaReportJson(result.report, model, context);
  json["total_time_s"] = result.total_time_s;
  if (result.lcurve) {
    json["lcurve"] = nlohmann::json::parse(LCurveJson(*result.lcurve));
  }
  return json;
}

NavLCurveResult SweepModelLCurve(const NavLCurveOptions& options,
                                 const Reconstruction& model,
                                 const ProgressLines& progress) {
  options.Check();
  const NavInputs inputs =
      LoadNavInputs(options.priors, model, options.input_path);
  if (inputs.priors.empty()) {
    throw ErrorAt(
        "an L-curve needs navigation priors (--nav or a database "
        "with priors)");
  }
  Reconstruction aligned = model;
  NavLCurveResult result;
  result.warnings = inputs.warnings;
  AlignToPriorsPlausibly(inputs.priors, options.priors.plausibility,
                         options.priors.PriorsName(), kAcceptFlag,
                         options.adjuster, &aligned, &result.warnings);
  result.noise_levels =
      EstimateAndReportNoiseLevels(options.adjuster, inputs, aligned, progress);
  result.curve = SweepAroundEstimate(
      options.adjuster, inputs, aligned, result.noise_levels, options.steps,
      options.lambda_min, options.lambda_max, progress);
  return result;
}

std::string FormatNavLCurveSummary(const NavLCurveResult& result) {
  const LCurve& curve = result.curve;
  std::string text =
      curve.corner_weight_px_per_m
          ? fmt::format("Corner: lambda = {:g} px/m\n",
                        *curve.corner_weight_px_per_m)
          : "No corner: the images alone do not deform the model\n";
  if (curve.balance_weight_px_per_m) {
    text += fmt::format("Balance point: lambda = {:g} px/m\n",
                        *curve.balance_weight_px_per_m);
  }
  text += fmt::format("Noise levels: lambda = {:g} px/m\n",
                      result.noise_levels.weight_px_per_m);
  return text;
}

}  // namespace uw
