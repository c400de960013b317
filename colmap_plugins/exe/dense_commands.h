// uwcolmap dense_mesher: a dense surface on the CPU.
#pragma once

namespace uw {

int RunDenseMesher(int argc, char** argv);

}  // namespace uw
