#include "calib/exe/detect_command.h"

#include <cstdio>

#include <fmt/format.h>

#include "calib/board_detection.h"
#include "calib/corners_vnl.h"
#include "calib/exe/board_flag.h"
#include "common/util/error.h"
#include "common/util/file.h"

namespace uw {
namespace {

void AddCalibDetectFlags(CommandLine* cli, CalibDetectOptions* options) {
  AddBoardFlag(cli, &options->board,
               "chessboard:COLSxROWS:SQUARE_M (inner corners, metres) or "
               "aprilgrid:COLSxROWS:TAG_M:GAP (Kalibr) or "
               "charuco:COLSxROWS:SQUARE_M:MARKER_M:DICT[:legacy] (squares)");
  cli->Add("--images", &options->images_dir, "Folder of the calibration images")
      ->required();
  cli->Add("--image_list_path", &options->image_list_path,
           "Only these images (names relative to --images, one a line)");
  cli->Add("--out", &options->out, "corners.vnl to write")->required();
  cli->Add("--num_threads", &options->num_threads, "Threads (<= 0: all)");
}

void RunCalibDetect(const CalibDetectOptions& options) {
  const std::vector<std::string> names =
      ListImages(options.images_dir, options.image_list_path);
  const std::vector<BoardObservation> observations = DetectBoardInImages(
      options.images_dir, names, options.board, options.num_threads,
      [](int done, int total) {
        if (done % 10 == 0 || done == total) {
          fmt::print(stderr, "[detect] {}/{} images\n", done, total);
        }
      });
  int found = 0;
  for (const BoardObservation& observation : observations) {
    found += observation.Found();
  }
  if (found == 0) {
    throw ErrorAt(options.images_dir, ": no image shows the whole board ",
                  options.board.ToString(), "; nothing written");
  }
  const std::string command =
      "uwcalib detect --board " + options.board.ToString();
  WriteFilesAtomically({{options.out,
                         [&](std::ostream& stream) {
                           stream << FormatCornersVnl(
                               observations, CornerWeightColumn::kLevel,
                               {"generated with " + command});
                         }}},
                       false);
  fmt::print("[detect] board found in {} of {} images; corners in {}\n", found,
             names.size(), options.out.c_str());
}

}  // namespace

Subcommand CalibDetectCommand() {
  return MakeSubcommand<CalibDetectOptions>(
      "detect", "find the board's corners in calibration images (corners.vnl)",
      "Finds a calibration board's corners in every image and writes them "
      "as mrcal's corners.vnl (the file mrgingham writes and "
      "mrcal-calibrate-cameras --corners-cache reads): the board's "
      "corners in mrcal's order, pixels with (0, 0) at the centre of the "
      "top-left pixel, level 0, and one row 'NAME - - -' for an image "
      "without the board. Chessboards are found by OpenCV's sector-based "
      "detector (whole boards only), Kalibr AprilGrids by libapriltag "
      "(any tags; corners of missing tags are '-'), ChArUco boards by "
      "OpenCV's ArUco markers (the corners next to found markers) "
      "(docs/uwcalib.md).\n\n"
      "Example:\n"
      "  uwcalib detect --board chessboard:9x6:0.025 --images calib "
      "--out corners.vnl\n"
      "  uwcalib detect --board charuco:20x20:0.004:0.0032:DICT_4X4_1000 "
      "--images cam1 --out corners.vnl",
      AddCalibDetectFlags, RunCalibDetect);
}

}  // namespace uw
