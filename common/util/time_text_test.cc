#include "common/util/time_text.h"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "common/util/error_testing.h"

namespace uw {
namespace {

TEST(SecondsText, KeepsEveryDigitPositionally) {
  EXPECT_EQ(SecondsText(1728410000.25), "1728410000.25");
  EXPECT_EQ(SecondsText(1700000000.0), "1700000000");
  EXPECT_EQ(SecondsText(1728410000.123456), "1728410000.123456");
  EXPECT_EQ(SecondsText(0.0), "0");
  EXPECT_EQ(SecondsText(-0.0), "0");
  EXPECT_EQ(SecondsText(-3.5), "-3.5");
  EXPECT_EQ(SecondsText(0.1), "0.1");
  EXPECT_EQ(SecondsText(0.00001234), "0.00001234");
  EXPECT_EQ(SecondsText(5011200.0), "5011200");  // 58 days
  EXPECT_EQ(SecondsText(1e20), "100000000000000000000");
  EXPECT_EQ(SecondsText(std::numeric_limits<double>::quiet_NaN()), "nan");
  EXPECT_EQ(SecondsText(-std::numeric_limits<double>::infinity()), "-inf");
}

TEST(SecondsText, ReadsBackToTheSameDouble) {
  for (const double value : {1728410000.25, 1728410000.1, 0.3, 1.0 / 3.0,
                             123456.789e3, 2.5e-9, -98765.4321, 1e15 + 0.5}) {
    EXPECT_EQ(std::stod(SecondsText(value)), value) << SecondsText(value);
  }
}

TEST(TimeText, GivesTheCalendarTimeOfAUnixTime) {
  EXPECT_EQ(TimeText(1728410000.25), "1728410000.25 (2024-10-08T17:53:20.25Z)");
  EXPECT_EQ(TimeText(951782400.0),
            "951782400 (2000-02-29T00:00:00Z)");  // a leap day
  EXPECT_EQ(TimeText(1e8), "100000000 (1973-03-03T09:46:40Z)");
  // Seconds since a survey's start, and what cannot be a date, as they are.
  EXPECT_EQ(TimeText(12.5), "12.5");
  EXPECT_EQ(TimeText(99999999.0), "99999999");
  EXPECT_EQ(TimeText(5e9), "5000000000");
  EXPECT_EQ(TimeText(-1728410000.0), "-1728410000");
}

TEST(DurationText, ReadsAsAClockErrorIsRead) {
  EXPECT_EQ(DurationText(5022000.0), "58 d 3 h");
  EXPECT_EQ(DurationText(7205.0), "2 h 0 min 5 s");
  EXPECT_EQ(DurationText(12.5), "12.5 s");
  EXPECT_EQ(DurationText(0.0), "0 s");
  EXPECT_EQ(DurationText(-86400.25), "-1 d 0 h 0 min 0.25 s");
  EXPECT_EQ(DurationText(59.9996), "1 min");
  EXPECT_EQ(DurationText(-0.0001), "0 s");
  EXPECT_EQ(DurationText(61.118), "1 min 1.118 s");
  EXPECT_EQ(DurationText(3.5e15), "3500000000000000 s");
  EXPECT_EQ(DurationText(std::nan("")), "nan s");
}

TEST(UnixTimeOfDay, CountsDaysFromTheEpoch) {
  EXPECT_EQ(UnixTimeOfDay(1970, 1, 1), 0.0);
  EXPECT_EQ(UnixTimeOfDay(2024, 10, 8), 1728345600.0);
  EXPECT_EQ(UnixTimeOfDay(2000, 2, 29), 951782400.0);
  EXPECT_EQ(*UnixTimeOfDay(2024, 3, 1) - *UnixTimeOfDay(2024, 2, 28),
            2 * 86400.0);
  EXPECT_FALSE(UnixTimeOfDay(2023, 2, 29));
  EXPECT_FALSE(UnixTimeOfDay(2024, 2, 30));
  EXPECT_FALSE(UnixTimeOfDay(2024, 13, 1));
  EXPECT_FALSE(UnixTimeOfDay(2024, 4, 31));
  EXPECT_FALSE(UnixTimeOfDay(24, 1, 1));
}

TEST(ParseIsoTime, ReadsZonesAndFractions) {
  const double t = 1728410000.25;  // 2024-10-08T17:53:20.25Z
  EXPECT_EQ(ParseIsoTime("2024-10-08T17:53:20.25Z", "f"), t);
  EXPECT_EQ(ParseIsoTime("2024-10-08 17:53:20,25z", "f"), t);
  EXPECT_EQ(ParseIsoTime("2024-10-08T19:53:20.250000+02:00", "f"), t);
  EXPECT_EQ(ParseIsoTime("2024-10-08T23:23:20.25+0530", "f"), t);
  EXPECT_EQ(ParseIsoTime("2024-10-08T09:53:20.25-08", "f"), t);
  EXPECT_EQ(ParseIsoTime("2024-10-09T01:53:20.25+08:00", "f"), t);  // next day
  EXPECT_EQ(ParseIsoTime("2000-02-29T00:00:00Z", "f"), 951782400.0);
  EXPECT_EQ(ParseIsoTime("1970-01-01T00:00:00Z", "f"), 0.0);
  // Without a zone only when the clock's zone is given.
  EXPECT_EQ(ParseIsoTime("2024-10-08T19:53:20.25", "f", 7200), t);
}

TEST(ParseIsoTime, RefusesWhatIsNotATimeNamingTheField) {
  const auto message = [](const std::string& text) {
    return ErrorOf([&] { ParseIsoTime(text, "nav.csv:7"); });
  };
  EXPECT_NE(message("2024-10-08T17:53:20")
                .find("nav.csv:7: '2024-10-08T17:53:20' has no time zone"),
            std::string::npos);
  EXPECT_NE(message("2024-02-30T00:00:00Z").find("no such day"),
            std::string::npos);
  EXPECT_NE(message("2023-02-29T00:00:00Z").find("no such day"),
            std::string::npos);
  EXPECT_NE(message("2024-10-08T24:00:00Z").find("no such time of day"),
            std::string::npos);
  EXPECT_NE(message("2024-10-08T17:53Z").find("Thh:mm:ss"), std::string::npos);
  EXPECT_NE(message("2024-10-08T17:53:20.Z").find("digits after"),
            std::string::npos);
  for (const char* text :
       {"2024-10-08T17:53:20Zx", "2024-10-08T17:53:20+2",
        "2024-10-08T17:53:20+15:00", "2024-10-08T17:53:20+02:60",
        "2024-10-08T17:53:20 UTC"}) {
    EXPECT_NE(message(text).find("expected the zone"), std::string::npos)
        << text;
  }
  EXPECT_NE(message("24-10-08T17:53:20Z").find("YYYY-MM-DD"),
            std::string::npos);
}

TEST(ParseTimeField, TakesSecondsOrIsoTimes) {
  EXPECT_EQ(ParseTimeField("1728410000.25", "f"), 1728410000.25);
  EXPECT_EQ(ParseTimeField(" 12.5 ", "f"), 12.5);
  EXPECT_EQ(ParseTimeField("2024-10-08T17:53:20.25Z", "f"), 1728410000.25);
  EXPECT_THROW(ParseTimeField("12:30", "f"), Error);
  EXPECT_THROW(ParseTimeField("", "f"), Error);
  EXPECT_THROW(ParseTimeField("2024-10-08", "f"), Error);
}

TEST(ParseZoneOffset, ReadsOffsetsEastOfUtc) {
  EXPECT_EQ(ParseZoneOffset("Z", "f"), 0);
  EXPECT_EQ(ParseZoneOffset("+02:00", "f"), 7200);
  EXPECT_EQ(ParseZoneOffset("-08:00", "f"), -28800);
  EXPECT_EQ(ParseZoneOffset("+0530", "f"), 19800);
  EXPECT_EQ(ParseZoneOffset("-03", "f"), -10800);
  EXPECT_EQ(ZoneOffsetText(-19800), "-05:30");
  EXPECT_EQ(ZoneOffsetText(0), "Z");
  EXPECT_THROW(ParseZoneOffset("02:00", "f"), Error);
  EXPECT_THROW(ParseZoneOffset("+2", "f"), Error);
  EXPECT_THROW(ParseZoneOffset("", "f"), Error);
}

TEST(IsoTimeText, WritesWhatParseIsoTimeReadsBack) {
  EXPECT_EQ(IsoTimeText(1728410000.25, 7200, 3),
            "2024-10-08T19:53:20.250+02:00");
  EXPECT_EQ(IsoTimeText(1728410000.25, 0, 0), "2024-10-08T17:53:20Z");
  EXPECT_EQ(IsoTimeText(1728410000.9999996, -19800, 6),
            "2024-10-08T12:23:21.000000-05:30");  // rounding carries
  EXPECT_EQ(IsoTimeText(951868799.5, 0, 1), "2000-02-29T23:59:59.5Z");
  for (const double t : {1728410000.123456, 951782400.0, 1.5e9 + 0.000001}) {
    for (const int zone : {0, 7200, -28800, 19800}) {
      EXPECT_NEAR(ParseIsoTime(IsoTimeText(t, zone, 6), "f"), t, 5e-7);
    }
  }
  EXPECT_THROW(IsoTimeText(1e12, 0, 3), Error);
  EXPECT_THROW(IsoTimeText(0.0, 0, 10), Error);
}

}  // namespace
}  // namespace uw
