#include "colmap_plugins/nav/image_time_source.h"

#include <regex>

#include <fmt/format.h>

#include "common/util/csv.h"
#include "common/util/error.h"
#include "common/util/exif_time.h"
#include "common/util/file.h"
#include "common/util/time_text.h"

namespace uw {

std::string ImageTimeSourceName(ImageTimeSource source) {
  return source == ImageTimeSource::kExif ? "exif" : "filename";
}

ImageTimeSource ImageTimeSourceFromName(const std::string& name) {
  for (const ImageTimeSource source :
       {ImageTimeSource::kExif, ImageTimeSource::kFileName}) {
    if (ImageTimeSourceName(source) == name) return source;
  }
  throw ErrorAt("unknown image time source '", name, "' (exif, filename)");
}

std::optional<std::string> TimeInFileName(const std::string& stem,
                                          const std::string& pattern) {
  std::string expression;
  std::string fields;  // the conversion letter of each group, in order
  for (size_t i = 0; i < pattern.size(); ++i) {
    const char c = pattern[i];
    if (c == '*') {
      expression += ".*";
    } else if (c != '%') {
      if (std::string("\\^$.|?+()[]{}").find(c) != std::string::npos) {
        expression += '\\';
      }
      expression += c;
    } else if (i + 1 == pattern.size()) {
      throw ErrorAt("--filename_pattern '", pattern, "' ends with '%'");
    } else {
      const char field = pattern[++i];
      switch (field) {
        case 'Y':
          expression += "(\\d{4})";
          break;
        case 'm':
        case 'd':
        case 'H':
        case 'M':
        case 'S':
          expression += "(\\d{2})";
          break;
        case 'f':
          expression += "(\\d+)";
          break;
        case 'z':
          expression += "(Z|[+-]\\d{2}:?\\d{2})";
          break;
        case '%':
          expression += '%';
          continue;
        default:
          throw ErrorAt("--filename_pattern '", pattern, "': unknown %", field,
                        " (%Y %m %d %H %M %S %f %z %%)");
      }
      if (fields.find(field) != std::string::npos) {
        throw ErrorAt("--filename_pattern '", pattern, "' has %", field,
                      " twice");
      }
      fields += field;
    }
  }
  for (const char needed : std::string("YmdHMS")) {
    if (fields.find(needed) == std::string::npos) {
      throw ErrorAt("--filename_pattern '", pattern, "' has no %", needed,
                    ": it needs %Y %m %d %H %M %S");
    }
  }
  std::smatch match;
  if (!std::regex_match(stem, match, std::regex(expression))) {
    return std::nullopt;
  }
  const auto field = [&](char letter) {
    const size_t k = fields.find(letter);
    return k == std::string::npos ? std::string() : match[k + 1].str();
  };
  std::string iso = fmt::format("{}-{}-{}T{}:{}:{}", field('Y'), field('m'),
                                field('d'), field('H'), field('M'), field('S'));
  if (!field('f').empty()) iso += "." + field('f');
  return iso + field('z');
}

void ImageTimesFromImagesOptions::Check() const {
  if (image_path.empty()) throw ErrorAt("--image_path is required");
  if (source == ImageTimeSource::kFileName) {
    if (filename_pattern.empty()) {
      throw ErrorAt(
          "--source filename needs --filename_pattern (e.g. "
          "IMG_%Y%m%d_%H%M%S_%f)");
    }
    TimeInFileName("", filename_pattern);  // refuses a bad pattern
  } else if (!filename_pattern.empty()) {
    throw ErrorAt("--filename_pattern is for --source filename");
  }
  if (!std::isfinite(clock_offset_s)) {
    throw ErrorAt("--clock_offset must be finite");
  }
}

ImageTimesFromImages ReadImageTimesFromImages(
    const ImageTimesFromImagesOptions& options,
    const std::function<void(size_t, size_t)>& progress) {
  options.Check();
  const std::vector<std::string> names =
      ListImages(options.image_path, "", nullptr, true);
  ImageTimesFromImages result;
  std::vector<std::string> missing;
  for (size_t i = 0; i < names.size(); ++i) {
    const std::string& name = names[i];
    const std::filesystem::path path =
        std::filesystem::path(options.image_path) / name;
    std::optional<double> time;
    bool zone_stated = false;
    if (options.source == ImageTimeSource::kExif) {
      time =
          ReadExifCaptureTime(path, options.time_zone_offset_s, &zone_stated);
    } else {
      const std::optional<std::string> iso =
          TimeInFileName(path.stem().string(), options.filename_pattern);
      if (iso) {
        zone_stated = options.filename_pattern.find("%z") != std::string::npos;
        time = ParseIsoTime(*iso, name + ": time in the file name",
                            options.time_zone_offset_s);
      }
    }
    if (!time) {
      missing.push_back(name);
    } else {
      ImageTime image_time;
      image_time.image_name = name;
      image_time.time_s = *time + options.clock_offset_s;
      result.times.push_back(image_time);
      ++(zone_stated ? result.zone_stated : result.zone_assumed);
    }
    if (progress) progress(i + 1, names.size());
  }
  if (!missing.empty()) {
    std::string examples;
    for (size_t k = 0; k < std::min<size_t>(missing.size(), 5); ++k) {
      examples += (k == 0 ? "" : ", ") + missing[k];
    }
    throw ErrorAt(options.image_path, ": ", missing.size(), " of ",
                  names.size(), " images have no ",
                  options.source == ImageTimeSource::kExif
                      ? std::string("EXIF capture time (DateTimeOriginal)")
                      : "time matching --filename_pattern '" +
                            options.filename_pattern + "'",
                  ": ", examples, missing.size() > 5 ? ", ..." : "");
  }
  return result;
}

std::string ImageTimesCsvText(const std::vector<ImageTime>& times,
                              const std::string& comment) {
  std::string text = "# " + comment + "\nimage_name,time\n";
  for (const ImageTime& time : times) {
    text += CsvField(time.image_name) + "," + SecondsText(time.time_s) + "\n";
  }
  return text;
}

}  // namespace uw
