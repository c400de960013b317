// uwcolmap database_analyzer: what a COLMAP database holds, in which schema.
#pragma once

namespace uw {

int RunDatabaseAnalyzer(int argc, char** argv);

}  // namespace uw
