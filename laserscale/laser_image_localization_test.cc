#include "laserscale/laser_image_localization.h"

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "common/util/error.h"
#include "common/util/error_testing.h"

namespace uw {
namespace {

namespace fs = std::filesystem;

TEST(ReadLaserImageList, OneNamePerLineWithoutTrailingBlanks) {
  const fs::path path = fs::path(::testing::TempDir()) / "laser_list.txt";
  std::ofstream(path) << "L00001.png \r\n\n  \nL00002.png\n";
  EXPECT_EQ(ReadLaserImageList(path.string()),
            (std::vector<std::string>{"L00001.png", "L00002.png"}));
}

TEST(ReadLaserImageList, AnEmptyOrMissingListIsAnError) {
  const fs::path path = fs::path(::testing::TempDir()) / "empty_list.txt";
  std::ofstream(path) << "\n \r\n";
  EXPECT_EQ(ErrorOf([&] { ReadLaserImageList(path.string()); }),
            path.string() + ": the image list is empty");
  const std::string missing =
      (fs::path(::testing::TempDir()) / "no_such_list.txt").string();
  EXPECT_EQ(ErrorOf([&] { ReadLaserImageList(missing); }),
            missing + ": cannot open the image list");
}

}  // namespace
}  // namespace uw
