// image_times.csv: when each image was taken (docs/formats.md), on the
// clock of nav.csv. Needed when the images are not the navigation's own
// samples: the cameras of an unsynchronised rig, or a log recorded at its
// own rate.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace uw {

struct ImageTime {
  std::string image_name;
  double time_s = 0.0;
  // The dive the image belongs to; 0 when the file has no dive column (it
  // is then the dive whose time span holds the image's time).
  int dive = 0;
  int line = 0;  // 1-based line in the file, for messages
};

// Reads image_times.csv strictly: header image_name,time[,dive] (any
// order), non-empty unique names, times in seconds or ISO 8601 (a time
// without a zone on the clock `time_zone_offset_s` east of UTC), dives
// integers >= 1. Throws uw::Error naming the file and line.
std::vector<ImageTime> ReadImageTimesCsv(
    const std::filesystem::path& path,
    std::optional<int> time_zone_offset_s = std::nullopt);

}  // namespace uw
