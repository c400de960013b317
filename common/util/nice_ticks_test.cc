#include "common/util/nice_ticks.h"

#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "common/util/error.h"

namespace uw {
namespace {

TEST(NiceTicks, AreMultiplesOfOneTwoOrFiveTimesAPowerOfTen) {
  EXPECT_EQ(NiceStep(0.3), 0.5);
  EXPECT_EQ(NiceStep(1.0), 1.0);
  EXPECT_EQ(NiceStep(1.2), 2.0);
  EXPECT_EQ(NiceStep(7.0), 10.0);
  EXPECT_DOUBLE_EQ(NiceStep(0.0012), 0.002);

  // The ranges the report's plots had raw ticks for (-0.5075 ... 2.28375).
  const Ticks ticks = NiceTicks(-0.5075, 2.28375, 6);
  EXPECT_EQ(ticks.step, 0.5);
  ASSERT_EQ(ticks.values.size(), 6u);
  EXPECT_DOUBLE_EQ(ticks.values.front(), -0.5);
  EXPECT_DOUBLE_EQ(ticks.values.back(), 2.0);
  std::vector<std::string> labels;
  for (const double value : ticks.values) {
    labels.push_back(TickLabel(value, ticks.step));
  }
  EXPECT_EQ(labels, (std::vector<std::string>{"-0.5", "0.0", "0.5", "1.0",
                                              "1.5", "2.0"}));
  // An image index from -1.085 to 2.9575: whole images.
  const Ticks images = NiceTicks(-1.085, 2.9575, 6);
  EXPECT_EQ(images.step, 1.0);
  EXPECT_EQ(TickLabel(images.values.front(), images.step), "-1");
  // Never more than asked, even where the first step would give one more.
  for (const auto& [lo, hi] :
       {std::pair{0.0, 10.0}, std::pair{-3.3, 7.1}, std::pair{1e6, 1e6 + 3.0},
        std::pair{-1e-5, 0.0}}) {
    const Ticks t = NiceTicks(lo, hi, 5);
    EXPECT_LE(t.values.size(), 5u) << lo << " " << hi;
    EXPECT_GE(t.values.size(), 2u) << lo << " " << hi;
    EXPECT_GE(t.values.front(), lo - 1e-9 * t.step);
    EXPECT_LE(t.values.back(), hi + 1e-9 * t.step);
  }
  // A span of a few ulps has its ends as ticks (it used to loop forever),
  // and so has one a double cannot hold.
  EXPECT_EQ(NiceTicks(0.3, 0.1 + 0.2 + 1e-16, 6).values.size(), 2u);
  EXPECT_EQ(NiceTicks(-1e308, 1e308, 6).values.size(), 2u);
  EXPECT_EQ(TickLabel(-1e-17, 0.1), "0.0");
  EXPECT_EQ(TickLabel(1000000.0, 1.0), "1000000");
  EXPECT_THROW(NiceTicks(1.0, 1.0, 5), Error);
  EXPECT_THROW(NiceTicks(0.0, 1.0, 1), Error);
}

}  // namespace
}  // namespace uw
