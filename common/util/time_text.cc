#include "common/util/time_text.h"

#include <cmath>
#include <cstdlib>
#include <ctime>
#include <string>

#include <fmt/format.h>

namespace uw {

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

}  // namespace uw
