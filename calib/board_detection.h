// The detector a board's kind calls for.
#pragma once

#include <string>

#include <opencv2/core.hpp>

#include "calib/board.h"
#include "calib/corners_vnl.h"

namespace uw {

// DetectChessboard, DetectAprilGrid or DetectCharuco with their default
// options, by board.kind.
BoardObservation DetectBoardCorners(const cv::Mat& image,
                                    const CalibrationBoard& board,
                                    const std::string& image_name);

}  // namespace uw
