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
    case NavLogFormat::kWaterLinked:
      return "waterlinked";
  }
  return "auto";
}

NavLogFormat NavLogFormatFromName(const std::string& name) {
  for (const NavLogFormat format :
       {NavLogFormat::kAuto, NavLogFormat::kCsv, NavLogFormat::kNmea,
        NavLogFormat::kWaterLinked}) {
    if (NavLogFormatName(format) == name) return format;
  }
  throw ErrorAt("unknown navigation log format '", name,
                "' (auto, csv, nmea, waterlinked)");
}

void NavLogOptions::Check() const {
  if (origin) origin->Check();
  nmea.Check();
}

std::vector<NavRecord> ReadNavigationLog(const std::filesystem::path& path,
                                         const NavLogOptions& options,
                                         NavLogFrame* frame) {
  options.Check();
  NavLogFormat format = options.format;
  if (format == NavLogFormat::kAuto) {
    format = LooksLikeNmea(path)      ? NavLogFormat::kNmea
             : LooksLikeUgpsLog(path) ? NavLogFormat::kWaterLinked
                                      : NavLogFormat::kCsv;
  }
  if (format != NavLogFormat::kWaterLinked &&
      (options.ugps.topside || !options.ugps.master_path.empty())) {
    throw ErrorAt(path.string(),
                  ": --ugps_topside and --ugps_master are for "
                  "a Water Linked log, and this is ",
                  NavLogFormatName(format));
  }
  if (format != NavLogFormat::kCsv && !options.columns.empty()) {
    throw ErrorAt(path.string(), ": --columns is for a CSV log, and this is ",
                  NavLogFormatName(format));
  }
  switch (format) {
    case NavLogFormat::kNmea:
      return ReadNmeaLog(path, options.nmea, options.origin, frame);
    case NavLogFormat::kWaterLinked:
      return ReadUgpsLog(path, options.ugps, options.origin, frame);
    default:
      return ReadNavigationCsv(path, options.origin, frame,
                               options.time_zone_offset_s, options.columns);
  }
}

}  // namespace uw
