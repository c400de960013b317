#include "sim/worlds/rocks.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "sim/world.h"
#include "sim/world_testing.h"

namespace uw::sim {
namespace {

TEST(WorldTest, RocksOnlyRaiseTheFloor) {
  WorldOptions options = SmallOptions();
  options.seafloor.length_m = 8.0;
  options.seafloor.width_m = 6.0;
  options.seafloor.rocks.count = 0;
  const World bare = MakeWorld(WorldKind::kSeafloor, options, 3);
  options.seafloor.rocks.count = 12;
  const World rocky = MakeWorld(WorldKind::kSeafloor, options, 3);
  ASSERT_EQ(bare.mesh.vertices.size(), rocky.mesh.vertices.size());
  int raised = 0;
  double highest = 0.0;
  for (size_t i = 0; i < bare.mesh.vertices.size(); ++i) {
    const double rise = rocky.mesh.vertices[i].z() - bare.mesh.vertices[i].z();
    ASSERT_GE(rise, 0.0);
    raised += rise > 0.0;
    highest = std::max(highest, rise);
  }
  EXPECT_GT(raised, 100);
  EXPECT_GT(highest, 0.1);  // the smallest rock is 0.2 m across
  EXPECT_LT(highest, 1.0);  // and the largest 1 m
}

// The breakwater's rocks lie on the seafloor around the mound and the
// canyon's on its floor: every vertex a rock raises was low before.
TEST(WorldTest, BreakwaterAndCanyonRocksLieOnTheFloor) {
  for (const WorldKind kind : {WorldKind::kBreakwater, WorldKind::kCanyon}) {
    WorldOptions options = SmallOptions();
    RockOptions& rocks = kind == WorldKind::kBreakwater
                             ? options.breakwater.rocks
                             : options.canyon.rocks;
    rocks.count = 0;
    const World bare = MakeWorld(kind, options, 3);
    rocks.count = 12;
    const World rocky = MakeWorld(kind, options, 3);
    ASSERT_EQ(bare.mesh.vertices.size(), rocky.mesh.vertices.size());
    int raised = 0;
    double highest_ground = -std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < bare.mesh.vertices.size(); ++i) {
      const double rise =
          rocky.mesh.vertices[i].z() - bare.mesh.vertices[i].z();
      ASSERT_GE(rise, 0.0) << bare.name;
      if (rise > 0.0) {
        ++raised;
        highest_ground = std::max(highest_ground, bare.mesh.vertices[i].z());
      }
    }
    EXPECT_GT(raised, 50) << bare.name;
    // The mound is 3 m high and the canyon's walls ~4 m; the floors' relief
    // is a few dm.
    EXPECT_LT(highest_ground, 1.0) << bare.name;
  }
}

// On a flat grid: rocks stand on the ground, no higher than a diameter, and
// never where `allowed` refuses them.
TEST(Rocks, RiseFromTheGroundWhereAllowed) {
  HeightGrid grid(-5.0, -5.0, 10.0, 10.0, 0.05);
  RockOptions options;
  options.count = 30;
  SplitMix64Stream random(4);
  const auto ground = [](double, double) { return 0.0; };
  AddRocks(options, ground, OutsideDisc(2.0), random, &grid);
  int raised = 0;
  for (int j = 0; j < grid.ny; ++j) {
    for (int i = 0; i < grid.nx; ++i) {
      const double z = grid.at(i, j);
      ASSERT_GE(z, 0.0);
      EXPECT_LT(z, options.max_diameter_m);
      if (z > 0.0) {
        ++raised;
        EXPECT_GT(std::hypot(grid.x(i), grid.y(j)), 2.0);
      }
    }
  }
  EXPECT_GT(raised, 200);

  HeightGrid nowhere(-5.0, -5.0, 10.0, 10.0, 0.05);
  AddRocks(
      options, ground, [](const Eigen::Vector2d&, double) { return false; },
      random, &nowhere);
  EXPECT_EQ(*std::max_element(nowhere.z.begin(), nowhere.z.end()), 0.0);
}

TEST(Rocks, OptionsAreChecked) {
  EXPECT_NO_THROW(RockOptions().Check("x.rocks"));
  RockOptions options;
  options.min_diameter_m = 2.0;
  EXPECT_EQ(ErrorOf([&] { options.Check("x.rocks"); }),
            "world options: x.rocks.min_diameter_m = 2: exceeds "
            "max_diameter_m = 1");
  options = RockOptions();
  options.count = -1;
  EXPECT_EQ(ErrorOf([&] { options.Check("x.rocks"); }),
            "world options: x.rocks.count = -1: must be in [0, 100000]");
}

}  // namespace
}  // namespace uw::sim
