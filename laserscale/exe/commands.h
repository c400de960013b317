// The laserscale subcommands (docs/laserscale.md); each parses its flags,
// calls the library and reports, returning the exit code.
#pragma once

namespace uw {

int RunDetect(int argc, char** argv);
int RunLocalize(int argc, char** argv);
int RunEstimate(int argc, char** argv);
int RunApply(int argc, char** argv);
int RunSimulate(int argc, char** argv);
int RunSparseSurface(int argc, char** argv);

}  // namespace uw
