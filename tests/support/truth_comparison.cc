#include "tests/support/truth_comparison.h"

#include <gtest/gtest.h>

#include "common/util/file.h"
#include "common/util/subprocess.h"
#include "tests/support/process.h"

namespace uw::testing {

TruthDeviation CompareWithTruth(const std::filesystem::path& uwcolmap,
                                const std::filesystem::path& model,
                                const std::filesystem::path& sim_dir,
                                const std::filesystem::path& out,
                                const std::string& alignment) {
  const auto result = RunProcess(
      Quoted(uwcolmap) + " model_comparer --input_path " + Quoted(model) +
          " --truth_dir " + Quoted(sim_dir) + " --alignment " + alignment +
          " --output_path " + Quoted(out),
      true);
  EXPECT_EQ(result.exit_code, 0) << result.output;
  const nlohmann::json json = nlohmann::json::parse(ReadFileToString(out));
  return {json["camera_rmse_m"].get<double>(),
          json["surface"]["rms_m"].get<double>(),
          json["surface"]["dome"]["sagitta_m"].get<double>(), json["segments"]};
}

void RunOrFail(const std::string& command) {
  const auto result = RunProcess(command, true);
  EXPECT_EQ(result.exit_code, 0) << command << "\n" << result.output;
}

}  // namespace uw::testing
