#include "common/util/time_text.h"

#include <cmath>
#include <cstdlib>
#include <ctime>
#include <string>

#include <fmt/format.h>

#include "common/util/error.h"
#include "common/util/number_text.h"

namespace uw {
namespace {

// Exactly n digits at text[*i], advancing past them; nullopt otherwise.
std::optional<int> Digits(const std::string& text, size_t* i, int n) {
  if (*i + n > text.size()) return std::nullopt;
  int value = 0;
  for (int k = 0; k < n; ++k) {
    const char c = text[*i + k];
    if (c < '0' || c > '9') return std::nullopt;
    value = 10 * value + (c - '0');
  }
  *i += n;
  return value;
}

bool Skip(const std::string& text, size_t* i, const char* any_of) {
  if (*i >= text.size()) return false;
  for (const char* c = any_of; *c != '\0'; ++c) {
    if (text[*i] == *c) {
      ++*i;
      return true;
    }
  }
  return false;
}

// The zone that ends `text` from i: Z, ±hh, ±hh:mm or ±hhmm, as seconds
// east of UTC.
std::optional<int> ZoneAt(const std::string& text, size_t i) {
  if (Skip(text, &i, "Zz"))
    return i == text.size() ? std::optional(0) : std::nullopt;
  if (i >= text.size() || (text[i] != '+' && text[i] != '-')) {
    return std::nullopt;
  }
  const int sign = text[i++] == '-' ? -1 : 1;
  const std::optional<int> hours = Digits(text, &i, 2);
  if (!hours || *hours > 14) return std::nullopt;
  int minutes = 0;
  if (i < text.size()) {
    Skip(text, &i, ":");
    const std::optional<int> mm = Digits(text, &i, 2);
    if (!mm || *mm > 59 || i != text.size()) return std::nullopt;
    minutes = *mm;
  }
  return sign * (3600 * *hours + 60 * minutes);
}

}  // namespace

std::string SecondsText(double seconds) {
  if (!std::isfinite(seconds)) return fmt::format("{}", seconds);
  if (seconds == 0.0) return "0";  // and never "-0"
  // fmt's shortest round trip picks exponent notation when it is shorter;
  // then the same digits are printed positionally, with as many decimals as
  // the mantissa has beyond the exponent.
  const std::string shortest = fmt::format("{}", seconds);
  const size_t e = shortest.find('e');
  if (e == std::string::npos) return shortest;
  const size_t point = shortest.find('.');
  const int mantissa_decimals = point == std::string::npos || point > e
                                    ? 0
                                    : static_cast<int>(e - point - 1);
  const int exponent = std::atoi(shortest.c_str() + e + 1);
  return fmt::format("{:.{}f}", seconds,
                     std::max(0, mantissa_decimals - exponent));
}

std::string TimeText(double seconds) {
  const std::string text = SecondsText(seconds);
  constexpr double kFirstUnixTime = 1e8;          // 1973-03-03
  constexpr double kLastUnixTime = 4102444800.0;  // 2100-01-01
  if (!(seconds >= kFirstUnixTime && seconds < kLastUnixTime)) return text;
  const double whole = std::floor(seconds);
  const std::time_t time = static_cast<std::time_t>(whole);
  std::tm utc{};
  gmtime_r(&time, &utc);
  // The fraction as SecondsText gave it: the digits after its point.
  const size_t point = text.find('.');
  const std::string fraction =
      point == std::string::npos ? "" : text.substr(point);
  return fmt::format("{} ({:04d}-{:02d}-{:02d}T{:02d}:{:02d}:{:02d}{}Z)", text,
                     utc.tm_year + 1900, utc.tm_mon + 1, utc.tm_mday,
                     utc.tm_hour, utc.tm_min, utc.tm_sec, fraction);
}

std::string DurationText(double seconds) {
  // Past 1e12 s (31 700 years: a clock in ns read as s) units stop helping.
  if (!(std::abs(seconds) < 1e12)) return SecondsText(seconds) + " s";
  // Whole milliseconds, so that the seconds print without float noise.
  const long long ms = std::llround(std::abs(seconds) * 1000.0);
  const long long units[] = {ms / 86400000, ms % 86400000 / 3600000,
                             ms % 3600000 / 60000, ms % 60000};
  const char* names[] = {"d", "h", "min", "s"};
  int first = 0;
  while (first < 3 && units[first] == 0) ++first;
  int last = 3;
  while (last > first && units[last] == 0) --last;
  std::string text = seconds < 0.0 && ms > 0 ? "-" : "";
  for (int k = first; k <= last; ++k) {
    text += k == first ? "" : " ";
    text += k == 3 ? SecondsText(static_cast<double>(units[3]) / 1000.0)
                   : std::to_string(units[k]);
    text += std::string(" ") + names[k];
  }
  return text;
}

std::optional<double> UnixTimeOfDay(int year, int month, int day) {
  if (year < 1900 || year > 9999 || month < 1 || month > 12 || day < 1 ||
      day > 31) {
    return std::nullopt;
  }
  std::tm utc{};
  utc.tm_year = year - 1900;
  utc.tm_mon = month - 1;
  utc.tm_mday = day;
  const std::time_t time = timegm(&utc);
  // timegm normalises: 2024-02-30 comes back as March 1st.
  if (utc.tm_year != year - 1900 || utc.tm_mon != month - 1 ||
      utc.tm_mday != day) {
    return std::nullopt;
  }
  return static_cast<double>(time);
}

int ParseZoneOffset(const std::string& text, const std::string& where) {
  const std::optional<int> offset = ZoneAt(text, 0);
  if (!offset) {
    throw ErrorAt(where, ": '", text,
                  "' is not a time zone (Z, +hh:mm or -hh:mm, e.g. +02:00)");
  }
  return *offset;
}

double ParseIsoTime(const std::string& text, const std::string& where,
                    std::optional<int> zone_offset_s) {
  const auto refuse = [&](const std::string& why) {
    return ErrorAt(where, ": '", text, "' is not an ISO 8601 time (", why,
                   "; e.g. 2024-10-08T17:53:20.25Z)");
  };
  size_t i = 0;
  const std::optional<int> year = Digits(text, &i, 4);
  const bool date_ok = year && Skip(text, &i, "-");
  const std::optional<int> month = date_ok ? Digits(text, &i, 2) : std::nullopt;
  const std::optional<int> day =
      month && Skip(text, &i, "-") ? Digits(text, &i, 2) : std::nullopt;
  if (!day) throw refuse("expected the date as YYYY-MM-DD");
  const std::optional<double> midnight = UnixTimeOfDay(*year, *month, *day);
  if (!midnight) throw refuse("no such day");
  const std::optional<int> hour =
      Skip(text, &i, "T ") ? Digits(text, &i, 2) : std::nullopt;
  const std::optional<int> minute =
      hour && Skip(text, &i, ":") ? Digits(text, &i, 2) : std::nullopt;
  const std::optional<int> second =
      minute && Skip(text, &i, ":") ? Digits(text, &i, 2) : std::nullopt;
  if (!second) throw refuse("expected the time of day as Thh:mm:ss");
  if (*hour > 23 || *minute > 59 || *second > 59) {
    throw refuse("no such time of day");
  }
  double fraction = 0.0;
  if (Skip(text, &i, ".,")) {
    const size_t first = i;
    while (i < text.size() && text[i] >= '0' && text[i] <= '9') ++i;
    if (i == first) throw refuse("expected digits after the decimal point");
    fraction = *FiniteDouble("0." + text.substr(first, i - first));
  }
  int offset = 0;
  if (i == text.size()) {
    if (!zone_offset_s) {
      throw ErrorAt(where, ": '", text,
                    "' has no time zone (Z or +hh:mm): a clock in local time "
                    "is ambiguous; give its zone (--time_zone)");
    }
    offset = *zone_offset_s;
  } else {
    const std::optional<int> zone = ZoneAt(text, i);
    if (!zone) throw refuse("expected the zone Z or +hh:mm after the time");
    offset = *zone;
  }
  return *midnight + 3600.0 * *hour + 60.0 * *minute + *second + fraction -
         offset;
}

double ParseTimeField(const std::string& text, const std::string& where,
                      std::optional<int> zone_offset_s) {
  const size_t first = text.find_first_not_of(" \t");
  const size_t last = text.find_last_not_of(" \t");
  const std::string trimmed =
      first == std::string::npos ? "" : text.substr(first, last - first + 1);
  if (const std::optional<double> seconds = FiniteDouble(trimmed)) {
    return *seconds;
  }
  if (trimmed.size() >= 10 && trimmed[4] == '-') {
    return ParseIsoTime(trimmed, where, zone_offset_s);
  }
  throw ErrorAt(where,
                ": expected seconds or an ISO 8601 time (e.g. "
                "2024-10-08T17:53:20.25Z), got '",
                text, "'");
}

std::string IsoTimeText(double unix_s, int zone_offset_s, int decimals) {
  if (decimals < 0 || decimals > 9) {
    throw ErrorAt("IsoTimeText: decimals must be 0 to 9, got ", decimals);
  }
  const double local = unix_s + zone_offset_s;
  // -2208988800 and 253402300800: 1900-01-01 and 10000-01-01.
  if (!(local >= -2208988800.0 && local < 253402300800.0)) {
    throw ErrorAt("time ", SecondsText(unix_s),
                  " s lies outside the years 1900 to 9999");
  }
  double whole = std::floor(local);
  const long long unit = std::llround(std::pow(10.0, decimals));
  long long fraction = std::llround((local - whole) * unit);
  if (fraction == unit) {
    whole += 1.0;
    fraction = 0;
  }
  const std::time_t time = static_cast<std::time_t>(whole);
  std::tm clock{};
  gmtime_r(&time, &clock);
  std::string text =
      fmt::format("{:04d}-{:02d}-{:02d}T{:02d}:{:02d}:{:02d}",
                  clock.tm_year + 1900, clock.tm_mon + 1, clock.tm_mday,
                  clock.tm_hour, clock.tm_min, clock.tm_sec);
  if (decimals > 0) text += fmt::format(".{:0{}d}", fraction, decimals);
  return text + ZoneOffsetText(zone_offset_s);
}

std::string ZoneOffsetText(int zone_offset_s) {
  if (zone_offset_s == 0) return "Z";
  const int minutes = std::abs(zone_offset_s) / 60;
  return fmt::format("{}{:02d}:{:02d}", zone_offset_s < 0 ? '-' : '+',
                     minutes / 60, minutes % 60);
}

}  // namespace uw
