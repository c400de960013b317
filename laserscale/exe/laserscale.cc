// laserscale: the metric scale of a COLMAP model, with its confidence
// interval, from laser-scaler images. Like `colmap`, the first argument
// names the command and the rest are its flags.
#include "laserscale/exe/laserscale_commands.h"

int main(int argc, char** argv) {
  return uw::DispatchSubcommand(
      "laserscale",
      "laserscale: the metric scale of a COLMAP model from laser-scaler "
      "images.\n\n"
      "Usage:\n  laserscale <command> [--flag value ...]\n"
      "  laserscale <command> --help\n\n"
      "Example (docs/laserscale.md):\n"
      "  laserscale detect   --images laser_images --lasers lasers.json "
      "--input_path sparse/0 --out spots.json\n"
      "  laserscale localize --database_path database.db --input_path "
      "sparse/0 --image_list_path laser_list.txt --out poses.json\n"
      "  laserscale estimate --mesh mesh.ply --poses poses.json --spots "
      "spots.json --lasers lasers.json --out report\n"
      "  laserscale apply    --input_path sparse/0 --scale "
      "report/scale.json --output_path sparse_metric\n",
      uw::LaserscaleCommands(), argc, argv);
}
