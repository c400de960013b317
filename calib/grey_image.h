// The 8-bit grey image the board detectors work on.
#pragma once

#include <string>

#include <opencv2/core.hpp>

namespace uw {

// `image` itself if 8-bit grey, its grey conversion if 8-bit BGR; throws
// uw::Error naming `where` for anything else (empty, other depths or
// channel counts).
cv::Mat GreyImage(const cv::Mat& image, const std::string& where);

}  // namespace uw
