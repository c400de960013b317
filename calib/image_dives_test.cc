#include "calib/image_dives.h"

#include <fstream>

#include <gtest/gtest.h>

#include "common/util/error_testing.h"
#include "tests/support/process.h"

namespace uw {
namespace {

TEST(ReadImageDives, EachImagesDive) {
  EXPECT_TRUE(ReadImageDives("").empty());
  const auto dir = testing::FreshTestDir("uw_image_dives_test");
  std::ofstream(dir / "dives.csv") << "dive,image_name\n2,L0.png\n1,L1.png\n";
  EXPECT_EQ(ReadImageDives((dir / "dives.csv").string()),
            (std::map<std::string, int>{{"L0.png", 2}, {"L1.png", 1}}));
}

TEST(ReadImageDives, AnImageListedTwiceOrADiveBelowOneIsRefused) {
  const auto dir = testing::FreshTestDir("uw_image_dives_test");
  std::ofstream(dir / "twice.csv") << "image_name,dive\nL0.png,1\nL0.png,2\n";
  ExpectErrorContaining([&] { ReadImageDives((dir / "twice.csv").string()); },
                        "twice.csv:3: image L0.png is listed twice");
  std::ofstream(dir / "zero.csv") << "image_name,dive\nL0.png,0\n";
  ExpectErrorContaining([&] { ReadImageDives((dir / "zero.csv").string()); },
                        "zero.csv:2");
}

}  // namespace
}  // namespace uw
