#include "colmap_plugins/exe/nav_flags.h"

#include <fmt/format.h>

#include "common/util/time_text.h"

namespace uw {

void AddNavFlags(CommandLine* cli, PosePriorImportOptions* options,
                 bool nav_required, const std::string& rig_flag) {
  CLI::Option* nav = cli->Add(
      "--nav", &options->nav_path,
      "Navigation log (nav.csv: time and vehicle position x,y,z in m, "
      "lat,lon,depth|alt in WGS84 deg and m, or UTM easting,northing,zone,"
      "depth|alt; optionally roll,pitch and yaw or heading in deg, and their "
      "sigmas; docs/formats.md)");
  if (nav_required) nav->required();
  cli->Add("--image_times", &options->image_times_path,
           "image_name,time of every image (image_times.csv); the log is "
           "then a time series interpolated at those times");
  cli->Add(rig_flag, &options->rig_config_path,
           "Camera rig (rig.json): each image gets the pose of the rig "
           "camera whose image_prefix starts its name");
  NavToCameraOptions& nav_to_camera = options->nav_to_camera;
  cli->Add<CameraMount>(
      "--mount", &nav_to_camera.mount,
      "How the (reference) camera looks: down, starboard, port, forward",
      CameraMountFromName, CameraMountName);
  cli->Add("--lever_arm", &nav_to_camera.lever_arm_m,
           "Camera centre in the vehicle frame (x forward, y left, z up), m: "
           "x,y,z");
  cli->Add("--boresight", &nav_to_camera.boresight_deg,
           "Small rotation after the mount, roll,pitch,yaw in deg");
  cli->Add("--time_offset", &nav_to_camera.time_offset_s,
           "Seconds added to every image time to get the navigation time at "
           "which it was taken");
  cli->Add<std::optional<GeoOrigin>>(
      "--origin", &options->log.origin,
      "lat,lon[,height] (deg, m) of the local east-north-up frame a "
      "geographic log (lat,lon or UTM) is read into; default: its first fix "
      "rounded to 0.001 deg, printed",
      [](const std::string& text) {
        return std::optional<GeoOrigin>(GeoOriginFromText(text, "--origin"));
      },
      [](const std::optional<GeoOrigin>& origin) {
        return origin ? GeoOriginText(*origin) : std::string("automatic");
      });
  cli->Add<NavLogFormat>(
      "--nav_format", &options->log.format,
      "Format of --nav: csv (nav.csv), nmea (NMEA 0183: GGA fixes, HDT "
      "headings, RMC/ZDA dates), waterlinked (a Water Linked UGPS acoustic "
      "log: timestamp,x,y,z relative to the topside) or auto (by its first "
      "line)",
      NavLogFormatFromName, NavLogFormatName);
  cli->Add("--nmea_date", &options->log.nmea.date,
           "UTC date YYYY-MM-DD of an NMEA log without RMC or ZDA sentences");
  cli->Add<std::optional<UgpsTopside>>(
      "--ugps_topside", &options->log.ugps.topside,
      "lat,lon,heading (deg) of the Water Linked topside of a --nav "
      "waterlinked log, when it did not move",
      [](const std::string& text) {
        return std::optional<UgpsTopside>(
            UgpsTopsideFromText(text, "--ugps_topside"));
      },
      [](const std::optional<UgpsTopside>& topside) {
        return topside ? fmt::format("{},{},{}", topside->lat_deg,
                                     topside->lon_deg, topside->heading_deg)
                       : std::string("none");
      });
  cli->Add<NavColumnMap>(
      "--columns", &options->log.columns,
      "An export's names for nav.csv's columns, ours=theirs: e.g. "
      "\"lat=Latitude,lon=Longitude,depth=Depth (m),time=timestamp\"; its "
      "other columns are ignored",
      [](const std::string& text) {
        return NavColumnMapFromText(text, "--columns");
      },
      NavColumnMapText);
  cli->Add("--ugps_master", &options->log.ugps.master_path,
           "The topside's own log of a --nav waterlinked log "
           "(timestamp,lat,lon,orientation: GET /api/v1/position/master), "
           "interpolated at each row's time");
  AddTimeZoneFlag(cli, &options->log.time_zone_offset_s,
                  "Zone (+hh:mm, -hh:mm or Z) of the clock that wrote ISO "
                  "8601 times without one in --nav and --image_times; "
                  "default: such times are an error");
  cli->Add("--unlogged_roll_pitch_sigma",
           &nav_to_camera.unlogged_roll_pitch_sigma_deg,
           "Sigma (deg) of the roll and pitch a log with heading but no roll "
           "and pitch is taken to have (0), carried through the lever arm");
}

void AddTimeZoneFlag(CommandLine* cli, std::optional<int>* offset_s,
                     const std::string& help) {
  cli->Add<std::optional<int>>(
      "--time_zone", offset_s, help,
      [](const std::string& text) {
        return std::optional<int>(ParseZoneOffset(text, "--time_zone"));
      },
      [](const std::optional<int>& offset) {
        return offset ? ZoneOffsetText(*offset) : std::string("none");
      });
}

void AddPlausibilityFlags(CommandLine* cli,
                          AlignmentPlausibilityOptions* options,
                          const std::string& prefix) {
  cli->Add(prefix + "min_range", &options->min_range_m,
           "Refuse an alignment whose scale puts the cameras closer than this "
           "to what they see (median depth, m): degrees read as metres");
  cli->Add(prefix + "max_range", &options->max_range_m,
           "Refuse an alignment whose scale puts the cameras farther than "
           "this from what they see (m): millimetres read as metres");
  cli->Add(prefix + "accept_implausible", &options->accept_implausible,
           "1: an implausible alignment (range, a navigation that does not "
           "follow the images) is a warning, not an error");
}

}  // namespace uw
