#include "sim/worlds/option_checks.h"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "sim/world_testing.h"

namespace uw::sim {
namespace {

TEST(WorldOptionChecks, MessagesNameTheFieldAndTheRule) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(OptionName("vent", "flange_count"),
            "world options: vent.flange_count");
  EXPECT_NO_THROW(CheckPositive(1.0, "a", "b"));
  EXPECT_EQ(ErrorOf([] { CheckPositive(0.0, "a", "b"); }),
            "world options: a.b = 0: must be a positive number");
  EXPECT_EQ(ErrorOf([&] { CheckPositive(inf, "a", "b"); }),
            "world options: a.b = inf: must be a positive number");
  EXPECT_NO_THROW(CheckNonNegative(0.0, "a", "b"));
  EXPECT_EQ(ErrorOf([&] { CheckNonNegative(nan, "a", "b"); }),
            "world options: a.b = nan: must be a non-negative number");
  EXPECT_NO_THROW(CheckRange(3.0, 3.0, 4.0, "a", "b"));
  EXPECT_EQ(ErrorOf([] { CheckRange(5.0, 3.0, 4.0, "a", "b"); }),
            "world options: a.b = 5: must be in [3, 4]");
  EXPECT_NO_THROW(CheckTriangles(kMaxWorldTriangles, "a", "spacing"));
  EXPECT_EQ(ErrorOf([] { CheckTriangles(3e7, "a", "spacing"); }),
            "world options: a: about 3e+07 triangles exceed the limit of "
            "2e+07; increase a.spacing or reduce the size");
}

}  // namespace
}  // namespace uw::sim
