// When each image was taken, from the images themselves: their EXIF
// capture time (exif_time.h) or a time in their file names
// ("IMG_20241008_175320_250.jpg"). What `uwcolmap image_times` writes as
// image_times.csv (docs/formats.md), on the navigation's clock.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "colmap_plugins/nav/image_times.h"

namespace uw {

enum class ImageTimeSource { kExif, kFileName };
std::string ImageTimeSourceName(ImageTimeSource source);
ImageTimeSource ImageTimeSourceFromName(const std::string& name);

// A file-name pattern: the whole name without its extension must match.
// %Y year, %m month, %d day, %H hour, %M minute, %S second (digits as
// written, 4 or 2), %f decimals of the second (one or more digits), %z a
// zone (Z, +hh:mm, +hhmm), * any run of characters, %% a '%'; anything else
// literally. E.g. "IMG_%Y%m%d_%H%M%S_%f" reads IMG_20241008_175320_250.
// Returns the ISO 8601 time the name gives ("2024-10-08T17:53:20.250"
// with the zone if the pattern has one), or nullopt when it does not
// match. Throws uw::Error on a pattern without %Y %m %d %H %M %S.
std::optional<std::string> TimeInFileName(const std::string& stem,
                                          const std::string& pattern);

struct ImageTimesFromImagesOptions {
  std::string image_path;  // every image below it, named as COLMAP does
  ImageTimeSource source = ImageTimeSource::kExif;
  std::string filename_pattern;  // for kFileName
  // Seconds east of UTC of the camera's clock, for times that state no
  // zone (EXIF without OffsetTimeOriginal; file names without %z). None:
  // such times are an error, as a local clock is hours of ambiguity.
  std::optional<int> time_zone_offset_s;
  // Seconds added to every camera time: the camera clock's error against
  // the navigation's (as pose_prior_importer's --time_offset; give it at
  // one of the two, not both).
  double clock_offset_s = 0.0;

  void Check() const;
};

struct ImageTimesFromImages {
  std::vector<ImageTime> times;  // sorted by name; line 0
  int zone_stated = 0;           // times whose zone the image stated
  int zone_assumed = 0;          // times read on time_zone_offset_s
};

// Every image's time; `progress` (if given) is called after each image
// with (done, total). Throws uw::Error naming the images without a time
// (the first few and how many) and on any image whose time is not one.
ImageTimesFromImages ReadImageTimesFromImages(
    const ImageTimesFromImagesOptions& options,
    const std::function<void(size_t, size_t)>& progress = nullptr);

// image_times.csv text: a comment line saying where the times came from,
// then image_name,time with every digit (Unix time).
std::string ImageTimesCsvText(const std::vector<ImageTime>& times,
                              const std::string& comment);

}  // namespace uw
