// Chessboard corners in a calibration image, for corners.vnl.
#pragma once

#include <opencv2/core.hpp>

#include "calib/board.h"
#include "calib/corners_vnl.h"

namespace uw {

// Finds the board's inner corners with OpenCV's sector-based detector
// (cv::findChessboardCornersSB, accurate mode: sub-pixel by its own
// refinement) in an 8-bit grey or BGR image. Corners come in mrcal's order
// as mrgingham numbers them: from the corner nearest the image's top left,
// along the board row that runs most nearly left to right first. Pixels in
// mrcal's convention ((0, 0) = centre of the top-left pixel); every corner
// has weight 1 (level 0). Returns an observation without corners when the
// whole board is not found (OpenCV finds complete boards only).
// `image_name` is stored as is. Throws uw::Error on an empty image or a
// non-chessboard board.
BoardObservation DetectChessboard(const cv::Mat& image,
                                  const CalibrationBoard& board,
                                  const std::string& image_name);

}  // namespace uw
