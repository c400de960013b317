#include "colmap_plugins/nav/nav_log.h"

#include "common/util/error.h"

namespace uw {

std::string NavLogFormatName(NavLogFormat format) {
  switch (format) {
    case NavLogFormat::kAuto:
      return "auto";
    case NavLogFormat::kCsv:
      return "csv";
    case NavLogFormat::kNmea:
      return "nmea";
  }
  return "auto";
}

NavLogFormat NavLogFormatFromName(const std::string& name) {
  for (const NavLogFormat format :
       {NavLogFormat::kAuto, NavLogFormat::kCsv, NavLogFormat::kNmea}) {
    if (NavLogFormatName(format) == name) return format;
  }
  throw ErrorAt("unknown navigation log format '", name, "' (auto, csv, nmea)");
}

void NavLogOptions::Check() const {
  if (origin) origin->Check();
  nmea.Check();
}

std::vector<NavRecord> ReadNavigationLog(const std::filesystem::path& path,
                                         const NavLogOptions& options,
                                         NavLogFrame* frame) {
  options.Check();
  const bool nmea =
      options.format == NavLogFormat::kNmea ||
      (options.format == NavLogFormat::kAuto && LooksLikeNmea(path));
  return nmea ? ReadNmeaLog(path, options.nmea, options.origin, frame)
              : ReadNavigationCsv(path, options.origin, frame,
                                  options.time_zone_offset_s);
}

}  // namespace uw
