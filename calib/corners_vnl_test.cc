#include "calib/corners_vnl.h"

#include <gtest/gtest.h>

#include "common/util/error.h"

namespace uw {
namespace {

// Two images of a 2x2 board as mrgingham writes them, and one without.
const char* kMrgingham =
    "## generated with mrgingham --gridn 2 *.jpg\n"
    "# filename x y level\n"
    "a.jpg 10.5 20.25 0\n"
    "a.jpg 30.000000 20.000000 1\n"
    "a.jpg 10 40 -\n"
    "a.jpg 30 40 2\n"
    "b.jpg - - -\n"
    "c.jpg 1 2 0\n"
    "c.jpg 3 4 0\n"
    "c.jpg 5 6 0\n"
    "c.jpg 7 8 0\n";

TEST(ParseCornersVnl, ReadsMrginghamsLevelsAsMrcalDoes) {
  const CornersVnl file = ParseCornersVnl(kMrgingham, "corners.vnl", 4);
  EXPECT_EQ(file.column, CornerWeightColumn::kLevel);
  ASSERT_EQ(file.observations.size(), 3u);
  const BoardObservation& a = file.observations[0];
  EXPECT_EQ(a.image, "a.jpg");
  ASSERT_EQ(a.pixels.size(), 4u);
  EXPECT_EQ(a.pixels[0], Eigen::Vector2d(10.5, 20.25));
  // weight = 2^-level; '-' marks a missing corner.
  EXPECT_EQ(a.weights, (std::vector<double>{1.0, 0.5, -1.0, 0.25}));
  EXPECT_EQ(a.NumFoundCorners(), 3);
  EXPECT_FALSE(file.observations[1].Found());
  EXPECT_EQ(file.observations[2].NumFoundCorners(), 4);
  // The board's size is taken from the first board when not given.
  EXPECT_EQ(ParseCornersVnl(kMrgingham, "x", 0).observations.size(), 3u);
}

TEST(FormatCornersVnl, RoundTripsInBothColumns) {
  const CornersVnl file = ParseCornersVnl(kMrgingham, "corners.vnl", 4);
  for (const CornerWeightColumn column :
       {CornerWeightColumn::kLevel, CornerWeightColumn::kWeight}) {
    const std::string text =
        FormatCornersVnl(file.observations, column, {"uwcalib detect"});
    EXPECT_EQ(text.rfind("## uwcalib detect\n", 0), 0u) << text;
    const CornersVnl again = ParseCornersVnl(text, "again", 4);
    EXPECT_EQ(again.column, column);
    ASSERT_EQ(again.observations.size(), file.observations.size());
    for (size_t i = 0; i < file.observations.size(); ++i) {
      EXPECT_EQ(again.observations[i].image, file.observations[i].image);
      EXPECT_EQ(again.observations[i].pixels, file.observations[i].pixels);
      EXPECT_EQ(again.observations[i].weights, file.observations[i].weights);
    }
  }
  // mrgingham's own layout: "%s %f %f %d".
  const std::string text =
      FormatCornersVnl(file.observations, CornerWeightColumn::kLevel, {});
  EXPECT_NE(text.find("a.jpg 30.000000 20.000000 1\n"), std::string::npos);
  EXPECT_NE(text.find("a.jpg - - -\n"), std::string::npos);
  EXPECT_NE(text.find("b.jpg - - -\n"), std::string::npos);
}

TEST(ParseCornersVnl, WeightColumnFromTheLegend) {
  const CornersVnl file = ParseCornersVnl(
      "# filename x y weight\nz.png 1 2 0.3\nz.png 3 4 0\nz.png 5 6 -\n"
      "z.png -1 8 1\n",
      "w.vnl", 4);
  EXPECT_EQ(file.column, CornerWeightColumn::kWeight);
  EXPECT_EQ(file.observations[0].weights,
            (std::vector<double>{0.3, -1.0, -1.0, -1.0}));
}

void ExpectError(const std::string& text, const std::string& expected) {
  try {
    ParseCornersVnl(text, "bad.vnl", 4);
    ADD_FAILURE() << "accepted:\n" << text;
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find(expected), std::string::npos)
        << error.what();
  }
}

TEST(ParseCornersVnl, RejectsMalformedFilesNamingLineAndImage) {
  ExpectError("a.jpg 1 2 0\na.jpg 1 2 0\n",
              "bad.vnl:1: image a.jpg has 2 rows");
  ExpectError("a.jpg 1 2\nb.jpg 1 2 0 0\n",
              "bad.vnl:2: expected 'filename x y");
  ExpectError("a.jpg 1 nan 0\n", "bad.vnl:1: image a.jpg: 'nan'");
  ExpectError("a.jpg 1 x1 0\n", "bad.vnl:1: image a.jpg: 'x1'");
  ExpectError("a.jpg 1 2 0.5\n", "bad.vnl:1: image a.jpg: level '0.5'");
  ExpectError("a.jpg - - -\nb.jpg - - -\na.jpg - - -\n",
              "bad.vnl:3: image a.jpg appears again (first at line 1)");
  ExpectError("# filename x y sigma\n", "fourth column must be 'level' or");
}

TEST(FormatCornersVnl, RejectsWhatMrcalCouldNotRead) {
  BoardObservation observation{"a b.jpg", {{1, 2}}, {1.0}};
  EXPECT_THROW(FormatCornersVnl({observation}, CornerWeightColumn::kLevel, {}),
               Error);
  observation.image = "a.jpg";
  observation.weights = {0.3};
  EXPECT_THROW(FormatCornersVnl({observation}, CornerWeightColumn::kLevel, {}),
               Error);
  EXPECT_NO_THROW(
      FormatCornersVnl({observation}, CornerWeightColumn::kWeight, {}));
  observation.pixels = {{1, NAN}};
  EXPECT_THROW(FormatCornersVnl({observation}, CornerWeightColumn::kWeight, {}),
               Error);
}

}  // namespace
}  // namespace uw
