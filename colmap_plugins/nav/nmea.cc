#include "colmap_plugins/nav/nmea.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "common/util/error.h"
#include "common/util/number_text.h"
#include "common/util/time_text.h"

namespace uw {
namespace {

// One sentence: its line, its type ("GGA") and its fields after the
// address field.
struct Sentence {
  int line = 0;
  std::string type;
  std::vector<std::string> fields;
};

constexpr double kSecondsPerDay = 86400.0;

// The text after the first '$' of a line, or empty when it has none.
std::string SentenceText(const std::string& line) {
  const size_t dollar = line.find('$');
  return dollar == std::string::npos ? std::string() : line.substr(dollar + 1);
}

bool IsBlankOrComment(const std::string& line) {
  const size_t first = line.find_first_not_of(" \t\r");
  return first == std::string::npos || line[first] == '#';
}

// Checks the checksum when there is one and splits the fields.
std::optional<Sentence> ParseSentence(const std::string& text, int line,
                                      const std::string& where) {
  std::string body = text;
  const size_t star = text.find('*');
  if (star != std::string::npos) {
    body = text.substr(0, star);
    const std::string given = text.substr(star + 1, 2);
    const unsigned checksum = NmeaChecksum(body);
    unsigned given_value = 0;
    const auto [end, error] = std::from_chars(
        given.data(), given.data() + given.size(), given_value, 16);
    if (given.size() != 2 || error != std::errc() ||
        end != given.data() + given.size() || given_value != checksum) {
      throw ErrorAt(where, ": checksum *", given, " does not match the ",
                    "sentence (computed *", fmt::format("{:02X}", checksum),
                    "): a line cut or corrupted");
    }
  }
  std::vector<std::string> fields;
  std::stringstream stream(body);
  for (std::string field; std::getline(stream, field, ',');) {
    fields.push_back(field);
  }
  if (!body.empty() && body.back() == ',') fields.emplace_back();
  // A talker's sentence: two letters and the type; proprietary ones (P...)
  // and others are skipped.
  if (fields.empty() || fields[0].size() != 5 || fields[0][0] == 'P') {
    return std::nullopt;
  }
  Sentence sentence;
  sentence.line = line;
  sentence.type = fields[0].substr(2);
  fields.erase(fields.begin());
  sentence.fields = std::move(fields);
  return sentence;
}

double Number(const std::string& text, const std::string& what,
              const std::string& where) {
  const std::optional<double> value = FiniteDouble(text);
  if (!value) throw ErrorAt(where, ": ", what, " '", text, "' is not a number");
  return *value;
}

// hhmmss(.sss) as seconds of the day.
double TimeOfDay(const std::string& text, const std::string& where) {
  if (text.size() < 6) {
    throw ErrorAt(where, ": time '", text, "' is not hhmmss.ss");
  }
  const double hours = Number(text.substr(0, 2), "hours", where);
  const double minutes = Number(text.substr(2, 2), "minutes", where);
  const double seconds = Number(text.substr(4), "seconds", where);
  if (hours >= 24.0 || minutes >= 60.0 || seconds >= 61.0 || hours < 0.0 ||
      minutes < 0.0 || seconds < 0.0) {
    throw ErrorAt(where, ": time '", text, "' is not hhmmss.ss");
  }
  return 3600.0 * hours + 60.0 * minutes + seconds;
}

// ddmm.mmmm (or dddmm.mmmm) and its hemisphere as signed degrees.
double Degrees(const std::string& text, const std::string& hemisphere,
               const char* positive, const char* negative, double limit,
               const std::string& where) {
  const double value = Number(text, "coordinate", where);
  const double degrees = std::floor(value / 100.0);
  const double minutes = value - 100.0 * degrees;
  if (value < 0.0 || minutes >= 60.0 || degrees > limit) {
    throw ErrorAt(where, ": '", text, "' is not degrees and minutes");
  }
  if (hemisphere != positive && hemisphere != negative) {
    throw ErrorAt(where, ": hemisphere '", hemisphere, "' is neither ",
                  positive, " nor ", negative);
  }
  return (hemisphere == positive ? 1.0 : -1.0) * (degrees + minutes / 60.0);
}

// 00:00Z of the date a RMC (ddmmyy) or ZDA (dd, mm, yyyy) gives.
double DayOf(const Sentence& sentence, const std::string& where) {
  int day = 0;
  int month = 0;
  int year = 0;
  if (sentence.type == "RMC") {
    const std::string& date = sentence.fields.at(8);
    if (date.size() != 6) {
      throw ErrorAt(where, ": RMC date '", date, "' is not ddmmyy");
    }
    day = static_cast<int>(Number(date.substr(0, 2), "day", where));
    month = static_cast<int>(Number(date.substr(2, 2), "month", where));
    year = static_cast<int>(Number(date.substr(4, 2), "year", where));
    // Two digits, as NMEA gives them: 1980 to 2079.
    year += year < 80 ? 2000 : 1900;
  } else {
    day = static_cast<int>(Number(sentence.fields.at(1), "day", where));
    month = static_cast<int>(Number(sentence.fields.at(2), "month", where));
    year = static_cast<int>(Number(sentence.fields.at(3), "year", where));
  }
  const std::optional<double> start = UnixTimeOfDay(year, month, day);
  if (!start) {
    throw ErrorAt(where, ": ", sentence.type, " date ", year, "-", month, "-",
                  day, " does not exist");
  }
  return *start;
}

// A date sentence's time of day and day, when it carries a date.
struct DateMark {
  double day = 0.0;
  double time_of_day = 0.0;
  bool timed = true;  // false: --nmea_date, a day without a time
};
std::optional<DateMark> DateOf(const Sentence& sentence,
                               const std::string& where) {
  const bool rmc = sentence.type == "RMC" && sentence.fields.size() >= 9;
  const bool zda = sentence.type == "ZDA" && sentence.fields.size() >= 4;
  if (!rmc && !zda) return std::nullopt;
  if (sentence.fields[0].empty() ||
      (rmc ? sentence.fields[8] : sentence.fields[1]).empty()) {
    return std::nullopt;  // a receiver without time yet
  }
  return DateMark{DayOf(sentence, where), TimeOfDay(sentence.fields[0], where)};
}

// The Unix time of a time of day on or next to `mark`'s day: within half a
// day of `after` (the previous fix, or the date sentence itself).
double UnixTime(double time_of_day, const DateMark& mark, double after) {
  double time = mark.day + time_of_day;
  while (time < after - kSecondsPerDay / 2) time += kSecondsPerDay;
  while (time > after + kSecondsPerDay / 2) time -= kSecondsPerDay;
  return time;
}

// 00:00Z of "YYYY-MM-DD", or nullopt.
std::optional<double> DayOfDate(const std::string& date) {
  int year = 0;
  int month = 0;
  int day = 0;
  char dash1 = 0;
  char dash2 = 0;
  std::istringstream stream(date);
  stream >> year >> dash1 >> month >> dash2 >> day;
  if (!stream || !stream.eof() || dash1 != '-' || dash2 != '-') {
    return std::nullopt;
  }
  return UnixTimeOfDay(year, month, day);
}

}  // namespace

void NmeaOptions::Check() const {
  if (!date.empty() && !DayOfDate(date)) {
    throw ErrorAt("--nmea_date ", date, " is not a date YYYY-MM-DD");
  }
}

unsigned NmeaChecksum(std::string_view body) {
  unsigned checksum = 0;
  for (const char c : body) checksum ^= static_cast<unsigned char>(c);
  return checksum;
}

bool LooksLikeNmea(const std::filesystem::path& path) {
  std::ifstream file(path);
  for (std::string line; std::getline(file, line);) {
    if (IsBlankOrComment(line)) continue;
    const std::string text = SentenceText(line);
    return text.size() > 6 && text[5] == ',';
  }
  return false;
}

std::vector<NavRecord> ReadNmeaLog(const std::filesystem::path& path,
                                   const NmeaOptions& options,
                                   const std::optional<GeoOrigin>& origin,
                                   NavLogFrame* frame) {
  options.Check();
  std::ifstream file(path);
  if (!file) throw ErrorAt(path.string(), ": cannot open for reading");
  const std::string name = path.string();
  std::vector<Sentence> sentences;
  size_t no_sentence = 0;
  int line_number = 0;
  for (std::string line; std::getline(file, line);) {
    ++line_number;
    if (IsBlankOrComment(line)) continue;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::string text = SentenceText(line);
    const std::string where = fmt::format("{}:{}", name, line_number);
    if (text.empty()) {
      ++no_sentence;
      continue;
    }
    if (auto sentence = ParseSentence(text, line_number, where)) {
      sentences.push_back(std::move(*sentence));
    }
  }

  // The first date in the log dates the fixes before it too.
  std::optional<DateMark> mark;
  for (const Sentence& sentence : sentences) {
    mark = DateOf(sentence, fmt::format("{}:{}", name, sentence.line));
    if (mark) break;
  }
  if (!mark && !options.date.empty()) {
    mark = DateMark{*DayOfDate(options.date), 0.0, false};
  }

  NavLogFrame read_frame;
  read_frame.position_columns = "NMEA GGA";
  std::vector<NavRecord> records;
  std::optional<LocalEnu> local;
  std::optional<double> heading_deg;
  bool has_heading_sentences = false;
  for (const Sentence& sentence : sentences) {
    has_heading_sentences |= sentence.type == "HDT";
  }
  size_t no_fix = 0;
  size_t before_heading = 0;
  double previous_time = 0.0;
  int previous_line = 0;
  for (const Sentence& sentence : sentences) {
    const std::string where = fmt::format("{}:{}", name, sentence.line);
    const std::vector<std::string>& f = sentence.fields;
    if (const std::optional<DateMark> date = DateOf(sentence, where)) {
      mark = date;  // a date sentence is the authority from here on
      continue;
    }
    if (sentence.type == "HDT") {
      if (f.empty() || f[0].empty()) continue;  // no heading yet
      heading_deg = Number(f[0], "HDT heading", where);
      continue;
    }
    if (sentence.type != "GGA") continue;
    if (f.size() < 10) {
      throw ErrorAt(where, ": GGA has ", f.size(),
                    " fields after its address, expected at least 10");
    }
    if (f[5].empty() || f[5] == "0" || f[1].empty() || f[3].empty()) {
      ++no_fix;
      continue;
    }
    if (!mark) {
      throw ErrorAt(name,
                    ": no RMC or ZDA sentence gives the date of its GGA "
                    "fixes; give it with --nmea_date YYYY-MM-DD (UTC)");
    }
    if (has_heading_sentences && !heading_deg) {
      ++before_heading;
      continue;
    }
    const double time_of_day = TimeOfDay(f[0], where);
    const double lat = Degrees(f[1], f[2], "N", "S", 90.0, where);
    const double lon = Degrees(f[3], f[4], "E", "W", 180.0, where);
    const double height = Number(f[8], "GGA altitude", where);
    // Within half a day of the later of the date's own time and the
    // previous fix: fixes before the first date sentence take its day (or
    // the one before), fixes past midnight the next.
    const double anchor = std::max(
        mark->timed ? mark->day + mark->time_of_day : mark->day + time_of_day,
        records.empty() ? 0.0 : previous_time);
    const double time = UnixTime(time_of_day, *mark, anchor);
    if (!records.empty() && !(time > previous_time)) {
      throw ErrorAt(where, ": time ", TimeText(time),
                    " s is not after the previous fix (line ", previous_line,
                    ", ", TimeText(previous_time),
                    " s); the fixes must come in strictly increasing time");
    }
    if (!local) {
      read_frame.origin = origin ? *origin : AutomaticOrigin(lat, lon);
      read_frame.origin_automatic = !origin;
      local.emplace(*read_frame.origin);
    }
    NavRecord record;
    record.line = sentence.line;
    record.time_s = time;
    record.position = local->FromGeodetic(lat, lon, height);
    record.has_roll_pitch = false;
    record.has_yaw = has_heading_sentences;
    if (heading_deg) {
      record.rpy_rad(2) =
          local->YawFromHeading(*heading_deg, lat, lon, height) * M_PI / 180.0;
    }
    records.push_back(record);
    previous_time = time;
    previous_line = sentence.line;
  }
  if (records.empty()) {
    throw ErrorAt(name, ": no GGA fix (", no_fix,
                  " GGA sentences without a fix)");
  }
  if (no_fix > 0) {
    read_frame.notes.push_back(fmt::format(
        "{}: {} GGA sentences without a fix (quality 0 or no coordinates) "
        "left out",
        name, no_fix));
  }
  if (before_heading > 0) {
    read_frame.notes.push_back(
        fmt::format("{}: {} fixes before the first HDT heading left out", name,
                    before_heading));
  }
  if (no_sentence > 0) {
    read_frame.notes.push_back(fmt::format(
        "{}: {} lines without an NMEA sentence skipped", name, no_sentence));
  }
  if (frame != nullptr) *frame = read_frame;
  return records;
}

}  // namespace uw
