#include "laserscale/exe/laserscale_commands.h"

#include <gtest/gtest.h>

namespace uw {
namespace {

// STYLE.md: flags map 1:1 onto option fields, so each default is written
// once, in the options header.
TEST(LaserscaleCommands, EveryFlagWritesAFieldOfItsOptions) {
  for (const Subcommand& command : LaserscaleCommands()) {
    const std::vector<std::string> unbound = UnboundFlags(command);
    EXPECT_TRUE(unbound.empty()) << "laserscale " << command.name << ": "
                                 << ::testing::PrintToString(unbound);
  }
}

}  // namespace
}  // namespace uw
