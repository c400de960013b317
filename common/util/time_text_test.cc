#include "common/util/time_text.h"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace uw
