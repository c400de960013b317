#include "colmap_plugins/nav/nmea.h"

#include <cmath>
#include <fstream>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "common/util/error_testing.h"
#include "common/util/time_text.h"
#include "tests/support/process.h"

namespace uw {
namespace {

namespace fs = std::filesystem;

// "$" + body + "*" + its checksum.
std::string Sentence(const std::string& body) {
  unsigned checksum = 0;
  for (const char c : body) checksum ^= static_cast<unsigned char>(c);
  return fmt::format("${}*{:02X}", body, checksum);
}

class NmeaTest : public ::testing::Test {
 protected:
  void SetUp() override {
    path_ = testing::FreshTestDir("uw_nmea_test") / "log.nmea";
  }

  std::vector<NavRecord> Read(const std::string& text,
                              const NmeaOptions& options = {},
                              NavLogFrame* frame = nullptr) {
    std::ofstream(path_, std::ios::binary) << text;
    return ReadNmeaLog(path_, options, origin_, frame ? frame : &frame_);
  }

  fs::path path_;
  GeoOrigin origin_{43.1, 5.4, 0.0};
  NavLogFrame frame_;
};

const double kDay = *UnixTimeOfDay(2024, 10, 8);

// A logger's lines: a timestamp before each sentence, HDT before its GGA,
// the date from RMC; positions as WGS84 through LocalEnu, heading at the fix.
TEST_F(NmeaTest, ReadsFixesHeadingsAndTheDate) {
  const std::string text =
      "2024-10-08T12:00:00.95Z " +
      Sentence(
          "GPRMC,120000.00,A,4306.0000,N,00524.0000,E,0.5,30.0,081024,,,A") +
      "\n2024-10-08T12:00:00.97Z " + Sentence("HEHDT,30.5,T") +
      "\n2024-10-08T12:00:01.00Z " +
      Sentence(
          "GPGGA,120001.00,4306.00123456,N,00524.00234567,E,1,08,0.9,-12.5,M,"
          "48.0,M,,") +
      "\n" + Sentence("HEHDT,31.0,T") + "\n" +
      Sentence(
          "GPGGA,120002.50,4306.00223456,N,00524.00334567,E,1,08,0.9,-13.0,M,"
          "48.0,M,,") +
      "\n";
  NavLogFrame frame;
  const std::vector<NavRecord> nav = Read(text, {}, &frame);
  ASSERT_EQ(nav.size(), 2u);
  EXPECT_EQ(nav[0].time_s, kDay + 12 * 3600 + 1.0);
  EXPECT_EQ(nav[1].time_s, kDay + 12 * 3600 + 2.5);
  const LocalEnu local(origin_);
  const double lat = 43.0 + 6.00223456 / 60.0;
  const double lon = 5.0 + 24.00334567 / 60.0;
  EXPECT_LT((nav[1].position - local.FromGeodetic(lat, lon, -13.0)).norm(),
            1e-9);
  EXPECT_NEAR(nav[1].rpy_rad(2) * 180.0 / M_PI,
              local.YawFromHeading(31.0, lat, lon, -13.0), 1e-9);
  EXPECT_TRUE(nav[1].has_yaw);
  EXPECT_FALSE(nav[1].has_roll_pitch);
  EXPECT_EQ(nav[1].line, 5);
  EXPECT_EQ(frame.position_columns, "NMEA GGA");
  EXPECT_FALSE(frame.origin_automatic);
  EXPECT_TRUE(frame.notes.empty());
}

// Hemispheres: south and west are negative.
TEST_F(NmeaTest, SouthAndWestAreNegative) {
  origin_ = GeoOrigin{-33.5, -70.5, 0.0};
  const std::vector<NavRecord> nav = Read(
      Sentence("GPZDA,235959.00,31,12,2023,00,00") + "\n" +
      Sentence("GPGGA,235959.50,3330.0000,S,07030.0000,W,1,08,0.9,0.0,M,,M,,") +
      "\n");
  ASSERT_EQ(nav.size(), 1u);
  EXPECT_LT(nav[0].position.norm(), 1e-9);
  EXPECT_EQ(nav[0].time_s, *UnixTimeOfDay(2023, 12, 31) + 86399.5);
  EXPECT_FALSE(nav[0].has_yaw);  // no HDT in the log
}

// Past midnight the day turns without a new date; fixes before the first
// date sentence take its day (the day before when they are late in it).
TEST_F(NmeaTest, TheDateCarriesAcrossMidnightAndBackwards) {
  const std::string gga = ",4306.0000,N,00524.0000,E,1,08,0.9,-1.0,M,,M,,";
  const std::vector<NavRecord> nav =
      Read(Sentence("GPGGA,235958.00" + gga) + "\n" +
           Sentence("GPZDA,235959.00,07,10,2024,00,00") + "\n" +
           Sentence("GPGGA,235959.00" + gga) + "\n" +
           Sentence("GPGGA,000000.50" + gga) + "\n");
  ASSERT_EQ(nav.size(), 3u);
  const double day = *UnixTimeOfDay(2024, 10, 7);
  EXPECT_EQ(nav[0].time_s, day + 86398.0);
  EXPECT_EQ(nav[1].time_s, day + 86399.0);
  EXPECT_EQ(nav[2].time_s, day + 86400.5);
}

// Without a date sentence the date must be given.
TEST_F(NmeaTest, ALogWithoutADateNeedsOne) {
  const std::string text =
      Sentence("GPGGA,120001.00,4306.0000,N,00524.0000,E,1,08,0.9,0,M,,M,,") +
      "\n";
  ExpectErrorContaining([&] { Read(text); },
                        "no RMC or ZDA sentence gives the date of its GGA "
                        "fixes; give it with --nmea_date YYYY-MM-DD");
  NmeaOptions options;
  options.date = "2024-10-08";
  EXPECT_EQ(Read(text, options).at(0).time_s, kDay + 12 * 3600 + 1.0);
  options.date = "2024-9-8";  // one-digit month and day, as Check allows
  EXPECT_EQ(Read(text, options).at(0).time_s,
            *UnixTimeOfDay(2024, 9, 8) + 12 * 3600 + 1.0);
  options.date = "2024-02-30";
  ExpectErrorContaining([&] { Read(text, options); },
                        "--nmea_date 2024-02-30 is not a date");
}

// Fixes the receiver marks invalid, and fixes before any heading in a log
// that has headings, are left out and said.
TEST_F(NmeaTest, FixesWithoutAFixOrHeadingAreLeftOutAndSaid) {
  const std::string gga = ",4306.0000,N,00524.0000,E,";
  NavLogFrame frame;
  const std::vector<NavRecord> nav =
      Read(Sentence("GPZDA,120000.00,08,10,2024,00,00") + "\nnoise\n" +
               Sentence("GPGGA,120000.50" + gga + "1,08,0.9,0,M,,M,,") + "\n" +
               Sentence("HEHDT,10.0,T") + "\n" +
               Sentence("GPGGA,120001.00" + gga + "0,00,,,M,,M,,") + "\n" +
               Sentence("GPGGA,120002.00,,,,,0,00,,,M,,M,,") + "\n" +
               Sentence("GPGGA,120003.00" + gga + "1,08,0.9,0,M,,M,,") + "\n",
           {}, &frame);
  ASSERT_EQ(nav.size(), 1u);
  EXPECT_EQ(nav[0].line, 7);
  ASSERT_EQ(frame.notes.size(), 3u);
  EXPECT_NE(frame.notes[0].find(": 2 GGA sentences without a fix"),
            std::string::npos);
  EXPECT_NE(frame.notes[1].find(": 1 fixes before the first HDT heading"),
            std::string::npos);
  EXPECT_NE(frame.notes[2].find(": 1 lines without an NMEA sentence"),
            std::string::npos);
}

TEST_F(NmeaTest, BadSentencesNameTheirLine) {
  const std::string date = Sentence("GPZDA,120000.00,08,10,2024,00,00") + "\n";
  const std::string where = path_.string() + ":";
  const struct {
    std::string text;
    std::string message;
  } cases[] = {
      {date +
           "$GPGGA,120001.00,4306.0000,N,00524.0000,E,1,08,0.9,0,M,,M,,*00\n",
       where + "2: checksum *00 does not match the sentence (computed *"},
      {date + Sentence("GPGGA,120001.00,4306.0000,N") + "\n",
       where + "2: GGA has 3 fields after its address, expected at least 10"},
      {date +
           Sentence(
               "GPGGA,126001.00,4306.0000,N,00524.0000,E,1,08,0.9,0,M,,M,,") +
           "\n",
       where + "2: time '126001.00' is not hhmmss.ss"},
      {date +
           Sentence(
               "GPGGA,120001.00,4375.0000,N,00524.0000,E,1,08,0.9,0,M,,M,,") +
           "\n",
       where + "2: '4375.0000' is not degrees and minutes"},
      {date +
           Sentence(
               "GPGGA,120001.00,4306.0000,X,00524.0000,E,1,08,0.9,0,M,,M,,") +
           "\n",
       where + "2: hemisphere 'X' is neither N nor S"},
      {date +
           Sentence(
               "GPGGA,120001.00,4306.0000,N,00524.0000,E,1,08,0.9,abc,M,,M,,") +
           "\n",
       where + "2: GGA altitude 'abc' is not a number"},
      {date +
           Sentence(
               "GPGGA,120001.00,4306.0000,N,00524.0000,E,1,08,0.9,0,M,,M,,") +
           "\n" +
           Sentence(
               "GPGGA,120001.00,4306.0000,N,00524.0000,E,1,08,0.9,0,M,,M,,") +
           "\n",
       where + "3: time 1728388801 (2024-10-08T12:00:01Z) s is not after the "
               "previous fix (line 2"},
      {date + Sentence("GPZDA,120000.00,30,02,2024,00,00") + "\n",
       where + "2: ZDA date 2024-2-30 does not exist"},
      {date, path_.string() + ": no GGA fix (0 GGA sentences without a fix)"},
  };
  for (const auto& test : cases) {
    std::string message = "no error";
    try {
      Read(test.text);
    } catch (const Error& error) {
      message = error.what();
    }
    EXPECT_EQ(message.substr(0, test.message.size()), test.message)
        << test.text;
  }
}

TEST_F(NmeaTest, LooksLikeNmeaByItsFirstLine) {
  std::ofstream(path_) << "# a comment\n\n"
                       << Sentence("GPZDA,1,2,3,4,0,0") << "\n";
  EXPECT_TRUE(LooksLikeNmea(path_));
  std::ofstream(path_) << "time,x,y,z\n1,2,3,4\n";
  EXPECT_FALSE(LooksLikeNmea(path_));
  std::ofstream(path_) << "12:00:00 " << Sentence("GPGGA,1,2,3,4,5,6,7,8,9")
                       << "\n";
  EXPECT_TRUE(LooksLikeNmea(path_));
}

}  // namespace
}  // namespace uw
