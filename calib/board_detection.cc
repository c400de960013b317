#include "calib/board_detection.h"

#include "calib/aprilgrid_detector.h"
#include "calib/charuco_detector.h"
#include "calib/chessboard_detector.h"

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

}  // namespace uw
