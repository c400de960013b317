#include <cstdio>
#include <sstream>

#include "common/cli/command.h"
#include "common/util/error.h"
#include "common/util/file.h"
#include "experiments/laser_experiment.h"
#include "laserscale/exe/commands.h"

namespace uw {
namespace {

std::vector<std::string> Split(const std::string& text, char separator) {
  std::vector<std::string> parts;
  std::stringstream stream(text);
  std::string part;
  while (std::getline(stream, part, separator)) parts.push_back(part);
  return parts;
}

double ParseNumber(const std::string& text, const std::string& flag) {
  try {
    size_t used = 0;
    const double value = std::stod(text, &used);
    if (used == text.size()) return value;
  } catch (...) {
  }
  throw ErrorAt("--", flag, ": '", text, "' is not a number");
}

// "feature_px:spot_px[:direction_deg[:origin_m]]".
ShotNoise ParseNoise(const std::string& text) {
  const std::vector<std::string> parts = Split(text, ':');
  if (parts.size() < 2 || parts.size() > 4) {
    throw ErrorAt(
        "--noise: expected feature_px:spot_px[:direction_deg"
        "[:origin_m]], got '",
        text, "'");
  }
  ShotNoise noise;
  noise.feature_px = ParseNumber(parts[0], "noise");
  noise.spot_px = ParseNumber(parts[1], "noise");
  if (parts.size() > 2) noise.direction_deg = ParseNumber(parts[2], "noise");
  if (parts.size() > 3) noise.origin_m = ParseNumber(parts[3], "noise");
  noise.Check();
  return noise;
}

std::string Row(const ViewsExperimentRow& row) {
  std::ostringstream line;
  line << row.setup << "," << row.distance_m << "," << row.noise.feature_px
       << "," << row.noise.spot_px << "," << row.noise.direction_deg << ","
       << row.noise.origin_m << "," << ScaleMethodName(row.method) << ","
       << row.num_views << "," << row.num_unlocalized;
  for (const ErrorStats* stats : {&row.items, &row.images}) {
    line << "," << stats->count << "," << stats->num_invalid << ","
         << 100.0 * stats->mean << "," << 100.0 * stats->std_dev << ","
         << 100.0 * stats->max_abs;
  }
  return line.str();
}

}  // namespace

int RunSimulate(int argc, char** argv) {
  CLI::App app(
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
      "laserscale simulate");
  ViewsExperimentOptions options;
  std::string target;
  std::string distances = "2,3,4";
  std::string setups = "A,B,C";
  std::string methods = "fum,pcm,direct,davis_tusting";
  std::vector<std::string> noise_levels;
  std::string out;
  app.add_option("--world", options.world,
                 "uwsim world (vent, seafloor, scarp, breakwater, canyon)")
      ->capture_default_str();
  app.add_option("--area", options.area,
                 "flank (vent only: rough), top (the world's views point), "
                 "custom (--target)")
      ->capture_default_str();
  app.add_option("--target", target, "x,y,z of the surveyed point (world m)");
  app.add_option("--distances", distances, "Camera-point distances (m)")
      ->capture_default_str();
  app.add_option("--setups", setups, "uwsim laser set-ups (A, B, C)")
      ->capture_default_str();
  app.add_option("--methods", methods, "Methods to compare")
      ->capture_default_str();
  app.add_option("--noise", noise_levels,
                 "feature_px:spot_px[:direction_deg[:origin_m]], repeatable "
                 "(default: 0:0, noise-free)");
  app.add_option("--model_scale", options.model_scale,
                 "The model is the world times this")
      ->capture_default_str();
  app.add_option("--trials", options.trials_per_view,
                 "Independent noise draws per view")
      ->capture_default_str();
  app.add_option("--max_angle_deg", options.max_angle_deg,
                 "Pitch and roll range")
      ->capture_default_str();
  app.add_option("--step_deg", options.step_deg, "Pitch and roll step")
      ->capture_default_str();
  app.add_option("--num_features", options.num_features, "Features per view")
      ->capture_default_str();
  app.add_option("--seed", options.seed, "Seed")->capture_default_str();
  app.add_option("--num_threads", options.num_threads, "Threads (<= 0: all)")
      ->capture_default_str();
  app.add_option("--out", out, "Output folder (accuracy.csv, views.csv)")
      ->required();
  return RunCommand(app, argc, argv, [&] {
    options.distances_m.clear();
    for (const std::string& d : Split(distances, ',')) {
      options.distances_m.push_back(ParseNumber(d, "distances"));
    }
    options.setups = Split(setups, ',');
    options.methods.clear();
    for (const std::string& m : Split(methods, ',')) {
      options.methods.push_back(ScaleMethodFromName(m));
    }
    if (!noise_levels.empty()) {
      options.noise_levels.clear();
      for (const std::string& n : noise_levels) {
        options.noise_levels.push_back(ParseNoise(n));
      }
    }
    if (!target.empty()) {
      const std::vector<std::string> xyz = Split(target, ',');
      if (xyz.size() != 3) throw ErrorAt("--target: expected x,y,z");
      options.target = Eigen::Vector3d(ParseNumber(xyz[0], "target"),
                                       ParseNumber(xyz[1], "target"),
                                       ParseNumber(xyz[2], "target"));
    }
    const std::vector<ViewsExperimentRow> rows =
        RunViewsExperiment(options, [](size_t done, size_t total) {
          std::printf("[simulate] %zu/%zu set-up x distance x noise done\n",
                      done, total);
          std::fflush(stdout);
        });
    std::ostringstream accuracy;
    accuracy << "setup,distance_m,feature_px,spot_px,direction_deg,origin_m,"
                "method,num_views,num_unlocalized,items_n,items_invalid,"
                "items_mean_pct,items_std_pct,items_max_abs_pct,images_n,"
                "images_invalid,images_mean_pct,images_std_pct,"
                "images_max_abs_pct\n";
    std::ostringstream views;
    views << "setup,distance_m,feature_px,spot_px,method,pitch_deg,roll_deg,"
             "scale_error_pct\n";
    std::printf(
        "\nscale error e = s * model_scale - 1, over %s views (%%):\n"
        "%-5s %5s %6s %6s %-14s %9s %9s %9s %9s\n",
        options.world.c_str(), "setup", "d[m]", "sf[px]", "sl[px]", "method",
        "mean", "sigma", "max|e|", "img max");
    for (const ViewsExperimentRow& row : rows) {
      accuracy << Row(row) << "\n";
      for (const auto& [pitch, roll, error] : row.image_errors) {
        views << row.setup << "," << row.distance_m << ","
              << row.noise.feature_px << "," << row.noise.spot_px << ","
              << ScaleMethodName(row.method) << "," << pitch << "," << roll
              << ",";
        if (!std::isnan(error)) views << 100.0 * error;
        views << "\n";
      }
      std::printf("%-5s %5.1f %6.2f %6.2f %-14s %9.4f %9.4f %9.4f %9.4f\n",
                  row.setup.c_str(), row.distance_m, row.noise.feature_px,
                  row.noise.spot_px, ScaleMethodName(row.method).c_str(),
                  100.0 * row.items.mean, 100.0 * row.items.std_dev,
                  100.0 * row.items.max_abs, 100.0 * row.images.max_abs);
    }
    std::filesystem::create_directories(out);
    const auto text = [](const std::string& content) {
      return [content](std::ostream& stream) { stream << content; };
    };
    WriteFilesAtomically(
        {{std::filesystem::path(out) / "accuracy.csv", text(accuracy.str())},
         {std::filesystem::path(out) / "views.csv", text(views.str())}},
        false);
    std::printf("[simulate] wrote %s/accuracy.csv and views.csv\n",
                out.c_str());
  });
}

}  // namespace uw
