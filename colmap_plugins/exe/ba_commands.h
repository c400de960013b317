// uwcolmap bundle_adjuster and lcurve: navigation-fused bundle adjustment.
#pragma once

namespace uw {

int RunBundleAdjuster(int argc, char** argv);
int RunLCurve(int argc, char** argv);

}  // namespace uw
