#include "sim/exe/uwsim_commands.h"

#include <gtest/gtest.h>

namespace uw::sim {
namespace {

// STYLE.md: flags map 1:1 onto option fields, so each default is written
// once, in the options header.
TEST(UwsimCommands, EveryFlagWritesAFieldOfItsOptions) {
  ASSERT_EQ(UwsimCommands().size(), 3u);
  for (const Subcommand& command : UwsimCommands()) {
    const std::vector<std::string> unbound = UnboundFlags(command);
    EXPECT_TRUE(unbound.empty()) << "uwsim " << command.name << ": "
                                 << ::testing::PrintToString(unbound);
  }
}

}  // namespace
}  // namespace uw::sim
