// Images written as PNG (overlays, maps, heat maps): encoded in memory so
// that they can join an atomic set of files (file.h).
#pragma once

#include <filesystem>
#include <string>

#include <opencv2/core.hpp>

namespace uw {

// The PNG bytes of `image`; throws uw::Error naming `path` (the file it is
// meant for) when OpenCV cannot encode it.
std::string EncodePng(const cv::Mat& image, const std::filesystem::path& path);

// Encodes `image` as PNG and writes it atomically; throws uw::Error naming
// the path.
void WritePngAtomically(const cv::Mat& image,
                        const std::filesystem::path& path);

}  // namespace uw
