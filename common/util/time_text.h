// Times as text a user can check against their logs: every digit the value
// holds, never 1.72841e+09 (a Unix time with its last four digits, and the
// fraction, gone), and the calendar time next to a Unix time, so that a
// clock days off shows in the message itself.
#pragma once

#include <optional>
#include <string>

namespace uw {

// Text that reads back to the same double, in positional notation, with
// the shortest round trip's digits where it has a fraction: 1728410000.25,
// 1700000000, 0.00001234, -3.5. (Past 1e16 the integer part is the
// double's exact value.) Non-finite values as "nan", "inf", "-inf".
std::string SecondsText(double seconds);

// SecondsText, and for a time from 1973 to 2100 read as Unix time (s since
// 1970-01-01 UTC) the UTC calendar time it is:
//   "1728410000.25 (2024-10-08T17:53:20.25Z)".
// Smaller values (seconds since a survey's start) are left alone: 1e8 s is
// three years.
std::string TimeText(double seconds);

// A span of time in the units a person reads a clock error in: "58 d 3 h",
// "2 h 0 min 5 s", "12.5 s", "-1 d 0 h 0 min 0.25 s" (whole days, hours and
// minutes, then seconds to the millisecond; zero units after the largest are
// left out only at the end). Past 1e12 s, and for non-finite values,
// SecondsText and " s".
std::string DurationText(double seconds);

// Seconds from 1970-01-01T00:00Z to 00:00Z of a UTC calendar day, or
// nullopt for a day that does not exist (2024-02-30, month 13) or lies
// outside 1900 to 9999.
std::optional<double> UnixTimeOfDay(int year, int month, int day);

// An ISO 8601 time as Unix time (s): "2024-10-08T17:53:20.25Z",
// "2024-10-08 19:53:20+02:00", "...-0800", "...+05"; any number of decimals
// after a '.' or ','. A time must state its zone: a clock in local time is a
// day's worth of ambiguity, so one without a zone is refused unless
// `zone_offset_s` (what --time_zone gives) says where the clock was. Throws
// uw::Error "<where>: ..." on anything else (2024-02-30, 24:00:01, trailing
// text), saying what was expected.
double ParseIsoTime(const std::string& text, const std::string& where,
                    std::optional<int> zone_offset_s = std::nullopt);

// A time field of a log: seconds (Unix or since any start) as a number, or
// an ISO 8601 time as ParseIsoTime reads it.
double ParseTimeField(const std::string& text, const std::string& where,
                      std::optional<int> zone_offset_s = std::nullopt);

// "+02:00", "-08:00", "Z" or "+05:30" (also "+0200", "+02") as seconds east
// of UTC, as --time_zone and EXIF's OffsetTime give it. Throws uw::Error
// naming `where`.
int ParseZoneOffset(const std::string& text, const std::string& where);

// Its inverse: "Z" for 0, else "+02:00", "-05:30".
std::string ZoneOffsetText(int zone_offset_s);

// A Unix time as ISO 8601 on a clock `zone_offset_s` east of UTC, with
// `decimals` (0 to 9) digits of the second, rounded:
//   IsoTimeText(1728410000.25, 7200, 3) == "2024-10-08T19:53:20.250+02:00".
// Zone 0 is written "Z". Throws uw::Error outside the years 1900 to 9999.
std::string IsoTimeText(double unix_s, int zone_offset_s, int decimals);

}  // namespace uw
