#include "sim/exe/generate_command.h"

#include <chrono>
#include <iostream>

#include <fmt/format.h>
#include <tbb/global_control.h>

#include "sim/generate.h"

namespace uw::sim {
namespace {

void AddGenerateFlags(CommandLine* cli, GenerateCommandOptions* options) {
  const SimConfig defaults;
  cli->Add<std::optional<WorldKind>>(
      "--world", &options->world,
      "seafloor | vent | scarp | breakwater | canyon",
      [](const std::string& name) { return WorldKindFromName(name); },
      [defaults](const std::optional<WorldKind>& kind) {
        return WorldKindName(kind.value_or(defaults.world));
      });
  cli->Add<std::optional<SurveyKind>>(
      "--survey", &options->survey,
      "lawnmower | single_pass | multi_dive | video | views",
      [](const std::string& name) { return SurveyKindFromName(name); },
      [defaults](const std::optional<SurveyKind>& kind) {
        return SurveyKindName(kind.value_or(defaults.survey));
      });
  cli->Add("--out", &options->out, "Output folder (new or empty)")->required();
  cli->Add("--seed", &options->seed, "Random seed",
           std::optional<uint64_t>(defaults.seed));
  cli->Add("--config", &options->config_path,
           "JSON file with any of the sections of truth/sim.json; flags "
           "override its world, survey and seed");
  cli->Add("--max_images", &options->max_images,
           "Stop the survey after this many images");
  cli->Add("--num_threads", &options->num_threads,
           "Threads to render with (-1: all cores); the output does not "
           "depend on it");
  cli->Add("--render_images", &options->render_images,
           "0: write no images, only the plan, navigation, laser set-up and "
           "truth (seconds, not minutes; enough for uwsim observe)");
}

void RunGenerate(const GenerateCommandOptions& options) {
  const SimConfig config = GenerateConfig(options);
  std::optional<tbb::global_control> thread_limit;
  if (options.num_threads > 0) {
    thread_limit.emplace(tbb::global_control::max_allowed_parallelism,
                         static_cast<size_t>(options.num_threads));
  }
  const auto start = std::chrono::steady_clock::now();
  const auto seconds = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() -
                                         start)
        .count();
  };
  const GenerateSummary summary = Generate(
      config, options.out,
      [&](size_t done, size_t total) {
        if (done == total || done % 10 == 0) {
          std::cout << fmt::format("[uwsim] rendered {}/{} images ({:.6g} s)",
                                   done, total, seconds())
                    << std::endl;
        }
      },
      options.render_images);
  std::cout << fmt::format(
                   "[uwsim] {} images and {} laser images (+ auxiliaries) of "
                   "{}/{} ({} triangles) {} to {} in {:.6g} s",
                   summary.num_images, summary.num_laser_images,
                   WorldKindName(config.world), SurveyKindName(config.survey),
                   summary.num_triangles,
                   options.render_images
                       ? "written"
                       : "planned (not rendered; truth written)",
                   options.out, seconds())
            << std::endl;
}

}  // namespace

SimConfig GenerateConfig(const GenerateCommandOptions& options) {
  SimConfig config = options.config_path.empty()
                         ? SimConfig()
                         : ReadSimConfig(options.config_path);
  if (options.world) config.world = *options.world;
  if (options.survey) config.survey = *options.survey;
  if (options.seed) config.seed = *options.seed;
  if (options.max_images && *options.max_images >= 0) {
    config.survey_options.max_images = *options.max_images;
  }
  return config;
}

Subcommand GenerateCommand() {
  return MakeSubcommand<GenerateCommandOptions>(
      "generate",
      "render a survey of a world: images, navigation, laser images, truth",
      "Render a survey of a world; writes images/, laser_images/, nav.csv, "
      "lasers.json and truth/ "
      "(docs/uwsim.md).\n\nExample:\n  uwsim generate --world seafloor "
      "--survey lawnmower --out sim --seed 1 [--config sim.json]",
      AddGenerateFlags, RunGenerate);
}

}  // namespace uw::sim
