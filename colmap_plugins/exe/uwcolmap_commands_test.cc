#include "colmap_plugins/exe/uwcolmap_commands.h"

#include <gtest/gtest.h>

namespace uw {
namespace {

// STYLE.md: flags map 1:1 onto option fields, so each default is written
// once, in the options header.
TEST(UwcolmapCommands, EveryFlagWritesAFieldOfItsOptions) {
  for (const Subcommand& command : UwcolmapCommands()) {
    const std::vector<std::string> unbound = UnboundFlags(command);
    EXPECT_TRUE(unbound.empty()) << "uwcolmap " << command.name << ": "
                                 << ::testing::PrintToString(unbound);
  }
}

}  // namespace
}  // namespace uw
