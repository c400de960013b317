#include "calib/rig_views.h"

#include <fnmatch.h>

#include <algorithm>
#include <cctype>
#include <filesystem>

#include "common/util/error.h"

namespace uw {

int FrameOfImage(const std::string& image) {
  const std::string stem = std::filesystem::path(image).stem().string();
  const size_t end = stem.find_last_of("0123456789");
  if (end == std::string::npos) {
    throw ErrorAt(image, ": a rig's image names need a frame number");
  }
  size_t begin = end;
  while (begin > 0 &&
         std::isdigit(static_cast<unsigned char>(stem[begin - 1]))) {
    --begin;
  }
  return std::stoi(stem.substr(begin, std::min<size_t>(end - begin + 1, 9)));
}

std::vector<RigCameraViews> SplitViewsByCamera(
    const std::vector<BoardObservation>& observations,
    const std::vector<std::string>& globs, const std::string& where) {
  std::vector<RigCameraViews> cameras(globs.size());
  for (size_t i = 0; i < observations.size(); ++i) {
    const BoardObservation& observation = observations[i];
    size_t c = 0;
    while (c < globs.size() &&
           fnmatch(globs[c].c_str(), observation.image.c_str(), 0) != 0) {
      ++c;
    }
    if (c == globs.size()) continue;  // not one of the cameras
    cameras[c].views.push_back(observation);
    cameras[c].frames.push_back(globs.size() == 1
                                    ? static_cast<int>(i)
                                    : FrameOfImage(observation.image));
  }
  for (size_t c = 0; c < globs.size(); ++c) {
    if (cameras[c].views.empty()) {
      throw ErrorAt(where, ": no image matches camera ", c, "'s glob '",
                    globs[c], "'");
    }
  }
  return cameras;
}

}  // namespace uw
