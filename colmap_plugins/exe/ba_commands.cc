#include "colmap_plugins/exe/ba_commands.h"

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "colmap_plugins/ba/covariance_files.h"
#include "colmap_plugins/exe/nav_flags.h"
#include "colmap_plugins/scene/model_io.h"
#include "common/util/error.h"
#include "common/util/file.h"

namespace uw {
namespace {

namespace fs = std::filesystem;

void PrintLine(const std::string& line) { std::cout << line << std::endl; }

// The flags bundle_adjuster and lcurve share: the model, its priors and the
// adjuster's options (COLMAP's BundleAdjustment.* with colmap 3.8's names
// and defaults, then ours).
void AddNavBundleAdjustmentFlags(CommandLine* cli, std::string* input_path,
                                 NavInputOptions* priors,
                                 NavBundleAdjustmentOptions* adjuster) {
  cli->Add("--input_path", input_path, "Model folder to adjust")->required();
  cli->Add("--database_path", &priors->database_path,
           "COLMAP database: its pose priors (without --nav), or the image "
           "list that --nav rows are checked against");
  AddNavFlags(cli, &priors->nav, false, "--Rig.config");
  cli->Add("--BundleAdjustment.max_num_iterations",
           &adjuster->max_num_iterations, "Solver iterations at most");
  cli->Add<UnconvergedPolicy>(
      "--BundleAdjustment.unconverged", &adjuster->unconverged,
      "A solve still lowering its cost at max_num_iterations: continue "
      "(solve on, up to max_continuations more times, then fail), fail "
      "(an error, nothing written) or warn (colmap's way: the model is "
      "written, with a warning)",
      UnconvergedPolicyFromName, UnconvergedPolicyName);
  cli->Add("--BundleAdjustment.max_continuations", &adjuster->max_continuations,
           "Further solves of max_num_iterations that continue may take");
  cli->Add("--BundleAdjustment.max_linear_solver_iterations",
           &adjuster->max_linear_solver_iterations,
           "Linear solver iterations at most");
  cli->Add("--BundleAdjustment.function_tolerance",
           &adjuster->function_tolerance,
           "Ceres' function tolerance (colmap: 0, which never stops a "
           "non-monotonic solve)");
  cli->Add("--BundleAdjustment.use_nonmonotonic_steps",
           &adjuster->use_nonmonotonic_steps,
           "Ceres' non-monotonic trust region: the cost may rise for a few "
           "steps (colmap: 0, monotonic, which crawls along a long strip's "
           "weak bending)");
  cli->Add("--BundleAdjustment.gradient_tolerance",
           &adjuster->gradient_tolerance, "Ceres' gradient tolerance");
  cli->Add("--BundleAdjustment.parameter_tolerance",
           &adjuster->parameter_tolerance, "Ceres' parameter tolerance");
  cli->Add("--BundleAdjustment.refine_focal_length",
           &adjuster->refine_focal_length, "Refine the focal lengths");
  cli->Add("--BundleAdjustment.refine_principal_point",
           &adjuster->refine_principal_point, "Refine the principal points");
  cli->Add("--BundleAdjustment.refine_extra_params",
           &adjuster->refine_extra_params, "Refine the distortion parameters");
  cli->Add("--BundleAdjustment.refine_extrinsics", &adjuster->refine_extrinsics,
           "Refine the camera poses");
  cli->Add("--Nav.use_attitude", &adjuster->use_attitude,
           "Also constrain camera attitudes by the navigation's roll, pitch "
           "and heading (needs --nav)");
  cli->Add<NavWeighting>(
      "--Nav.weighting", &adjuster->weighting,
      "likelihood: the Gaussian likelihood (lambda is the ratio of the two "
      "noise levels); thesis: Eq. 2, each objective divided by its number "
      "of terms (priors M/N times stiffer; docs/uwcolmap.md)",
      NavWeightingFromName, NavWeightingName);
  cli->Add<LossType>("--Nav.loss", &adjuster->nav_loss,
                     "Robust loss on the position priors: none, huber, cauchy",
                     LossTypeFromName, LossTypeName);
  cli->Add("--Nav.loss_scale", &adjuster->nav_loss_scale,
           "Where the robust loss starts, in prior sigmas");
  cli->Add("--Nav.position_sigma", &priors->position_sigma_m,
           "Prior position sigma (m, per axis) for priors without a usable "
           "covariance, or for all with --Nav.override_sigma 1");
  cli->Add("--Nav.override_sigma", &priors->override_sigma,
           "Use --Nav.position_sigma for every prior");
  AddPlausibilityFlags(cli, &priors->plausibility, "--Nav.");
  cli->Add("--Dive.offsets", &adjuster->dive_offsets,
           "Estimate one 3D navigation offset per dive (reference dive "
           "fixed); needs --nav");
  cli->Add("--Dive.reference", &adjuster->reference_dive,
           "Reference dive (0: the lowest dive number)");
  cli->Add("--Dive.offset_sigma", &adjuster->dive_offset_sigma_m,
           "Sigma (m, per axis) of the weak zero prior on offsets");
  cli->Add("--Rig.interpolate", &adjuster->rig_interpolate_time,
           "Interpolate the rig pose at each rig camera's own time");
  cli->Add("--Rig.rotation_sigma", &priors->rig_rotation_sigma_deg,
           "Rotation sigma (deg) of rig cameras whose rig.json sigma is 0");
  cli->Add("--Rig.translation_sigma", &priors->rig_translation_sigma_m,
           "Translation sigma (m) of rig cameras whose rig.json sigma is 0");
  cli->Add("--num_threads", &adjuster->num_threads, "-1: all cores");
}

void AddCovarianceFlags(CommandLine* cli, BundleCovarianceOptions* options) {
  cli->Add<CovarianceGauge>(
      "--Covariance.gauge", &options->gauge,
      "What fixes the datum: priors (the navigation), held (the first "
      "image's pose and the second's scale, as COLMAP) or free_network "
      "(minimum-norm pseudo-inverse, inner constraints)",
      CovarianceGaugeFromName, CovarianceGaugeName);
  cli->Add<CovarianceMethod>(
      "--Covariance.method", &options->method,
      "schur (ours: Schur complement, sparse inverse) or ceres_sparse_qr "
      "(ceres::Covariance, the slow peer it is benchmarked against; "
      "marginals only)",
      CovarianceMethodFromName, CovarianceMethodName);
  cli->Add("--Covariance.pixel_sigma", &options->pixel_sigma_px,
           "Pixel noise per coordinate (px); 0: estimated from the "
           "reprojection residuals and the images' redundancy");
  cli->Add("--Covariance.nav_weight", &options->nav_weight_px_per_m,
           "The weight (px/m) the adjustment gave the navigation "
           "(ba_report.json's weight_px_per_m): the priors' sigmas are "
           "taken as it weighted them; 0: as stated. bundle_adjuster uses "
           "its own");
  cli->Add("--Covariance.points", &options->point_marginals,
           "Also the 3x3 marginal of every point");
  cli->Add("--Covariance.covisible", &options->covisible_cross,
           "Also the cross-covariances of image pairs that see a common "
           "point (in memory; not written yet)");
  cli->Add("--Covariance.samples", &options->num_samples,
           "Joint draws of the model's error, similarity removed, written "
           "to samples.bin for a Monte Carlo that re-samples the model "
           "(e.g. 200; docs/covariance.md); 0: none");
  cli->Add("--Covariance.sample_seed", &options->sample_seed,
           "Seed of the draws (they depend on it alone)");
}

// The covariance of `model`, its summary and warnings printed. Its json
// also carries `adjuster_warnings` (what the adjuster found wrong with the
// model it describes, an unconverged solve above all), which the adjuster
// printed already.
BundleCovariance EstimateCovariance(
    const NavBundleAdjustmentOptions& adjuster, const NavInputs& inputs,
    const BundleCovarianceOptions& options, const Reconstruction& model,
    const std::vector<std::string>& adjuster_warnings = {}) {
  PrintLine("Covariance: " + std::to_string(model.Images().size()) +
            " images, " + std::to_string(model.Points3D().size()) +
            " points, gauge " + CovarianceGaugeName(options.gauge));
  BundleCovariance covariance = EstimateBundleCovariance(
      adjuster, inputs.priors, inputs.rig ? &*inputs.rig : nullptr,
      inputs.image_times, model, options);
  const nlohmann::json summary = CovarianceSummaryJson(covariance, model);
  std::cout << "  pixel sigma " << covariance.pixel_sigma_px << " px ("
            << covariance.pixel_sigma_source << ")\n";
  if (!inputs.priors.empty()) {
    std::cout << "  navigation sigmas: stated x " << covariance.nav_sigma_scale
              << " (" << covariance.nav_sigma_source << ")\n";
  }
  std::cout << "  camera centre sigma: median "
            << summary["images"]["sigma_position_m"]["median"].get<double>()
            << " m, max "
            << summary["images"]["sigma_position_m"]["max"].get<double>()
            << " m; rotation median "
            << summary["images"]["sigma_rotation_deg"]["median"].get<double>()
            << " deg\n";
  if (options.point_marginals) {
    std::cout
        << "  point sigma (largest axis): median "
        << summary["points"]["sigma_largest_axis_m"]["median"].get<double>()
        << " m, p95 "
        << summary["points"]["sigma_largest_axis_m"]["p95"].get<double>()
        << " m; " << summary["points"]["num_weak"].get<long>()
        << " weak points (> 3x the median)\n";
  }
  std::cout << "  " << covariance.total_time_s << " s (factor "
            << covariance.factor_time_s << " s, sparse inverse "
            << covariance.inverse_time_s << " s)\n";
  for (const std::string& warning : covariance.warnings) {
    if (std::find(adjuster_warnings.begin(), adjuster_warnings.end(),
                  warning) == adjuster_warnings.end()) {
      std::cerr << "WARNING: " << warning << "\n";
    }
  }
  for (const std::string& warning : adjuster_warnings) {
    if (std::find(covariance.warnings.begin(), covariance.warnings.end(),
                  warning) == covariance.warnings.end()) {
      covariance.warnings.push_back(warning);
    }
  }
  return covariance;
}

void WriteCovariance(const CovarianceFiles& files,
                     const BundleCovariance& covariance,
                     const fs::path& folder) {
  files.Write();
  PrintLine("Wrote " + folder.string() +
            " (covariance.bin, covariance.json, cameras.csv, points.ply, "
            "uncertainty_map.png and .svg" +
            (covariance.samples.NumSamples() > 0 ? ", samples.bin)" : ")"));
}

void AddBundleAdjusterFlags(CommandLine* cli, BundleAdjusterOptions* options) {
  NavBundleAdjustmentControllerOptions& adjustment = options->adjustment;
  AddNavBundleAdjustmentFlags(cli, &adjustment.input_path, &adjustment.priors,
                              &adjustment.adjuster);
  cli->Add("--output_path", &options->output_path,
           "Folder for the adjusted model and ba_report.json")
      ->required();
  cli->Add<NavStrategy>(
      "--Nav.strategy", &adjustment.strategy,
      "prior: navigation inside the adjustment (multiobjective); posterior: "
      "plain adjustment, then a similarity to the navigation (what colmap "
      "bundle_adjuster + model_aligner do)",
      NavStrategyFromName, NavStrategyName);
  cli->Add<NavWeight>(
      "--Nav.weight", &adjustment.weight,
      "lambda = sigma_v / sigma_n in px/m; auto: both noise levels "
      "estimated from the images-only adjustment and its similarity to the "
      "navigation; corner / balance: the L-curve's maximum-curvature corner "
      "/ balance point (docs/uwcolmap.md)",
      NavWeightFromText, NavWeightText);
  cli->Add("--Nav.lcurve_steps", &adjustment.lcurve_steps,
           "Adjustments in the L-curve sweep of --Nav.weight corner|balance");
  cli->Add("--BA.covariance", &options->covariance,
           "Also the covariance of the adjusted model, into "
           "OUTPUT/covariance (as covariance_estimator)");
  AddCovarianceFlags(cli, &options->covariance_options);
}

void RunBundleAdjuster(const BundleAdjusterOptions& options) {
  const NavBundleAdjustmentControllerOptions& adjustment = options.adjustment;
  Reconstruction model = ReadModel(adjustment.input_path);
  const ModelFiles files = DetectModelFiles(adjustment.input_path);
  const NavBundleAdjustmentResult result =
      AdjustModelWithNavigation(adjustment, &model, PrintLine);
  std::cout << FormatNavBundleAdjustmentSummary(adjustment, result, model);
  for (const std::string& warning : result.report.warnings) {
    std::cerr << "WARNING: " << warning << "\n";
  }
  const nlohmann::json json =
      NavBundleAdjustmentJson(adjustment, result, model);
  // Computed before anything is written: a model without a covariance
  // (a free gauge, an image seeing too few points) writes nothing.
  std::optional<BundleCovariance> covariance;
  if (options.covariance) {
    // The problem just solved: with the priors inside it, or, after a
    // posterior similarity, the images alone.
    NavInputs inputs =
        LoadNavInputs(adjustment.priors, model, adjustment.input_path);
    if (adjustment.strategy == NavStrategy::kPosterior) inputs.priors.clear();
    // The priors as the adjustment weighted them (--Nav.weight auto: their
    // sigmas x the s_n the data show), not as stated.
    BundleCovarianceOptions covariance_options = options.covariance_options;
    if (!inputs.priors.empty() &&
        adjustment.adjuster.weighting == NavWeighting::kLikelihood) {
      covariance_options.nav_weight_px_per_m = result.report.weight_px_per_m;
    }
    covariance =
        EstimateCovariance(adjustment.adjuster, inputs, covariance_options,
                           model, result.report.warnings);
  }
  const fs::path output(options.output_path);
  // The figures too: a plotting failure (no matplotlib) writes nothing.
  std::optional<CovarianceFiles> covariance_files;
  if (covariance)
    covariance_files.emplace(*covariance, model, output / "covariance");
  const std::vector<FigureFiles> lcurve_figures =
      result.lcurve ? DrawFigures(LCurveFigures(*result.lcurve))
                    : std::vector<FigureFiles>();
  WriteModel(model, output, files.format);
  std::vector<PendingFile> report = {
      {output / "ba_report.json",
       [&](std::ostream& out) { out << json.dump(2) << "\n"; }}};
  // The model's frame beside it, in a form a GIS reads.
  if (result.world_frame) {
    report.push_back({output / "world_frame.json", [&](std::ostream& out) {
                        out << WorldFrameJson(*result.world_frame).dump(2)
                            << "\n";
                      }});
  }
  if (result.lcurve) {
    for (const PendingFile& figure :
         FigureFileSet(lcurve_figures, LCurveFigurePaths(output))) {
      report.push_back(figure);
    }
  }
  WriteFilesAtomically(report, true);
  // A model in its priors' own frame has none: an earlier run's would lie.
  if (!result.world_frame) fs::remove(output / "world_frame.json");
  std::cout << "Wrote " << options.output_path << " (model, ba_report.json"
            << (result.world_frame ? ", world_frame.json" : "")
            << (result.lcurve ? ", lcurve.png, lcurve_curvature.png" : "")
            << ")\n";
  if (covariance) {
    WriteCovariance(*covariance_files, *covariance, output / "covariance");
  }
}

void AddCovarianceEstimatorFlags(CommandLine* cli,
                                 CovarianceEstimatorOptions* options) {
  AddNavBundleAdjustmentFlags(cli, &options->input_path, &options->priors,
                              &options->adjuster);
  cli->Add("--output_path", &options->output_path,
           "Folder (new or empty) for covariance.bin, covariance.json, "
           "cameras.csv, points.ply and uncertainty_map.png (and .svg)")
      ->required();
  AddCovarianceFlags(cli, &options->covariance);
}

void RunCovarianceEstimator(const CovarianceEstimatorOptions& options) {
  const Reconstruction model = ReadModel(options.input_path);
  const NavInputs inputs =
      LoadNavInputs(options.priors, model, options.input_path);
  const BundleCovariance covariance =
      EstimateCovariance(options.adjuster, inputs, options.covariance, model);
  WriteCovariance(CovarianceFiles(covariance, model, options.output_path),
                  covariance, options.output_path);
}

void AddLCurveFlags(CommandLine* cli, LCurveCommandOptions* options) {
  NavLCurveOptions& lcurve = options->lcurve;
  AddNavBundleAdjustmentFlags(cli, &lcurve.input_path, &lcurve.priors,
                              &lcurve.adjuster);
  cli->Add("--output_path", &options->output_path,
           "Folder for lcurve.json and the figures lcurve.png and "
           "lcurve_curvature.png (and .svg)")
      ->required();
  cli->Add("--lambda_min", &lcurve.lambda_min,
           "Smallest lambda, px/m (0: sigma_v/sigma_n / 30 with sigma_v from "
           "the model's point errors)");
  cli->Add("--lambda_max", &lcurve.lambda_max,
           "Largest lambda, px/m (0: sigma_v/sigma_n * 30)");
  cli->Add("--steps", &lcurve.steps, "Number of lambdas");
}

void RunLCurve(const LCurveCommandOptions& options) {
  const Reconstruction model = ReadModel(options.lcurve.input_path);
  const NavLCurveResult result =
      SweepModelLCurve(options.lcurve, model, PrintLine);
  std::cout << FormatNavLCurveSummary(result);
  for (const std::string& warning : result.warnings) {
    std::cerr << "WARNING: " << warning << "\n";
  }
  const std::string json = LCurveJson(result.curve);
  const fs::path output(options.output_path);
  const std::vector<FigureFiles> figures =
      DrawFigures(LCurveFigures(result.curve));
  std::vector<PendingFile> files =
      FigureFileSet(figures, LCurveFigurePaths(output));
  files.push_back(
      {output / "lcurve.json", [&](std::ostream& out) { out << json; }});
  WriteFilesAtomically(files, true);
}

}  // namespace

void BundleAdjusterOptions::Check() const {
  std::error_code ignored;
  if (fs::equivalent(adjustment.input_path, output_path, ignored)) {
    throw ErrorAt("--output_path ", output_path,
                  " is the input folder; write to another folder");
  }
  if (covariance_options.nav_weight_px_per_m != 0.0) {
    throw ErrorAt(
        "--Covariance.nav_weight is for covariance_estimator: "
        "bundle_adjuster gives its covariance the weight it solved with");
  }
  adjustment.Check();
}

Subcommand BundleAdjusterCommand() {
  return MakeSubcommand<BundleAdjusterOptions>(
      "bundle_adjuster",
      "bundle adjustment fused with navigation, dive offsets, soft rigs",
      "Bundle adjustment of a COLMAP model, optionally fused with vehicle "
      "navigation (the thesis's multiobjective BA): reprojection errors plus "
      "camera-centre priors (full 3x3 covariance, lever arm and boresight), "
      "optional attitude priors, per-dive navigation offsets and soft rig "
      "constraints. COLMAP's BundleAdjustment.* flags keep their meaning. "
      "Writes the adjusted model (same layout and format) and "
      "ba_report.json into --output_path. docs/uwcolmap.md explains the "
      "weights and the report.\n\n"
      "Example (uwsim floor survey, priors from its navigation):\n"
      "  uwcolmap bundle_adjuster --input_path sparse/0 --output_path "
      "sparse_nav --nav sim/nav.csv --mount down --lever_arm 0.6,0,-0.3 "
      "--boresight 0.3,-0.5,0.8 --Nav.strategy prior --Nav.weight auto",
      AddBundleAdjusterFlags, RunBundleAdjuster);
}

void CovarianceEstimatorOptions::Check() const {
  std::error_code ignored;
  if (fs::exists(output_path) && !fs::is_empty(output_path, ignored)) {
    throw ErrorAt("--output_path ", output_path,
                  " is not empty; give a new or empty folder");
  }
  priors.Check();
  adjuster.Check();
  covariance.Check();
}

Subcommand CovarianceEstimatorCommand() {
  return MakeSubcommand<CovarianceEstimatorOptions>(
      "covariance_estimator",
      "pose, intrinsics and point covariances of a model (sparse, fast)",
      "The covariance of a COLMAP model under the bundle adjustment "
      "bundle_adjuster solves with the same flags (reprojection, navigation "
      "priors, attitude, dive offsets, soft rig; losses applied): per-image "
      "6x6 pose marginals, the intrinsics' block, per-point 3x3 marginals. "
      "Schur complement onto the cameras, one sparse Cholesky (CHOLMOD) and "
      "the sparse-inverse recursion on its pattern: no dense inverse. The "
      "gauge is stated: the navigation priors, held coordinates (COLMAP's "
      "choice) or free_network. A problem without a covariance (an image "
      "seeing < 3 points, a point seen once, a free gauge, rank "
      "deficiency) is an error naming what is wrong. docs/covariance.md "
      "explains the outputs.\n\n"
      "Examples:\n"
      "  uwcolmap covariance_estimator --input_path sparse_nav --output_path "
      "cov --nav sim/nav.csv --mount down --lever_arm 0.6,0,-0.3 "
      "--boresight 0.3,-0.5,0.8\n"
      "  uwcolmap covariance_estimator --input_path sparse/0 --output_path "
      "cov --Covariance.gauge free_network",
      AddCovarianceEstimatorFlags, RunCovarianceEstimator);
}

Subcommand LCurveCommand() {
  return MakeSubcommand<LCurveCommandOptions>(
      "lcurve", "sweep the navigation weight; L-curve plot and corner",
      "Sweeps the navigation weight lambda of the multiobjective bundle "
      "adjustment over log-spaced values, plots the two objectives "
      "(reprojection and navigation mean squares) in log-log space and "
      "picks the point of maximum curvature (thesis ch. 4 §5.2.1); also "
      "reports the balance point and lambda from the estimated noise levels "
      "(what bundle_adjuster --Nav.weight auto uses). Writes lcurve.json and "
      "the figures lcurve.png and lcurve_curvature.png (with .svg); the "
      "model is not changed.\n\n"
      "Example:\n"
      "  uwcolmap lcurve --input_path sparse/0 --output_path lcurve --nav "
      "sim/nav.csv --mount down --lambda_min 0.1 --lambda_max 100",
      AddLCurveFlags, RunLCurve);
}

}  // namespace uw
