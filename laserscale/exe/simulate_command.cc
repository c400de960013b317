#include "laserscale/exe/simulate_command.h"

#include <filesystem>

#include <fmt/format.h>

#include "common/util/file.h"
#include "experiments/views_experiment_io.h"
#include "laserscale/exe/scale_method_flags.h"

namespace uw {
namespace {

void AddSimulateFlags(CommandLine* cli, SimulateOptions* options) {
  ViewsExperimentOptions& experiment = options->experiment;
  cli->Add("--world", &experiment.world,
           "uwsim world (vent, seafloor, scarp, breakwater, canyon)");
  cli->Add("--area", &experiment.area,
           "flank (vent only: rough), top (the world's views point), "
           "custom (--target)");
  cli->Add("--target", &experiment.target,
           "x,y,z of the surveyed point (world m)");
  cli->Add("--distances", &experiment.distances_m,
           "Camera-point distances (m)");
  cli->Add("--setups", &experiment.setups, "uwsim laser set-ups (A, B, C)");
  AddScaleMethodsFlag(cli, "--methods", &experiment.methods,
                      "Methods to compare");
  cli->AddRepeated<ShotNoise>(
      "--noise", &experiment.noise_levels,
      "feature_px:spot_px[:direction_deg[:origin_m]], repeatable; 0:0 is "
      "noise-free",
      ParseShotNoise, ShotNoiseText);
  cli->Add("--model_scale", &experiment.model_scale,
           "The model is the world times this");
  cli->Add("--trials", &experiment.trials_per_view,
           "Independent noise draws per view");
  cli->Add("--max_angle_deg", &experiment.max_angle_deg,
           "Pitch and roll range");
  cli->Add("--step_deg", &experiment.step_deg, "Pitch and roll step");
  cli->Add("--num_features", &experiment.num_features, "Features per view");
  cli->Add("--seed", &experiment.seed, "Seed");
  cli->Add("--num_threads", &experiment.num_threads, "Threads (<= 0: all)");
  cli->Add("--out", &options->out, "Output folder (accuracy.csv, views.csv)")
      ->required();
}

void RunSimulate(const SimulateOptions& options) {
  const std::vector<ViewsExperimentRow> rows =
      RunViewsExperiment(options.experiment, [](size_t done, size_t total) {
        fmt::print("[simulate] {}/{} set-up x distance x noise done\n", done,
                   total);
        std::fflush(stdout);
      });
  fmt::print(
      "\nscale error e = s * model_scale - 1, over {} views (%):\n"
      "{:<5} {:>5} {:>6} {:>6} {:<14} {:>9} {:>9} {:>9} {:>9}\n",
      options.experiment.world.c_str(), "setup", "d[m]", "sf[px]", "sl[px]",
      "method", "mean", "sigma", "max|e|", "img max");
  for (const ViewsExperimentRow& row : rows) {
    fmt::print(
        "{:<5} {:5.1f} {:6.2f} {:6.2f} {:<14} {:9.4f} {:9.4f} {:9.4f} "
        "{:9.4f}\n",
        row.setup.c_str(), row.distance_m, row.noise.feature_px,
        row.noise.spot_px, ScaleMethodName(row.method).c_str(),
        100.0 * row.items.mean, 100.0 * row.items.std_dev,
        100.0 * row.items.max_abs, 100.0 * row.images.max_abs);
  }
  std::filesystem::create_directories(options.out);
  const auto text = [](const std::string& content) {
    return [content](std::ostream& stream) { stream << content; };
  };
  WriteFilesAtomically({{std::filesystem::path(options.out) / "accuracy.csv",
                         text(AccuracyCsvText(rows))},
                        {std::filesystem::path(options.out) / "views.csv",
                         text(ViewsCsvText(rows))}},
                       false);
  fmt::print("[simulate] wrote {}/accuracy.csv and views.csv\n",
             options.out.c_str());
}

}  // namespace

Subcommand SimulateCommand() {
  return MakeSubcommand<SimulateOptions>(
      "simulate",
      "the thesis's accuracy study of a laser set-up, before a cruise",
      "The thesis's chapter-3 accuracy study of laser set-ups on a uwsim "
      "world: a camera looks at one surface point from every pitch and roll "
      "(-40..40 deg in 5 deg steps: 289 views) at each distance; features "
      "and spots are synthesised with the given noise, each view is "
      "localized against the model (the world scaled by --model_scale) and "
      "every method estimates the scale. The scale error e = s * "
      "model_scale - 1 is tabulated per set-up, distance, noise and method "
      "(mean, sigma, max |e| over lasers/pairs and over images), so a set-up "
      "can be judged before a cruise.\n\n"
      "Example:\n"
      "  laserscale simulate --setups A,B,C --distances 2,3,4 --noise 0:0 "
      "--noise 0.5:0.25 --out sim_accuracy",
      AddSimulateFlags, RunSimulate);
}

}  // namespace uw
