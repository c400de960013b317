// uwcolmap model_converter / model_analyzer: same flags and output as
// COLMAP's commands of the same name, on our reader and writer.
#pragma once

namespace uw {

int RunModelConverter(int argc, char** argv);
int RunModelAnalyzer(int argc, char** argv);

}  // namespace uw
