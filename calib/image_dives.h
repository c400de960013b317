// The dive of each image (docs/uwcalib.md: --image_dives, a CSV
// image_name,dive), for uwcalib lasers-from-mission's RMS per dive.
#pragma once

#include <map>
#include <string>

namespace uw {

// Empty for an empty path (every image is dive 1). Images the file does not
// name are dive 1. Throws uw::Error naming file and line for a dive that is
// no integer >= 1 or an image listed twice, and as the CSV reader does for
// a missing file or a bad header.
std::map<std::string, int> ReadImageDives(const std::string& path);

}  // namespace uw
