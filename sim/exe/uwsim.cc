// uwsim: synthetic underwater worlds and surveys with ground truth. Like
// `colmap`, the first argument names the command and the rest are its
// flags.
#include "sim/exe/uwsim_commands.h"

int main(int argc, char** argv) {
  return uw::DispatchSubcommand(
      "uwsim",
      "uwsim: synthetic underwater worlds and surveys with ground truth "
      "(images, navigation, true poses, mesh).\n\n"
      "Usage:\n  uwsim <command> [--flag value ...]\n"
      "  uwsim <command> --help\n\n"
      "Example:\n"
      "  uwsim generate --world seafloor --survey lawnmower --out sim --seed "
      "1\n",
      uw::sim::UwsimCommands(), argc, argv);
}
