// Kalibr AprilGrid corners in an image, for corners.vnl.
#pragma once

#include <opencv2/core.hpp>

#include "calib/board.h"
#include "calib/corners_vnl.h"

namespace uw {

struct AprilGridOptions {
  // Kalibr: an observation needs this many tags.
  int min_tags = 4;
  // Corners are refined by cornerSubPix (they are X-junctions: each tag
  // corner touches a small black square) in a (2 half + 1)^2 window; a
  // corner the refinement moves further than max_refine_shift_px is
  // dropped (Kalibr's 5x5 window and sqrt(1.5) px).
  int refine_half_window_px = 2;
  double max_refine_shift_px = 1.2247;

  void Check() const;
};

// The grid's tags with libapriltag (tag36h11 codes, 2-cell border) in four
// passes whose tags are pooled by id: the image at quad decimation 1 and 2,
// then the image with white grown by a 3x3 maximum (dim or blurred frames
// merge a tag's border with the corner squares otherwise) at 2 and 1.
// Each tag gives its 4 corners at their place in Kalibr's order; the rest
// are missing (weight -1). 8-bit grey or BGR. No board (no corners) below
// min_tags tags. The dilated passes' corners are moved back out by the
// pixel the dilation took. Then grid completion: a missing tag is
// predicted by the homography of the nearest found ones and kept if the
// image there shows its code (<= 2 bits off). `num_tags` (if given) gets the
// tags found. Throws uw::Error for a board that is no AprilGrid.
BoardObservation DetectAprilGrid(const cv::Mat& image,
                                 const CalibrationBoard& board,
                                 const std::string& image_name,
                                 const AprilGridOptions& options,
                                 int* num_tags = nullptr);

}  // namespace uw
