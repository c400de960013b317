// ChArUco board corners in an image, for corners.vnl.
#pragma once

#include <string>

#include <opencv2/core.hpp>

#include "calib/board.h"
#include "calib/corners_vnl.h"

namespace uw {

struct CharucoOptions {
  // An observation needs this many corners (mrcal needs a pose per board).
  int min_corners = 6;

  void Check() const;
};

// The board's markers by OpenCV's ArUco detector; then each inner corner
// next to a found marker, predicted through the homography of the found
// markers within a square of it and moved onto its X-junction by
// cornerSubPix (in a window inside the white margin around the markers,
// where the corner is a clean chessboard corner); a corner the refinement
// moves by more than half that window is dropped. OpenCV's own
// interpolateCornersCharuco is not used: OpenCV 4.6 knows only the new
// layout and would misplace the corners of a legacy board. Missing corners
// have weight -1; no board below min_corners corners. 8-bit grey or BGR.
// `num_markers` (if given) gets the board's markers found. Throws uw::Error
// for a board that is no ChArUco board.
BoardObservation DetectCharuco(const cv::Mat& image,
                               const CalibrationBoard& board,
                               const std::string& image_name,
                               const CharucoOptions& options,
                               int* num_markers = nullptr);

// Where marker `id` of the board sits: its square (column from the left,
// row from the top); (-1, -1) for an id the board does not have.
cv::Point CharucoMarkerSquare(const CalibrationBoard& board, int id);

}  // namespace uw
