#include "sim/exe/map_command.h"

#include <iostream>

#include "sim/survey_map.h"

namespace uw::sim {
namespace {

void AddMapFlags(CommandLine* cli, MapCommandOptions* options) {
  cli->Add("--sim", &options->sim, "Output folder of uwsim generate")
      ->required();
  cli->Add("--out", &options->out, "Image to write: .png, .jpg or .jpeg")
      ->required();
  cli->Add("--width", &options->map.width_px,
           "Figure width in pixels (800-8000); the height follows the "
           "survey's aspect ratio");
  cli->Add("--title", &options->map.title, "Title above the map (ASCII)");
}

void RunMap(const MapCommandOptions& options) {
  WriteSurveyMap(options.sim, options.out, options.map);
  std::cout << "[uwsim] map of " << options.sim << " written to " << options.out
            << std::endl;
}

}  // namespace

Subcommand MapCommand() {
  return MakeSubcommand<MapCommandOptions>(
      "map", "draw a top view of an output folder: mesh, cameras, tracks",
      "Draw a top view of an uwsim output folder: the mesh as a hillshaded "
      "height map, the true camera centres by dive, the true vehicle track "
      "and the navigation track (docs/uwsim.md).\n\nExample:\n  uwsim map "
      "--sim sim --out sim_map.png [--width 1600]",
      AddMapFlags, RunMap);
}

}  // namespace uw::sim
