// uwsim: synthetic underwater worlds and surveys with ground truth.
#include <chrono>
#include <fstream>
#include <iostream>
#include <optional>

#include <tbb/global_control.h>
#include <CLI/CLI.hpp>

#include "common/util/error.h"
#include "common/util/file.h"
#include "sim/generate.h"
#include "sim/observe.h"
#include "sim/survey_map.h"

int main(int argc, char** argv) {
  CLI::App app(
      "uwsim: synthetic underwater worlds and surveys with ground truth "
      "(images, navigation, true poses, mesh).\n\n"
      "Example:\n"
      "  uwsim generate --world seafloor --survey lawnmower --out sim --seed 1",
      "uwsim");
  app.require_subcommand(1);
  CLI::App* generate = app.add_subcommand(
      "generate",
      "Render a survey of a world; writes images/, laser_images/, nav.csv, "
      "lasers.json and truth/ "
      "(docs/uwsim.md).\n\nExample:\n  uwsim generate --world seafloor "
      "--survey lawnmower --out sim --seed 1 [--config sim.json]");
  std::string world = "seafloor";
  std::string survey = "lawnmower";
  std::string out;
  std::string config_path;
  uint64_t seed = 1;
  int max_images = -1;
  int num_threads = -1;
  generate
      ->add_option("--world", world,
                   "seafloor | vent | scarp | breakwater | canyon")
      ->capture_default_str();
  generate
      ->add_option("--survey", survey,
                   "lawnmower | single_pass | multi_dive | video | views")
      ->capture_default_str();
  generate->add_option("--out", out, "Output folder (new or empty)")
      ->required();
  generate->add_option("--seed", seed, "Random seed")->capture_default_str();
  generate->add_option("--config", config_path,
                       "JSON file with any of the sections of truth/sim.json; "
                       "flags override its world, survey and seed");
  generate->add_option("--max_images", max_images,
                       "Stop the survey after this many images");
  generate
      ->add_option("--num_threads", num_threads,
                   "Threads to render with (-1: all cores); the output "
                   "does not depend on it")
      ->capture_default_str();
  CLI::App* map_command = app.add_subcommand(
      "map",
      "Draw a top view of an uwsim output folder: the mesh as a hillshaded "
      "height map, the true camera centres by dive, the true vehicle track "
      "and the navigation track (docs/uwsim.md).\n\nExample:\n  uwsim map "
      "--sim sim --out sim_map.png [--width 1600]");
  std::string map_sim;
  std::string map_out;
  uw::SurveyMapOptions map_options;
  map_command->add_option("--sim", map_sim, "Output folder of uwsim generate")
      ->required();
  map_command
      ->add_option("--out", map_out, "Image to write: .png, .jpg or .jpeg")
      ->required();
  map_command
      ->add_option("--width", map_options.width_px,
                   "Figure width in pixels (800-8000); the height follows "
                   "the survey's aspect ratio")
      ->capture_default_str();
  map_command->add_option("--title", map_options.title,
                          "Title above the map (ASCII)");
  CLI::App* observe_command = app.add_subcommand(
      "observe",
      "Write the feature tracks a perfect matcher and mapper would give for "
      "an uwsim output folder: points sampled on truth/mesh.ply, observed by "
      "every image that sees them, with Gaussian pixel noise; a COLMAP text "
      "model with truth/'s camera and image ids (docs/uwsim.md).\n\n"
      "Example:\n  uwsim observe --sim sim --output_path tracks "
      "--pixel_sigma 0.5 --init perturbed");
  std::string observe_sim;
  std::string observe_out;
  std::string observe_init = "truth";
  uw::sim::ObserveOptions observe_options;
  observe_command
      ->add_option("--sim", observe_sim, "Output folder of uwsim generate")
      ->required();
  observe_command
      ->add_option("--output_path", observe_out,
                   "Model folder to write (new or empty)")
      ->required();
  observe_command
      ->add_option("--pixel_sigma", observe_options.pixel_sigma,
                   "Standard deviation of the pixel noise per coordinate")
      ->capture_default_str();
  observe_command
      ->add_option("--num_points", observe_options.num_points,
                   "3D points, each seen by at least 2 images")
      ->capture_default_str();
  observe_command->add_option("--seed", observe_options.seed, "Random seed")
      ->capture_default_str();
  observe_command
      ->add_option("--init", observe_init,
                   "Poses and points: truth, or perturbed (the truth moved "
                   "by a random similarity, scale 0.3-3, with pose noise)")
      ->capture_default_str();
  observe_command
      ->add_option("--perturb_rotation_deg",
                   observe_options.perturb_rotation_deg,
                   "perturbed: rotation noise per camera and axis")
      ->capture_default_str();
  observe_command
      ->add_option("--perturb_position_m", observe_options.perturb_position_m,
                   "perturbed: camera centre noise per axis, world metres")
      ->capture_default_str();
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    return app.exit(error) == 0 ? 0 : 2;
  }
  if (map_command->parsed()) {
    try {
      uw::sim::WriteSurveyMap(map_sim, map_out, map_options);
      std::cout << "[uwsim] map of " << map_sim << " written to " << map_out
                << std::endl;
    } catch (const std::exception& error) {
      std::cerr << "ERROR: " << error.what() << std::endl;
      return 1;
    }
    return 0;
  }
  if (observe_command->parsed()) {
    try {
      observe_options.init = uw::sim::ObserveInitFromName(observe_init);
      const uw::sim::ObserveSummary summary =
          uw::sim::ObserveSimulation(observe_sim, observe_out, observe_options);
      std::cout << "[uwsim] observe: " << summary.num_points << " points ("
                << summary.num_candidates << " sampled), "
                << summary.num_observations << " observations, init "
                << observe_init << " (model_from_world "
                << uw::ToJson(summary.model_from_world).dump()
                << ") written to " << observe_out << std::endl;
    } catch (const std::exception& error) {
      std::cerr << "ERROR: " << error.what() << std::endl;
      return 1;
    }
    return 0;
  }
  try {
    uw::sim::SimConfig config;
    if (!config_path.empty()) {
      nlohmann::json json;
      try {
        json = nlohmann::json::parse(uw::ReadFileToString(config_path));
      } catch (const nlohmann::json::parse_error& error) {
        throw uw::ErrorAt(config_path, ": ", error.what());
      }
      try {
        json.get_to(config);
      } catch (const nlohmann::json::exception& error) {
        throw uw::ErrorAt(config_path, ": ", error.what());
      }
    }
    if (generate->count("--world") || config_path.empty()) {
      config.world = uw::sim::WorldKindFromName(world);
    }
    if (generate->count("--survey") || config_path.empty()) {
      config.survey = uw::sim::SurveyKindFromName(survey);
    }
    if (generate->count("--seed") || config_path.empty()) config.seed = seed;
    if (max_images >= 0) config.survey_options.max_images = max_images;
    std::optional<tbb::global_control> thread_limit;
    if (num_threads > 0) {
      thread_limit.emplace(tbb::global_control::max_allowed_parallelism,
                           static_cast<size_t>(num_threads));
    }
    const auto start = std::chrono::steady_clock::now();
    const auto seconds = [&] {
      return std::chrono::duration<double>(std::chrono::steady_clock::now() -
                                           start)
          .count();
    };
    const uw::sim::GenerateSummary summary =
        uw::sim::Generate(config, out, [&](size_t done, size_t total) {
          if (done == total || done % 10 == 0) {
            std::cout << "[uwsim] rendered " << done << "/" << total
                      << " images (" << seconds() << " s)" << std::endl;
          }
        });
    std::cout << "[uwsim] " << summary.num_images << " images and "
              << summary.num_laser_images << " laser images (+ auxiliaries) of "
              << uw::sim::WorldKindName(config.world) << "/"
              << uw::sim::SurveyKindName(config.survey) << " ("
              << summary.num_triangles << " triangles) written to " << out
              << " in " << seconds() << " s" << std::endl;
  } catch (const std::exception& error) {
    std::cerr << "ERROR: " << error.what() << std::endl;
    return 1;
  }
  return 0;
}
