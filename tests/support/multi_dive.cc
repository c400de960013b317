#include "tests/support/multi_dive.h"

#include <cmath>
#include <limits>
#include <set>
#include <string>

#include <nlohmann/json.hpp>

#include "colmap_plugins/align/similarity_with_offsets.h"
#include "colmap_plugins/nav/nav_csv.h"
#include "colmap_plugins/scene/model_io.h"
#include "common/util/error.h"
#include "common/util/file.h"
#include "common/util/subprocess.h"
#include "tests/support/process.h"
#include "tests/support/uwsim_survey.h"

namespace uw::testing {

namespace fs = std::filesystem;

namespace {

// MultiDiveChain::ideal_offset_errors' fit, over the images of `model`.
SimilarityWithOffsets IdealOffsets(const std::vector<NavRecord>& logged,
                                   const std::vector<NavRecord>& truth,
                                   const Reconstruction& model,
                                   int reference_dive) {
  std::set<std::string> registered;
  for (const Image& image : model.Images()) registered.insert(image.name);
  std::vector<Eigen::Vector3d> true_positions, logged_positions;
  std::vector<Eigen::Matrix3d> covariances;
  std::vector<int> dives;
  for (size_t i = 0; i < logged.size(); ++i) {
    if (truth[i].image_name != logged[i].image_name) {
      throw ErrorAt("row ", i + 1, " of uwsim's logs names ",
                    logged[i].image_name, " and, in the truth, ",
                    truth[i].image_name);
    }
    if (registered.count(logged[i].image_name) == 0) continue;
    true_positions.push_back(truth[i].position);
    logged_positions.push_back(logged[i].position);
    covariances.push_back(
        logged[i].position_sigma.cwiseAbs2().asDiagonal().toDenseMatrix());
    dives.push_back(logged[i].dive);
  }
  const SimilarityWithOffsets fit = EstimateSimilarityWithOffsets(
      true_positions, logged_positions, covariances, dives, reference_dive,
      SimilarityWithOffsetsOptions());
  if (!fit.converged) throw ErrorAt("the ideal offsets' fit did not converge");
  return fit;
}

}  // namespace

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
  chain.output_dir = dir / "ba";
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
  const SimilarityWithOffsets ideal =
      IdealOffsets(logged, truth, ReadModel(dir / "ba"), reference);
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
    Eigen::Vector3d ideal_error;
    for (int k = 0; k < 3; ++k) {
      ideal_error(k) =
          offset.at("offset_m")[k].get<double>() - ideal.offsets.at(dive)(k);
    }
    chain.ideal_offset_errors.push_back(ideal_error);
    chain.offset_sigmas.push_back(sigma);
  }
  return chain;
}

}  // namespace uw::testing
