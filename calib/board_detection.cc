#include "calib/board_detection.h"

#include <atomic>
#include <filesystem>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <opencv2/imgcodecs.hpp>

#include "calib/aprilgrid_detector.h"
#include "calib/charuco_detector.h"
#include "calib/chessboard_detector.h"
#include "common/util/error.h"

namespace uw {

BoardObservation DetectBoardCorners(const cv::Mat& image,
                                    const CalibrationBoard& board,
                                    const std::string& image_name) {
  switch (board.kind) {
    case BoardKind::kAprilGrid:
      return DetectAprilGrid(image, board, image_name, AprilGridOptions());
    case BoardKind::kCharuco:
      return DetectCharuco(image, board, image_name, CharucoOptions());
    case BoardKind::kChessboard:
      break;
  }
  return DetectChessboard(image, board, image_name);
}

std::vector<BoardObservation> DetectBoardInImages(
    const std::string& images_dir, const std::vector<std::string>& names,
    const CalibrationBoard& board, int num_threads,
    const std::function<void(int done, int total)>& progress) {
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
      if (progress) progress(finished, static_cast<int>(names.size()));
    });
  });
  return observations;
}

}  // namespace uw
