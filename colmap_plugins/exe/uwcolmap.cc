// uwcolmap: COLMAP-compatible commands of uwmetric. Like `colmap`, the first
// argument names the command and the rest are its flags.
#include "colmap_plugins/exe/uwcolmap_commands.h"

int main(int argc, char** argv) {
  return uw::DispatchSubcommand(
      "uwcolmap",
      "uwcolmap: uwmetric's COLMAP-compatible commands.\n\n"
      "Usage:\n  uwcolmap <command> [--flag value ...]\n"
      "  uwcolmap <command> --help\n\n"
      "Example:\n  uwcolmap model_analyzer --path sparse/0\n",
      uw::UwcolmapCommands(), argc, argv);
}
