#include "common/util/number_text.h"

#include <gtest/gtest.h>

namespace uw {
namespace {

TEST(FiniteDoubles, TakesCommaSeparatedNumbers) {
  EXPECT_EQ(FiniteDoubles("43.1, 5.4,-100"),
            (std::vector<double>{43.1, 5.4, -100.0}));
  EXPECT_EQ(FiniteDoubles("7"), std::vector<double>{7.0});
  EXPECT_FALSE(FiniteDoubles(""));
  EXPECT_FALSE(FiniteDoubles("1,,2"));
  EXPECT_FALSE(FiniteDoubles("1,2,"));
  EXPECT_FALSE(FiniteDoubles("1;2"));
  EXPECT_FALSE(FiniteDoubles("1,nan"));
}

TEST(FiniteDouble, TakesOnlyWholeFiniteNumbers) {
  EXPECT_EQ(FiniteDouble("12.5"), 12.5);
  EXPECT_EQ(FiniteDouble("-3e2"), -300.0);
  EXPECT_EQ(FiniteDouble("4306.00123456"), 4306.00123456);
  for (const char* bad :
       {"", " 1", "1 ", "12.5x", "x", "nan", "inf", "1e999", "--1", "1,5"}) {
    EXPECT_FALSE(FiniteDouble(bad)) << bad;
  }
}

}  // namespace
}  // namespace uw
