// uwcolmap covariance_estimator and bundle_adjuster --BA.covariance 1 on
// the uwsim survey (stock colmap's model, uwsim's navigation): the files,
// the draws, the two commands agreeing, and what they refuse.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <string>
#include <utility>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "common/util/file.h"
#include "common/util/subprocess.h"
#include "tests/support/process.h"
#include "tests/support/uwsim_survey.h"

namespace uw {
namespace {

namespace fs = std::filesystem;
using testing::FreshTestDir;
using testing::Quoted;
using testing::SurveyMountFlags;

const fs::path kUwcolmap = fs::path(UW_BIN_DIR) / "uwcolmap";
const fs::path kSurveyDir = UW_SURVEY_DIR;
const fs::path kSimDir = kSurveyDir / "sim";
const fs::path kSparseDir = kSurveyDir / "sparse" / "0";

std::string NavFlags() {
  return " --nav " + Quoted(kSimDir / "nav.csv") + SurveyMountFlags(kSimDir);
}

nlohmann::json ReadJson(const fs::path& path) {
  return nlohmann::json::parse(ReadFileToString(path));
}

// CTest runs every case in its own process, two at a time: each case has
// its own folder.
// A navigation-fused adjustment with its covariance and 40 draws; then
// covariance_estimator on the adjusted model, given the weight the
// adjustment solved with, must give the same.
TEST(CovarianceEstimator, BundleAdjusterAndEstimatorAgree) {
  const fs::path dir = FreshTestDir("uw_covariance_estimator_agree");
  const auto adjuster = RunProcess(
      Quoted(kUwcolmap) + " bundle_adjuster --input_path " +
          Quoted(kSparseDir) + " --output_path " + Quoted(dir / "ba") +
          NavFlags() + " --BA.covariance 1 --Covariance.samples 40",
      true);
  ASSERT_EQ(adjuster.exit_code, 0) << adjuster.output;
  const fs::path folder = dir / "ba" / "covariance";
  for (const char* name :
       {"covariance.bin", "covariance.json", "cameras.csv", "points.ply",
        "uncertainty_map.png", "uncertainty_map.svg", "samples.bin"}) {
    EXPECT_TRUE(fs::is_regular_file(folder / name)) << name;
  }
  EXPECT_NE(adjuster.output.find("samples.bin"), std::string::npos);
  const nlohmann::json json = ReadJson(folder / "covariance.json");
  EXPECT_EQ(json.at("gauge"), "priors");
  EXPECT_EQ(json.at("samples").at("count"), 40);
  EXPECT_NE(json.at("samples")
                .at("log_scale_meaning")
                .get<std::string>()
                .find("navigation"),
            std::string::npos);
  const double scale_sigma =
      json.at("samples").at("log_scale_sigma").get<double>();
  std::cout << "[ figures ] survey: median centre sigma "
            << json.at("images").at("sigma_position_m").at("median")
            << " m, median point sigma "
            << json.at("points").at("sigma_largest_axis_m").at("median")
            << " m, navigation scale sigma " << scale_sigma << ", "
            << json.at("time_s").at("total") << " s\n";
  EXPECT_GT(scale_sigma, 0.0);
  EXPECT_LT(scale_sigma, 0.1);  // a scale known to 10 %: not the gauge's
  const std::string csv = ReadFileToString(folder / "cameras.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'),
            json.at("num_images").get<long>() + 1);

  // The priors as the adjustment weighted them: stated x sigma_px /
  // (lambda sigma_n), printed.
  const nlohmann::json report = ReadJson(dir / "ba" / "ba_report.json");
  const double weight = report.at("weight_px_per_m").get<double>();
  const double nav_sigma_scale = json.at("nav_sigma_scale").get<double>();
  std::cout << "[ figures ] survey: navigation sigmas as stated x "
            << nav_sigma_scale << " (lambda " << weight << " px/m)\n";
  EXPECT_NEAR(nav_sigma_scale,
              json.at("pixel_sigma_px").get<double>() /
                  (weight * report.at("nav_sigma_m").get<double>()),
              1e-12);
  EXPECT_NE(adjuster.output.find("navigation sigmas: stated x"),
            std::string::npos);

  const auto result = RunProcess(
      Quoted(kUwcolmap) + " covariance_estimator --input_path " +
          Quoted(dir / "ba") + " --output_path " + Quoted(dir / "cov") +
          NavFlags() + " --Covariance.nav_weight " +
          report.at("weight_px_per_m").dump(),
      true);
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const nlohmann::json ours = ReadJson(dir / "cov" / "covariance.json");
  const nlohmann::json& adjusters = json;
  EXPECT_EQ(ours.at("model_fingerprint"), adjusters.at("model_fingerprint"));
  for (const auto& [kind, sigma] :
       {std::pair{"images", "sigma_position_m"},
        std::pair{"images", "sigma_rotation_deg"},
        std::pair{"points", "sigma_largest_axis_m"}}) {
    for (const char* statistic : {"median", "max"}) {
      const double a = ours.at(kind).at(sigma).at(statistic).get<double>();
      const double b = adjusters.at(kind).at(sigma).at(statistic).get<double>();
      EXPECT_NEAR(a, b, 1e-6 * b) << kind << " " << sigma << " " << statistic;
    }
  }
  // Asked for no draws: none written.
  EXPECT_FALSE(fs::exists(dir / "cov" / "samples.bin"));
  EXPECT_FALSE(ours.contains("samples"));

  // As stated: the factor is 1, and says so.
  const auto stated =
      RunProcess(Quoted(kUwcolmap) + " covariance_estimator --input_path " +
                     Quoted(dir / "ba") + " --output_path " +
                     Quoted(dir / "stated") + NavFlags(),
                 true);
  ASSERT_EQ(stated.exit_code, 0) << stated.output;
  const nlohmann::json as_stated = ReadJson(dir / "stated" / "covariance.json");
  EXPECT_EQ(as_stated.at("nav_sigma_scale").get<double>(), 1.0);
  EXPECT_EQ(as_stated.at("nav_sigma_source"), "the priors' sigmas as stated");
}

TEST(CovarianceEstimator, HeldGaugeOnStockColmapsModel) {
  const fs::path out = FreshTestDir("uw_covariance_estimator_held") / "out";
  const auto result =
      RunProcess(Quoted(kUwcolmap) + " covariance_estimator --input_path " +
                     Quoted(kSparseDir) + " --output_path " + Quoted(out) +
                     " --Covariance.gauge held --Covariance.samples 5",
                 true);
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const nlohmann::json json = ReadJson(out / "covariance.json");
  EXPECT_EQ(json.at("gauge"), "held");
  EXPECT_EQ(json.at("method"), "schur");
  // Without priors the draws' scale is the gauge's, and says so.
  EXPECT_NE(json.at("samples")
                .at("log_scale_meaning")
                .get<std::string>()
                .find("not a measurement"),
            std::string::npos);
  // A lawnmower at 75 % / 50 % overlap: no hole, no short baseline.
  EXPECT_TRUE(json.at("points").at("coverage_gaps").at("cells").empty());
  EXPECT_TRUE(json.at("points").at("short_baselines").at("cells").empty())
      << json.at("points").at("short_baselines").dump();
}

// --Covariance.method ceres_sparse_qr (the benchmark's peer) on stock
// colmap's model: the same camera marginals as ours.
TEST(CovarianceEstimator, CeresMethodAgreesOnStockColmapsModel) {
  const fs::path dir = FreshTestDir("uw_covariance_estimator_ceres");
  for (const char* method : {"schur", "ceres_sparse_qr"}) {
    const auto result = RunProcess(
        Quoted(kUwcolmap) + " covariance_estimator --input_path " +
            Quoted(kSparseDir) + " --output_path " + Quoted(dir / method) +
            " --Covariance.gauge held --Covariance.points 0" +
            " --Covariance.method " + method,
        true);
    ASSERT_EQ(result.exit_code, 0) << result.output;
  }
  const nlohmann::json ours = ReadJson(dir / "schur" / "covariance.json");
  const nlohmann::json ceres =
      ReadJson(dir / "ceres_sparse_qr" / "covariance.json");
  EXPECT_EQ(ceres.at("method"), "ceres_sparse_qr");
  std::cout << "[ figures ] stock colmap's model: schur "
            << ours.at("time_s").at("total") << " s, ceres_sparse_qr "
            << ceres.at("time_s").at("total") << " s\n";
  for (const char* sigma : {"sigma_position_m", "sigma_rotation_deg"}) {
    for (const char* statistic : {"median", "max"}) {
      const double a = ours.at("images").at(sigma).at(statistic).get<double>();
      const double b = ceres.at("images").at(sigma).at(statistic).get<double>();
      EXPECT_NEAR(a, b, 1e-6 * b) << sigma << " " << statistic;
    }
  }
  // Draws need the Schur route's factor.
  const auto refused = RunProcess(
      Quoted(kUwcolmap) + " covariance_estimator --input_path " +
          Quoted(kSparseDir) + " --output_path " + Quoted(dir / "refused") +
          " --Covariance.gauge held --Covariance.method ceres_sparse_qr" +
          " --Covariance.samples 10",
      true);
  EXPECT_NE(refused.exit_code, 0);
  EXPECT_NE(refused.output.find("marginals only"), std::string::npos)
      << refused.output;
  EXPECT_FALSE(fs::exists(dir / "refused"));
}

TEST(CovarianceEstimator, RefusesAGaugeItCannotHaveAndWritesNothing) {
  const fs::path dir = FreshTestDir("uw_covariance_estimator_refuses");
  {
    const fs::path out = dir / "no_priors";
    const auto result =
        RunProcess(Quoted(kUwcolmap) + " covariance_estimator --input_path " +
                       Quoted(kSparseDir) + " --output_path " + Quoted(out),
                   true);
    EXPECT_NE(result.exit_code, 0);
    EXPECT_NE(result.output.find("--Covariance.gauge held"), std::string::npos)
        << result.output;
    EXPECT_FALSE(fs::exists(out / "covariance.json"));
  }
  {
    const fs::path out = dir / "twice";
    const auto result =
        RunProcess(Quoted(kUwcolmap) + " covariance_estimator --input_path " +
                       Quoted(kSparseDir) + " --output_path " + Quoted(out) +
                       NavFlags() + " --Covariance.gauge free_network",
                   true);
    EXPECT_NE(result.exit_code, 0);
    EXPECT_NE(result.output.find("fix it twice"), std::string::npos)
        << result.output;
    EXPECT_FALSE(fs::exists(out / "covariance.json"));
  }
  {
    // bundle_adjuster weights its covariance's priors as it solved.
    const fs::path out = dir / "weight";
    const auto result = RunProcess(
        Quoted(kUwcolmap) + " bundle_adjuster --input_path " +
            Quoted(kSparseDir) + " --output_path " + Quoted(out) + NavFlags() +
            " --BA.covariance 1 --Covariance.nav_weight 2",
        true);
    EXPECT_NE(result.exit_code, 0);
    EXPECT_NE(result.output.find("--Covariance.nav_weight is for "
                                 "covariance_estimator"),
              std::string::npos)
        << result.output;
    EXPECT_FALSE(fs::exists(out));
  }
}

}  // namespace
}  // namespace uw
