// uwcolmap pose_prior_importer: navigation priors into a COLMAP database.
#pragma once

namespace uw {

int RunPosePriorImporter(int argc, char** argv);

}  // namespace uw
