#include "common/util/median.h"

#include <cmath>

#include <gtest/gtest.h>

namespace uw {
namespace {

TEST(Median, IsTheUpperMedianAndNanForNone) {
  EXPECT_EQ(Median({3.0, 1.0, 2.0}), 2.0);
  EXPECT_EQ(Median({4.0, 1.0, 3.0, 2.0}), 3.0);
  EXPECT_EQ(Median({-1.0}), -1.0);
  EXPECT_TRUE(std::isnan(Median({})));
}

}  // namespace
}  // namespace uw
