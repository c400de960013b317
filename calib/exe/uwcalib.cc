// uwcalib: mrcal-style camera calibration sessions. Like `colmap`, the
// first argument names the command and the rest are its flags.
#include "calib/exe/uwcalib_commands.h"

int main(int argc, char** argv) {
  return uw::DispatchSubcommand(
      "uwcalib",
      "uwcalib: camera calibration from board images, with mrcal.\n\n"
      "Usage:\n  uwcalib <command> [--flag value ...]\n"
      "  uwcalib <command> --help\n\n"
      "Example (docs/uwcalib.md):\n"
      "  uwcalib detect    --board chessboard:9x6:0.025 --images calib "
      "--out corners.vnl\n"
      "  uwcalib calibrate --board chessboard:9x6:0.025 --corners "
      "corners.vnl --lens_model LENSMODEL_OPENCV8 --focal 850 --imagersize "
      "1024,768 --out cal\n"
      "  uwcalib export    --cameramodel cal/camera-0.cameramodel --to "
      "colmap --output_path sparse_camera\n"
      "  uwcalib lasers    --images laser_boards --board chessboard:9x7:0.08 "
      "--cameramodel cal/camera-0.cameramodel --num_lasers 4 --out "
      "lasers.json\n"
      "  uwcalib lasers-from-mission --input_path sparse/0 --mesh mesh.ply "
      "--spots spots.json --poses poses.json --origins origins.json --out "
      "lasers.json\n",
      uw::UwcalibCommands(), argc, argv);
}
