#include "common/util/png_file.h"

#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "common/util/error.h"
#include "common/util/file.h"

namespace uw {

std::string EncodePng(const cv::Mat& image, const std::filesystem::path& path) {
  std::vector<uchar> bytes;
  if (image.empty() || !cv::imencode(".png", image, bytes)) {
    throw ErrorAt(path.string(), ": cannot encode the image as PNG");
  }
  return std::string(bytes.begin(), bytes.end());
}

void WritePngAtomically(const cv::Mat& image,
                        const std::filesystem::path& path) {
  const std::string bytes = EncodePng(image, path);
  WriteFilesAtomically({{path, [&](std::ostream& out) { out << bytes; }}},
                       true);
}

}  // namespace uw
