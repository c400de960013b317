// uwcolmap model_aligner / model_comparer: a model moved onto navigation or
// reference positions by a similarity, and a model measured against another
// model or uwsim's truth (colmap_plugins/align).
#pragma once

namespace uw {

int RunModelAligner(int argc, char** argv);
int RunModelComparer(int argc, char** argv);

}  // namespace uw
