#include "calib/exe/uwcalib_commands.h"

#include <gtest/gtest.h>

namespace uw {
namespace {

// STYLE.md: flags map 1:1 onto option fields, so each default is written
// once, in the options header.
TEST(UwcalibCommands, EveryFlagWritesAFieldOfItsOptions) {
  for (const Subcommand& command : UwcalibCommands()) {
    const std::vector<std::string> unbound = UnboundFlags(command);
    EXPECT_TRUE(unbound.empty()) << "uwcalib " << command.name << ": "
                                 << ::testing::PrintToString(unbound);
  }
}

}  // namespace
}  // namespace uw
