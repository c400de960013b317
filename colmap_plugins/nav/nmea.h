// NMEA 0183 navigation logs, as GPS receivers, USBL systems and vehicle
// loggers write them: GGA fixes, HDT headings, and the UTC date from RMC or
// ZDA sentences (docs/formats.md, "NMEA logs").
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "colmap_plugins/nav/nav_csv.h"

namespace uw {

struct NmeaOptions {
  // The UTC date (YYYY-MM-DD) of a log with neither RMC nor ZDA sentences;
  // empty: such a log is an error. A date sentence in the log wins.
  std::string date;

  void Check() const;
};

// The checksum of a sentence: the XOR of the bytes between its '$' and
// its '*', written after the '*' as two hex digits.
unsigned NmeaChecksum(std::string_view body);

// Whether `path` is an NMEA log: its first line that is neither blank nor
// a '#' comment holds a sentence ("$GPGGA,...", after any prefix a logger
// wrote, such as a timestamp).
bool LooksLikeNmea(const std::filesystem::path& path);

// One NavRecord per GGA fix: its UTC time (Unix s, the fix's time of day
// on the date of the latest RMC or ZDA, or of the first one for fixes
// before it; past midnight the next day), its position from latitude,
// longitude and the GGA altitude (m above mean sea level, so height 0 of
// the local frame is sea level) in LocalEnu at `origin` (AutomaticOrigin of
// the first fix when not given), and the heading of the latest HDT before
// it in the file (none in the log: a position-only log). Sigmas read 0.
// Sentences may follow a prefix on their line; other sentences are
// skipped. A fix of quality 0 (no fix) or with empty coordinates is left
// out and counted in `frame->notes`. Throws uw::Error naming file:line for
// a checksum that does not match, a malformed GGA, HDT, RMC or ZDA, a time
// that does not increase, and a log with fixes but no date.
std::vector<NavRecord> ReadNmeaLog(const std::filesystem::path& path,
                                   const NmeaOptions& options,
                                   const std::optional<GeoOrigin>& origin,
                                   NavLogFrame* frame);

}  // namespace uw
