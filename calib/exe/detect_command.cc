#include <atomic>
#include <cstdio>
#include <filesystem>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <opencv2/imgcodecs.hpp>

#include "calib/board.h"
#include "calib/board_detection.h"
#include "calib/corners_vnl.h"
#include "calib/exe/commands.h"
#include "common/cli/command.h"
#include "common/util/error.h"
#include "common/util/file.h"

namespace uw {

int RunCalibDetect(int argc, char** argv) {
  CLI::App app(
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
      "uwcalib detect");
  std::string board_spec;
  std::string images_dir;
  std::string image_list_path;
  std::string out;
  int num_threads = 0;
  app.add_option("--board", board_spec,
                 "chessboard:COLSxROWS:SQUARE_M (inner corners, metres) or "
                 "aprilgrid:COLSxROWS:TAG_M:GAP (Kalibr) or "
                 "charuco:COLSxROWS:SQUARE_M:MARKER_M:DICT[:legacy] (squares)")
      ->required();
  app.add_option("--images", images_dir, "Folder of the calibration images")
      ->required();
  app.add_option("--image_list_path", image_list_path,
                 "Only these images (names relative to --images, one a line)");
  app.add_option("--out", out, "corners.vnl to write")->required();
  app.add_option("--num_threads", num_threads, "Threads (<= 0: all)")
      ->capture_default_str();
  return RunCommand(app, argc, argv, [&] {
    const CalibrationBoard board = ParseBoard(board_spec);
    const std::vector<std::string> names =
        ListImages(images_dir, image_list_path);
    for (const std::string& name : names) {
      if (name.find_first_of(" \t") != std::string::npos) {
        throw ErrorAt(images_dir, "/", name,
                      ": image names with white space cannot go into "
                      "corners.vnl (mrcal splits at it)");
      }
    }
    std::vector<BoardObservation> observations(names.size());
    std::atomic<int> done{0};
    tbb::task_arena arena(num_threads > 0 ? num_threads
                                          : tbb::task_arena::automatic);
    arena.execute([&] {
      tbb::parallel_for(size_t{0}, names.size(), [&](size_t i) {
        const std::filesystem::path path =
            std::filesystem::path(images_dir) / names[i];
        const cv::Mat image = cv::imread(path.string(), cv::IMREAD_GRAYSCALE);
        if (image.empty()) {
          throw ErrorAt(path.string(), ": cannot read the image");
        }
        observations[i] = DetectBoardCorners(image, board, names[i]);
        const int finished = ++done;
        if (finished % 10 == 0 || finished == static_cast<int>(names.size())) {
          std::fprintf(stderr, "[detect] %d/%zu images\n", finished,
                       names.size());
        }
      });
    });
    int found = 0;
    for (const BoardObservation& observation : observations) {
      found += observation.Found();
    }
    if (found == 0) {
      throw ErrorAt(images_dir, ": no image shows the whole board ",
                    board.ToString(), "; nothing written");
    }
    const std::string command = "uwcalib detect --board " + board.ToString();
    WriteFilesAtomically({{out,
                           [&](std::ostream& stream) {
                             stream << FormatCornersVnl(
                                 observations, CornerWeightColumn::kLevel,
                                 {"generated with " + command});
                           }}},
                         false);
    std::printf("[detect] board found in %d of %zu images; corners in %s\n",
                found, names.size(), out.c_str());
  });
}

}  // namespace uw
