#include "common/util/figure.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "common/util/error_testing.h"
#include "common/util/file.h"
#include "tests/support/svg_ticks.h"

namespace uw {
namespace {

namespace fs = std::filesystem;

bool IsPng(const std::string& bytes) {
  return bytes.rfind("\x89PNG\r\n\x1a\n", 0) == 0;
}

// The ranges that gave raw-float ticks before (-0.5075, 2.28375; 0.0371842)
// get labels at multiples of 1, 2 or 5 x 10^k with the decimals they need,
// as text in the SVG.
TEST(Figure, TicksAreNiceMultiplesWrittenAsText) {
  Figure narrow("narrow", "x (m)", "y (m)");
  narrow.Line({0.0371842, 0.0385}, {2.28375, -0.5075}, Figure::Colour(0),
              "line");
  Figure wide("wide", "x", "y");
  wide.Points({-3e5, 2e5}, {1.00013, 1.00031}, Figure::Colour(1));
  Figure decades("decades", "x", "y");
  decades.Line({1e-3, 1e2}, {1.0, 2.0}, Figure::Colour(2));
  decades.LogX();
  // A northing in UTM and a millionth: matplotlib would put "1e6" or
  // "1e-6" apart from the numbers.
  Figure extremes("extremes", "easting", "northing");
  extremes.Points({3.1e-6, 3.7e-6}, {5312345.0, 5312987.0}, Figure::Colour(3));
  const std::vector<FigureFiles> drawn =
      DrawFigures({narrow, wide, decades, extremes});
  ASSERT_EQ(drawn.size(), 4u);
  for (const FigureFiles& files : drawn) {
    EXPECT_TRUE(IsPng(files.png));
    for (const char axis : {'x', 'y'}) {
      const std::vector<std::string> labels = SvgTickLabels(files.svg, axis);
      EXPECT_EQ(TickProblem(labels), "") << axis;
    }
  }
  EXPECT_NE(drawn[0].svg.find(">x (m)</text>"), std::string::npos);
  // No offset or power of ten apart from the labels: each label is the
  // value itself.
  const std::vector<std::string> y = SvgTickLabels(drawn[1].svg, 'y');
  ASSERT_FALSE(y.empty());
  EXPECT_NEAR(std::stod(y.front()), 1.0001, 1e-4);
  const std::vector<std::string> x = SvgTickLabels(drawn[2].svg, 'x');
  ASSERT_FALSE(x.empty());
  EXPECT_NEAR(std::stod(x.front()), 1e-3, 1e-12);
  const std::vector<std::string> northing = SvgTickLabels(drawn[3].svg, 'y');
  const std::vector<std::string> easting = SvgTickLabels(drawn[3].svg, 'x');
  ASSERT_FALSE(northing.empty());
  ASSERT_FALSE(easting.empty());
  EXPECT_NEAR(std::stod(northing.front()), 5.3123e6, 1e3);
  EXPECT_NEAR(std::stod(easting.back()), 3.7e-6, 2e-7);
}

// Per-image axes are labelled with the images' names, thinned evenly to at
// most 60.
TEST(Figure, AnItemAxisNamesTheItems) {
  std::vector<std::string> names;
  std::vector<double> x, y;
  for (int i = 0; i < 130; ++i) {
    names.push_back("dive 1&2/<img_" + std::to_string(1000 + i) + ">.png");
    x.push_back(i);
    y.push_back(0.01 * i);
  }
  Figure figure("per image", "image", "|e| (m)");
  figure.Bars(x, y, 0.7, Figure::Colour(0), "|e|");
  figure.ItemAxis(names);
  const std::vector<std::string> labels =
      SvgTickLabels(DrawFigures({figure}).at(0).svg, 'x');
  ASSERT_GE(labels.size(), 30u);
  EXPECT_LE(labels.size(), 60u);
  EXPECT_EQ(labels[0], names[0]);
  EXPECT_EQ(labels[1], names[3]);
}

// Not-a-number values (an image without a result) are left out, not drawn
// and not an error.
TEST(Figure, LeavesOutNonFiniteValues) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  Figure figure("gaps", "x", "y");
  figure.Points({0.0, 1.0, 2.0}, {1.0, nan, 3.0}, Figure::Colour(0));
  figure.ErrorBars({0.0, 1.0}, {0.5, nan}, {1.5, 2.0}, Figure::Colour(1));
  figure.HorizontalLine(nan, Figure::Colour(2));
  EXPECT_EQ(TickProblem(SvgTickLabels(DrawFigures({figure}).at(0).svg, 'y')),
            "");
}

// PNG and SVG appear together; the same figure gives the same bytes (no
// date, fixed ids), so reports can be compared run to run.
TEST(Figure, WritesPngAndSvgTogetherAndReproducibly) {
  const fs::path dir = fs::path(testing::TempDir()) / "figure_write";
  fs::remove_all(dir);
  Figure figure("h", "scale s", "iterations");
  figure.Histogram({1.0, 1.01, 1.02, 1.02, 1.03}, 5, Figure::Colour(0));
  figure.VerticalLine(1.02, Figure::Colour(3), "median");
  WriteFigures({figure, figure}, {dir / "a.png", dir / "sub" / "b.png"});
  EXPECT_TRUE(IsPng(ReadFileToString(dir / "a.png")));
  EXPECT_EQ(ReadFileToString(dir / "a.svg"),
            ReadFileToString(dir / "sub" / "b.svg"));
  ExpectErrorContaining([&] { WriteFigures({figure}, {}); },
                        "1 figures for 0 paths");
}

TEST(TickProblem, NamesRawFloatsAndUnevenTicks) {
  EXPECT_EQ(TickProblem({"0.0", "0.5", "1.0", "1.5"}), "");
  EXPECT_EQ(TickProblem({"-200000", "0", "200000"}), "");
  EXPECT_EQ(TickProblem({"0.001", "0.1", "10"}), "");
  EXPECT_EQ(TickProblem({"1", "10"}), "");
  EXPECT_EQ(TickProblem({"1", "2", "5", "10", "20"}), "");
  EXPECT_NE(TickProblem({"1", "3", "10"}), "");
  EXPECT_NE(TickProblem({"-0.5075", "0.19", "0.8875"}), "");
  EXPECT_NE(TickProblem({"0.4875", "1.0125", "1.5375"}), "");
  EXPECT_NE(TickProblem({"0.0", "0.25", "0.50"}), "");   // 2.5 x 10^k
  EXPECT_NE(TickProblem({"1.00", "1.50", "2.00"}), "");  // decimals
  EXPECT_NE(TickProblem({"1e+06", "2e+06"}), "");
  EXPECT_NE(TickProblem({"img_1.png", "img_2.png"}), "");
  EXPECT_NE(TickProblem({"1"}), "");
}

}  // namespace
}  // namespace uw
