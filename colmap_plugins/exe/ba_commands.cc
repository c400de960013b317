#include "colmap_plugins/exe/ba_commands.h"

#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>

#include <nlohmann/json.hpp>

#include "colmap_plugins/align/sim3.h"
#include "colmap_plugins/align/similarity.h"
#include "colmap_plugins/ba/ba_report.h"
#include "colmap_plugins/ba/lcurve.h"
#include "colmap_plugins/ba/nav_bundle_adjuster.h"
#include "colmap_plugins/ba/nav_inputs.h"
#include "colmap_plugins/ba/noise_levels.h"
#include "colmap_plugins/ba/prior_alignment.h"
#include "colmap_plugins/exe/legacy_nav_flags.h"
#include "colmap_plugins/nav/pose_prior_import.h"
#include "colmap_plugins/scene/database.h"
#include "colmap_plugins/scene/model_io.h"
#include "common/cli/command.h"
#include "common/util/error.h"
#include "common/util/file.h"

namespace uw {
namespace {

namespace fs = std::filesystem;

// COLMAP's BundleAdjustment.* flags (colmap 3.8 names and defaults).
struct ColmapBundleAdjustmentFlags {
  int max_num_iterations = 100;
  int max_linear_solver_iterations = 200;
  double function_tolerance = 0.0;
  double gradient_tolerance = 0.0;
  double parameter_tolerance = 0.0;
  std::string refine_focal_length = "1";
  std::string refine_principal_point = "0";
  std::string refine_extra_params = "1";
  std::string refine_extrinsics = "1";

  void Add(CLI::App& app) {
    app.add_option("--BundleAdjustment.max_num_iterations", max_num_iterations)
        ->default_val(100);
    app.add_option("--BundleAdjustment.max_linear_solver_iterations",
                   max_linear_solver_iterations)
        ->default_val(200);
    app.add_option("--BundleAdjustment.function_tolerance", function_tolerance)
        ->default_val(0.0);
    app.add_option("--BundleAdjustment.gradient_tolerance", gradient_tolerance)
        ->default_val(0.0);
    app.add_option("--BundleAdjustment.parameter_tolerance",
                   parameter_tolerance)
        ->default_val(0.0);
    app.add_option("--BundleAdjustment.refine_focal_length",
                   refine_focal_length)
        ->default_val("1");
    app.add_option("--BundleAdjustment.refine_principal_point",
                   refine_principal_point)
        ->default_val("0");
    app.add_option("--BundleAdjustment.refine_extra_params",
                   refine_extra_params)
        ->default_val("1");
    app.add_option("--BundleAdjustment.refine_extrinsics", refine_extrinsics)
        ->default_val("1");
  }

  void Apply(NavBundleAdjustmentOptions* options) const {
    options->max_num_iterations = max_num_iterations;
    options->max_linear_solver_iterations = max_linear_solver_iterations;
    options->function_tolerance = function_tolerance;
    options->gradient_tolerance = gradient_tolerance;
    options->parameter_tolerance = parameter_tolerance;
    options->refine_focal_length = ParseColmapBool(
        refine_focal_length, "BundleAdjustment.refine_focal_length");
    options->refine_principal_point = ParseColmapBool(
        refine_principal_point, "BundleAdjustment.refine_principal_point");
    options->refine_extra_params = ParseColmapBool(
        refine_extra_params, "BundleAdjustment.refine_extra_params");
    options->refine_extrinsics = ParseColmapBool(
        refine_extrinsics, "BundleAdjustment.refine_extrinsics");
  }
};

// Flags of the navigation-fused adjustment shared by bundle_adjuster and
// lcurve.
struct NavBaFlags {
  std::string input_path;
  std::string database_path;
  NavFlags nav;
  ColmapBundleAdjustmentFlags colmap;
  std::string use_attitude = "0";
  std::string weighting = "likelihood";
  std::string nav_loss = "none";
  double nav_loss_scale = 2.7955;
  double position_sigma = 0.0;
  std::string override_sigma = "0";
  std::string dive_offsets = "0";
  int reference_dive = 0;
  double dive_offset_sigma = 10.0;
  std::string rig_interpolate = "1";
  double rig_rotation_sigma = 0.0;
  double rig_translation_sigma = 0.0;
  int num_threads = -1;

  void Add(CLI::App& app) {
    app.add_option("--input_path", input_path, "Model folder to adjust")
        ->required();
    app.add_option("--database_path", database_path,
                   "COLMAP database: its pose priors (without --nav), or the "
                   "image list that --nav rows are checked against");
    nav.Add(app, false, "--Rig.config");
    colmap.Add(app);
    app.add_option("--Nav.use_attitude", use_attitude,
                   "Also constrain camera attitudes by the navigation's "
                   "roll, pitch and heading (needs --nav)")
        ->default_val("0");
    app.add_option("--Nav.weighting", weighting,
                   "likelihood: the Gaussian likelihood (lambda is the "
                   "ratio of the two noise levels); thesis: Eq. 2, each "
                   "objective divided by its number of terms (priors M/N "
                   "times stiffer; docs/uwcolmap.md)")
        ->default_val("likelihood");
    app.add_option("--Nav.loss", nav_loss,
                   "Robust loss on the position priors: none, huber, cauchy")
        ->default_val("none");
    app.add_option("--Nav.loss_scale", nav_loss_scale,
                   "Where the robust loss starts, in prior sigmas")
        ->default_val(2.7955);
    app.add_option("--Nav.position_sigma", position_sigma,
                   "Prior position sigma (m, per axis) for priors without a "
                   "usable covariance, or for all with "
                   "--Nav.override_sigma 1");
    app.add_option("--Nav.override_sigma", override_sigma,
                   "Use --Nav.position_sigma for every prior")
        ->default_val("0");
    app.add_option("--Dive.offsets", dive_offsets,
                   "Estimate one 3D navigation offset per dive (reference "
                   "dive fixed); needs --nav")
        ->default_val("0");
    app.add_option("--Dive.reference", reference_dive,
                   "Reference dive (0: the lowest dive number)")
        ->default_val(0);
    app.add_option("--Dive.offset_sigma", dive_offset_sigma,
                   "Sigma (m, per axis) of the weak zero prior on offsets")
        ->default_val(10.0);
    app.add_option("--Rig.interpolate", rig_interpolate,
                   "Interpolate the rig pose at each rig camera's own time")
        ->default_val("1");
    app.add_option("--Rig.rotation_sigma", rig_rotation_sigma,
                   "Rotation sigma (deg) of rig cameras whose rig.json "
                   "sigma is 0");
    app.add_option("--Rig.translation_sigma", rig_translation_sigma,
                   "Translation sigma (m) of rig cameras whose rig.json "
                   "sigma is 0");
    app.add_option("--num_threads", num_threads, "-1: all cores")
        ->default_val(-1);
  }

  NavBundleAdjustmentOptions Options() const {
    NavBundleAdjustmentOptions options;
    colmap.Apply(&options);
    options.use_attitude = ParseColmapBool(use_attitude, "Nav.use_attitude");
    options.weighting = NavWeightingFromName(weighting);
    options.nav_loss = LossTypeFromName(nav_loss);
    options.nav_loss_scale = nav_loss_scale;
    options.dive_offsets = ParseColmapBool(dive_offsets, "Dive.offsets");
    options.reference_dive = reference_dive;
    options.dive_offset_sigma_m = dive_offset_sigma;
    options.rig_interpolate_time =
        ParseColmapBool(rig_interpolate, "Rig.interpolate");
    options.num_threads = num_threads;
    if ((options.use_attitude || options.dive_offsets) &&
        nav.nav_path.empty()) {
      throw ErrorAt(
          "--Nav.use_attitude and --Dive.offsets need --nav (a "
          "database stores neither attitudes with covariances nor "
          "dives)");
    }
    return options;
  }

  // The priors of the model's images, from --nav or the database.
  NavInputs Inputs(const Reconstruction& model) const {
    const bool override_all =
        ParseColmapBool(override_sigma, "Nav.override_sigma");
    if (override_all && !(position_sigma > 0.0)) {
      throw ErrorAt("--Nav.override_sigma 1 needs --Nav.position_sigma > 0");
    }
    if (!nav.nav_path.empty()) {
      const PosePriorImportOptions options = nav.ToOptions();
      std::vector<std::pair<std::string, camera_t>> images;
      if (!database_path.empty()) {
        const Database database =
            Database::Open(database_path, Database::Mode::kReadOnly);
        for (const DatabaseImage& image : database.ReadAllImages()) {
          images.emplace_back(image.name, image.camera_id);
        }
      } else {
        for (const Image& image : model.Images()) {
          images.emplace_back(image.name, image.camera_id);
        }
      }
      const LoadedCameraPriors loaded = LoadCameraPriors(
          options, images,
          database_path.empty() ? "the model " + input_path : database_path);
      return NavInputsForModel(
          loaded.priors, loaded.rig.cameras.empty() ? nullptr : &loaded.rig,
          model, position_sigma, override_all, rig_rotation_sigma,
          rig_translation_sigma);
    }
    if (!database_path.empty()) {
      const Database database =
          Database::Open(database_path, Database::Mode::kReadOnly);
      return NavInputsFromDatabase(database.ReadAllPosePriors(), model,
                                   position_sigma, override_all);
    }
    return {};
  }
};

void CheckOutputPath(const std::string& input_path,
                     const std::string& output_path) {
  std::error_code ignored;
  if (fs::equivalent(input_path, output_path, ignored)) {
    throw ErrorAt("--output_path ", output_path,
                  " is the input folder; write to another folder");
  }
}

// Estimates and prints the noise levels behind --Nav.weight auto.
NoiseLevels PrintNoiseLevels(const NavBundleAdjustmentOptions& options,
                             const std::vector<ImagePosePrior>& priors,
                             const Reconstruction& model) {
  std::cout << "Noise levels: images-only adjustment, then its similarity "
               "to the navigation"
            << std::endl;
  const NoiseLevels levels = EstimateNoiseLevels(options, priors, model);
  std::cout << "  sigma_v = " << levels.pixel_sigma << " px ("
            << levels.reprojection_dof
            << " dof), sigma_n = " << levels.nav_sigma_m << " m ("
            << levels.navigation_dof << " dof; stated "
            << levels.stated_nav_sigma_m << " m, x" << levels.nav_scale
            << "): lambda = " << levels.weight_px_per_m << " px/m\n";
  return levels;
}

nlohmann::json NoiseLevelsJson(const NoiseLevels& levels) {
  return {{"pixel_sigma_px", levels.pixel_sigma},
          {"reprojection_dof", levels.reprojection_dof},
          {"nav_sigma_m", levels.nav_sigma_m},
          {"stated_nav_sigma_m", levels.stated_nav_sigma_m},
          {"nav_scale", levels.nav_scale},
          {"navigation_dof", levels.navigation_dof},
          {"weight_px_per_m", levels.weight_px_per_m}};
}

// The L-curve over lambda / 30 .. lambda * 30 around the noise-level
// estimate (or the given bounds), with progress.
LCurve SweepAroundEstimate(const NavBundleAdjustmentOptions& options,
                           const NavInputs& inputs, const Reconstruction& model,
                           const NoiseLevels& levels, int steps,
                           double lambda_min = 0.0, double lambda_max = 0.0) {
  const double low =
      lambda_min > 0.0 ? lambda_min : levels.weight_px_per_m / 30.0;
  const double high =
      lambda_max > 0.0 ? lambda_max : levels.weight_px_per_m * 30.0;
  std::cout << "L-curve: " << steps << " adjustments, lambda from " << low
            << " to " << high << " px/m\n";
  LCurve curve = SweepLCurve(
      options, inputs.priors, inputs.rig ? &*inputs.rig : nullptr,
      inputs.image_times, model, LogSpacedWeights(low, high, steps),
      [](size_t i, size_t n, const LCurvePoint& point) {
        std::cout << "  [" << i << "/" << n << "] lambda "
                  << point.weight_px_per_m << " px/m: reprojection MS "
                  << point.reprojection_ms_px2 << " px^2, navigation MS "
                  << point.navigation_ms_m2 << " m^2" << std::endl;
      });
  curve.noise_weight_px_per_m = levels.weight_px_per_m;
  return curve;
}

void PrintTerms(const NavBundleAdjustmentReport& report) {
  std::cout << std::setw(22) << std::left << "term" << std::setw(10) << "blocks"
            << std::setw(16) << "initial MS"
            << "final MS\n";
  for (const auto& [name, term] : report.final_terms) {
    const auto initial = report.initial_terms.find(name);
    std::cout << std::setw(22) << name << std::setw(10)
              << term.num_residual_blocks << std::setw(16)
              << (initial != report.initial_terms.end()
                      ? initial->second.mean_squared
                      : 0.0)
              << term.mean_squared << "\n";
  }
  std::cout << std::right;
}

}  // namespace

int RunBundleAdjuster(int argc, char** argv) {
  CLI::App app(
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
      "uwcolmap bundle_adjuster");
  NavBaFlags flags;
  flags.Add(app);
  std::string output_path;
  std::string strategy = "prior";
  std::string weight = "auto";
  int lcurve_steps = 21;
  app.add_option("--output_path", output_path,
                 "Folder for the adjusted model and ba_report.json")
      ->required();
  app.add_option("--Nav.strategy", strategy,
                 "prior: navigation inside the adjustment (multiobjective); "
                 "posterior: plain adjustment, then a similarity to the "
                 "navigation (what colmap bundle_adjuster + model_aligner "
                 "do)")
      ->default_val("prior");
  app.add_option("--Nav.weight", weight,
                 "lambda = sigma_v / sigma_n in px/m; auto: both noise "
                 "levels estimated from the images-only adjustment and its "
                 "similarity to the navigation; corner / balance: the "
                 "L-curve's maximum-curvature corner / balance point "
                 "(docs/uwcolmap.md)")
      ->default_val("auto");
  app.add_option("--Nav.lcurve_steps", lcurve_steps,
                 "Adjustments in the L-curve sweep of --Nav.weight "
                 "corner|balance")
      ->default_val(21);
  return RunCommand(app, argc, argv, [&] {
    CheckOutputPath(flags.input_path, output_path);
    if (strategy != "prior" && strategy != "posterior") {
      throw ErrorAt("--Nav.strategy ", strategy, ": prior or posterior");
    }
    NavBundleAdjustmentOptions options = flags.Options();
    Reconstruction model = ReadModel(flags.input_path);
    const ModelFiles files = DetectModelFiles(flags.input_path);
    const NavInputs inputs = flags.Inputs(model);
    const SoftRig* rig = inputs.rig ? &*inputs.rig : nullptr;
    std::cout << "Model: " << flags.input_path << ", " << model.Images().size()
              << " images, " << model.Points3D().size() << " points\n";
    if (!flags.nav.nav_path.empty() || !flags.database_path.empty()) {
      std::cout << "Priors: " << inputs.priors.size() << " images ("
                << inputs.num_priors_without_image
                << " priors of images not in the model)\n";
    }
    nlohmann::json context = {
        {"input_path", flags.input_path},
        {"strategy",
         inputs.priors.empty() ? std::string("none (no priors)") : strategy},
        {"nav", flags.nav.nav_path},
        {"database_path", flags.database_path},
        {"camera_on_vehicle", flags.nav.Describe()},
        {"rig_config", flags.nav.rig_config_path}};
    std::optional<LCurve> lcurve;
    const auto start = std::chrono::steady_clock::now();
    NavBundleAdjustmentReport report;
    if (strategy == "prior" && !inputs.priors.empty()) {
      AlignToPriors(inputs.priors, &model);
      if (weight == "auto" || weight == "corner" || weight == "balance") {
        const NoiseLevels levels =
            PrintNoiseLevels(options, inputs.priors, model);
        context["noise_levels"] = NoiseLevelsJson(levels);
        options.weight_px_per_m = levels.weight_px_per_m;
        if (weight != "auto") {
          lcurve =
              SweepAroundEstimate(options, inputs, model, levels, lcurve_steps);
          const bool corner = weight == "corner";
          const std::optional<double> chosen =
              corner ? lcurve->corner_weight_px_per_m
                     : lcurve->balance_weight_px_per_m;
          if (!chosen) {
            throw ErrorAt("the L-curve has no ", weight,
                          " in the swept range; use --Nav.weight auto or a "
                          "number");
          }
          options.weight_px_per_m = *chosen;
          std::cout << "L-curve: lambda = " << *chosen << " px/m (" << weight
                    << ")\n";
        }
      } else {
        try {
          options.weight_px_per_m = std::stod(weight);
        } catch (const std::exception&) {
          throw ErrorAt("--Nav.weight ", weight,
                        ": a number (px/m), auto, corner or balance");
        }
      }
      report = AdjustWithNavigation(options, inputs.priors, rig,
                                    inputs.image_times, &model);
    } else {
      report =
          AdjustWithNavigation(options, {}, rig, inputs.image_times, &model);
      if (!inputs.priors.empty()) {
        const Sim3d world_from_model = AlignToPriors(inputs.priors, &model);
        context["posterior_similarity"] = ToJson(world_from_model);
      }
    }
    const double total_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
            .count();
    PrintTerms(report);
    for (const DiveOffsetEstimate& offset : report.dive_offsets) {
      if (!options.dive_offsets) break;
      std::cout << "Dive " << offset.dive
                << " offset: " << offset.offset_in_world.transpose() << " m";
      if (offset.covariance) {
        std::cout << " +- "
                  << offset.covariance->diagonal().cwiseSqrt().transpose()
                  << " m (1 sigma)";
      }
      std::cout << " over " << offset.num_images << " images\n";
    }
    if (!report.prior_residuals.empty()) {
      for (const nlohmann::json& dive :
           BaReportJson(report, model, {})["prior_residuals_by_dive"]) {
        std::cout << "Dive " << dive["dive"] << ": " << dive["num_images"]
                  << " priors, camera minus prior: mean "
                  << dive["mean_error_m"].dump() << " m, RMS "
                  << dive["rms_error_m"] << " m\n";
      }
    }
    std::cout << report.num_iterations << " iterations, " << report.termination
              << ", " << report.solve_time_s << " s solve, " << total_s
              << " s in all\n";
    nlohmann::json json = BaReportJson(report, model, context);
    json["total_time_s"] = total_s;
    if (lcurve) json["lcurve"] = nlohmann::json::parse(LCurveJson(*lcurve));
    WriteModel(model, output_path, files.format);
    WriteFilesAtomically(
        {{fs::path(output_path) / "ba_report.json",
          [&](std::ostream& out) { out << json.dump(2) << "\n"; }}},
        false);
    if (lcurve) WriteLCurvePlot(*lcurve, fs::path(output_path) / "lcurve.png");
    std::cout << "Wrote " << output_path << " (model, ba_report.json"
              << (lcurve ? ", lcurve.png" : "") << ")\n";
  });
}

int RunLCurve(int argc, char** argv) {
  CLI::App app(
      "Sweeps the navigation weight lambda of the multiobjective bundle "
      "adjustment over log-spaced values, plots the two objectives "
      "(reprojection and navigation mean squares) in log-log space and "
      "picks the point of maximum curvature (thesis ch. 4 §5.2.1); also "
      "reports the balance point and lambda from the estimated noise levels "
      "(what bundle_adjuster --Nav.weight auto uses). Writes lcurve.json and "
      "lcurve.png; the model is not changed.\n\n"
      "Example:\n"
      "  uwcolmap lcurve --input_path sparse/0 --output_path lcurve --nav "
      "sim/nav.csv --mount down --lambda_min 0.1 --lambda_max 100",
      "uwcolmap lcurve");
  NavBaFlags flags;
  flags.Add(app);
  std::string output_path;
  double lambda_min = 0.0;
  double lambda_max = 0.0;
  int steps = 25;
  app.add_option("--output_path", output_path,
                 "Folder for lcurve.json and lcurve.png")
      ->required();
  app.add_option("--lambda_min", lambda_min,
                 "Smallest lambda, px/m (0: sigma_v/sigma_n / 30 with "
                 "sigma_v from the model's point errors)");
  app.add_option("--lambda_max", lambda_max,
                 "Largest lambda, px/m (0: sigma_v/sigma_n * 30)");
  app.add_option("--steps", steps, "Number of lambdas")->default_val(25);
  return RunCommand(app, argc, argv, [&] {
    const NavBundleAdjustmentOptions options = flags.Options();
    Reconstruction model = ReadModel(flags.input_path);
    const NavInputs inputs = flags.Inputs(model);
    if (inputs.priors.empty()) {
      throw ErrorAt(
          "an L-curve needs navigation priors (--nav or a database "
          "with priors)");
    }
    AlignToPriors(inputs.priors, &model);
    const NoiseLevels levels = PrintNoiseLevels(options, inputs.priors, model);
    const LCurve curve = SweepAroundEstimate(options, inputs, model, levels,
                                             steps, lambda_min, lambda_max);
    if (curve.corner_weight_px_per_m) {
      std::cout << "Corner: lambda = " << *curve.corner_weight_px_per_m
                << " px/m\n";
    } else {
      std::cout << "No corner: the images alone do not deform the model\n";
    }
    if (curve.balance_weight_px_per_m) {
      std::cout << "Balance point: lambda = " << *curve.balance_weight_px_per_m
                << " px/m\n";
    }
    std::cout << "Noise levels: lambda = " << levels.weight_px_per_m
              << " px/m\n";
    const std::string json = LCurveJson(curve);
    WriteFilesAtomically({{fs::path(output_path) / "lcurve.json",
                           [&](std::ostream& out) { out << json; }}},
                         false);
    WriteLCurvePlot(curve, fs::path(output_path) / "lcurve.png");
  });
}

}  // namespace uw
