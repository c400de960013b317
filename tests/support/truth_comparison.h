// A model against uwsim's truth through `uwcolmap model_comparer`, for the
// integration tests of the navigation-fused adjustment.
#pragma once

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

namespace uw::testing {

struct TruthDeviation {
  double camera_rmse_m = 0.0;
  double surface_rms_m = 0.0;
  double sagitta_m = 0.0;   // of the surface's deviation, ends vs middle
  nlohmann::json segments;  // compare.json's per-segment scales
};

// Runs `uwcolmap model_comparer --truth_dir sim_dir --alignment ALIGNMENT`
// on `model`, writes compare.json to `out` and returns its figures; a
// failure of the command fails the test.
TruthDeviation CompareWithTruth(const std::filesystem::path& uwcolmap,
                                const std::filesystem::path& model,
                                const std::filesystem::path& sim_dir,
                                const std::filesystem::path& out,
                                const std::string& alignment);

// Runs a shell command; a non-zero exit fails the test with its output.
void RunOrFail(const std::string& command);

}  // namespace uw::testing
