// --board, as every uwcalib command that sees a board takes it: the spec
// ParseBoard reads ("chessboard:9x6:0.025", "aprilgrid:6x6:0.088:0.3",
// "charuco:20x20:0.004:0.0032:DICT_4X4_1000").
#pragma once

#include <string>

#include "calib/board.h"
#include "common/cli/flags.h"

namespace uw {

// Binds --board to `board` (required): ParseBoard's uw::Error for a bad
// spec, as for any bad input.
CLI::Option* AddBoardFlag(CommandLine* cli, CalibrationBoard* board,
                          const std::string& help);

}  // namespace uw
