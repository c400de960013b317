// The uwcalib subcommands (docs/uwcalib.md); each parses its flags, calls
// the library and reports, returning the exit code.
#pragma once

namespace uw {

int RunCalibDetect(int argc, char** argv);
int RunCalibrate(int argc, char** argv);
int RunCalibExport(int argc, char** argv);
int RunCalibLasers(int argc, char** argv);
int RunLasersFromMission(int argc, char** argv);

}  // namespace uw
