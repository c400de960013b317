#include "calib/grey_image.h"

#include <opencv2/imgproc.hpp>

#include "common/util/error.h"

namespace uw {

cv::Mat GreyImage(const cv::Mat& image, const std::string& where) {
  if (image.empty() || image.depth() != CV_8U ||
      (image.channels() != 1 && image.channels() != 3)) {
    throw ErrorAt(where, ": expected an 8-bit grey or BGR image, got ",
                  image.empty() ? std::string("an empty one")
                                : std::to_string(image.channels()) +
                                      " channels of depth " +
                                      std::to_string(image.depth()));
  }
  if (image.channels() == 1) return image;
  cv::Mat grey;
  cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
  return grey;
}

}  // namespace uw
