// The projection-uncertainty map as mrcal-show-projection-uncertainty draws
// it: a heat map over the image with contours (docs/uwcalib.md).
#pragma once

#include <string>

#include <opencv2/core.hpp>

#include "calib/projection_uncertainty.h"

namespace uw {

// The map over an image of image_width x image_height (scaled to about 900
// pixels across), interpolated between its samples: colour from 0 to
// colour_max_px (mrcal's default --cbmax, 3 px; above saturates, so the same
// colour means the same uncertainty in every report), contours at mrcal's
// round step near a tenth of that (0.2 px for 3 px) labelled in pixels, a
// colour bar, and `title` over a line with the centre's and the worst
// value.
cv::Mat RenderProjectionUncertainty(const ProjectionUncertaintyMap& map,
                                    int image_width, int image_height,
                                    const std::string& title,
                                    double colour_max_px = 3.0);

}  // namespace uw
