#include "calib/exe/board_flag.h"

namespace uw {

CLI::Option* AddBoardFlag(CommandLine* cli, CalibrationBoard* board,
                          const std::string& help) {
  return cli
      ->Add<CalibrationBoard>(
          "--board", board, help, ParseBoard,
          // A board without corners is no spec: the flag has no default.
          [](const CalibrationBoard& value) {
            return value.NumCorners() > 0 ? value.ToString() : std::string();
          })
      ->required();
}

}  // namespace uw
