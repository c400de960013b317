#include "tests/support/multi_dive.h"

#include <cmath>
#include <limits>

#include <nlohmann/json.hpp>

#include "colmap_plugins/nav/nav_csv.h"
#include "common/util/error.h"
#include "common/util/file.h"
#include "common/util/subprocess.h"
#include "tests/support/process.h"
#include "tests/support/uwsim_survey.h"

namespace uw::testing {

namespace fs = std::filesystem;

MultiDiveChain RunMultiDiveChain(const fs::path& bin_dir,
                                 const fs::path& config, const fs::path& dir,
                                 int num_points) {
  const std::string uwsim = Quoted(bin_dir / "uwsim");
  const auto generate =
      RunProcess(uwsim + " generate --survey multi_dive --out " +
                     Quoted(dir / "sim") + " --config " + Quoted(config),
                 true);
  if (generate.exit_code != 0) {
    throw ErrorAt("uwsim generate failed: ", generate.output);
  }
  const auto observe = RunProcess(
      uwsim + " observe --sim " + Quoted(dir / "sim") + " --output_path " +
          Quoted(dir / "tracks") + " --pixel_sigma 0.5 --num_points " +
          std::to_string(num_points) + " --init perturbed",
      true);
  if (observe.exit_code != 0) {
    throw ErrorAt("uwsim observe failed: ", observe.output);
  }

  MultiDiveChain chain;
  const nlohmann::json sim =
      nlohmann::json::parse(ReadFileToString(dir / "sim/truth/sim.json"));
  const auto& biases = sim.at("truth").at("dive_biases_m");
  const auto bias_of = [&](int dive) {
    const auto& bias = biases.at(dive - 1);
    return Eigen::Vector3d(bias[0].get<double>(), bias[1].get<double>(),
                           bias[2].get<double>());
  };
  const std::vector<NavRecord> logged =
      ReadNavigationCsv(dir / "sim" / "nav.csv");
  const std::vector<NavRecord> truth =
      ReadNavigationCsv(dir / "sim" / "truth" / "nav.csv");
  if (logged.size() != truth.size()) {
    throw ErrorAt("uwsim wrote ", logged.size(), " navigation rows and ",
                  truth.size(), " true ones");
  }
  double squared = 0.0;
  for (size_t i = 0; i < logged.size(); ++i) {
    squared +=
        (logged[i].position - bias_of(logged[i].dive) - truth[i].position)
            .squaredNorm();
  }
  chain.realised_nav_m = std::sqrt(squared / (3.0 * logged.size()));

  const auto adjusted = RunProcess(
      Quoted(bin_dir / "uwcolmap") + " bundle_adjuster --input_path " +
          Quoted(dir / "tracks") + " --output_path " + Quoted(dir / "ba") +
          " --nav " + Quoted(dir / "sim" / "nav.csv") +
          SurveyMountFlags(dir / "sim") +
          " --BundleAdjustment.refine_focal_length 0"
          " --BundleAdjustment.refine_extra_params 0 --Dive.offsets 1",
      true);
  chain.exit_code = adjusted.exit_code;
  chain.output = adjusted.output;
  if (adjusted.exit_code != 0) return chain;
  const nlohmann::json report =
      nlohmann::json::parse(ReadFileToString(dir / "ba" / "ba_report.json"));
  chain.termination = report.at("termination").get<std::string>();
  chain.iterations = report.at("iterations").get<int>();
  chain.nav_sigma_m =
      report.at("run").at("noise_levels").at("nav_sigma_m").get<double>();
  chain.warnings = report.at("warnings").get<std::vector<std::string>>();
  const int reference = report.at("dive_offsets").at(0).at("dive").get<int>();
  for (const nlohmann::json& offset : report.at("dive_offsets")) {
    const int dive = offset.at("dive").get<int>();
    if (dive == reference) continue;
    const Eigen::Vector3d expected = bias_of(reference) - bias_of(dive);
    Eigen::Vector3d error, sigma;
    for (int k = 0; k < 3; ++k) {
      error(k) = offset.at("offset_m")[k].get<double>() - expected(k);
      sigma(k) = offset.contains("sigma_m")
                     ? offset["sigma_m"][k].get<double>()
                     : std::numeric_limits<double>::quiet_NaN();
    }
    chain.dives.push_back(dive);
    chain.offset_errors.push_back(error);
    chain.offset_sigmas.push_back(sigma);
  }
  return chain;
}

}  // namespace uw::testing
