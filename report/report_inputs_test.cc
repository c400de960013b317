#include "report/report_inputs.h"

#include <gtest/gtest.h>

#include "common/util/error.h"
#include "report/test_report_inputs.h"
#include "tests/support/process.h"

namespace uw {
namespace {

namespace fs = std::filesystem;

class ReportInputsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    // One folder per case: CTest runs the cases in parallel.
    dir_ = testing::FreshTestDir("report_inputs_test");
    inputs_ = WriteTestReportInputs(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path dir_;
  SurveyReportInputs inputs_;
};

template <typename Function>
std::string ErrorOf(Function function) {
  try {
    function();
  } catch (const Error& error) {
    return error.what();
  }
  ADD_FAILURE() << "no uw::Error";
  return "";
}

TEST_F(ReportInputsTest, ReadsWhatTheReportShows) {
  inputs_.Check();
  const BaReportSummary ba = ReadBaReport(inputs_.ba_report_path);
  EXPECT_EQ(ba.weight_px_per_m, 0.4077);
  EXPECT_EQ(ba.weighting, "likelihood");
  EXPECT_EQ(ba.strategy, "prior");
  ASSERT_EQ(ba.residuals.size(), 4u);
  EXPECT_EQ(ba.residuals[3].name, "3.png");
  EXPECT_EQ(ba.residuals[3].dive, 2);
  EXPECT_EQ(ba.residuals[3].error_m, Eigen::Vector3d(0, 0.5, 0));
  EXPECT_EQ(ba.residuals[3].mahalanobis, 3.5);
  ASSERT_EQ(ba.dive_offsets.size(), 2u);
  EXPECT_FALSE(ba.dive_offsets[0].sigma_m.has_value());
  EXPECT_EQ(ba.dive_offsets[1].offset_m, Eigen::Vector3d(0.25, -0.5, 0));
  ASSERT_EQ(ba.warnings.size(), 1u);
  EXPECT_NE(ba.warnings[0].find("nearly on one line"), std::string::npos);

  const LaserReportSummary laser = ReadLaserReport(inputs_.laser_report_dir);
  EXPECT_EQ(laser.scale, 1.0125);
  EXPECT_EQ(laser.ci95_low, 1.0075);
  EXPECT_EQ(laser.ci95_high, 1.0175);
  EXPECT_EQ(laser.num_accepted, 2);
  ASSERT_TRUE(laser.items.has_value());
  EXPECT_EQ(laser.items->NumRows(), 4u);
  EXPECT_EQ(laser.items->Text(1, "item"), "L0-L1");
  ASSERT_TRUE(laser.segments.has_value());
  EXPECT_EQ(laser.plots.size(), 3u);
  ASSERT_EQ(laser.overlays.size(), 2u);
  EXPECT_EQ(laser.overlays[0].filename(), "L0.png");

  EXPECT_EQ(laser.model_draws, 200);
  EXPECT_EQ(laser.model_gauge, "priors");
  ASSERT_EQ(laser.variance_shares.size(), 2u);
  EXPECT_EQ(laser.variance_shares[1].first, "model");
  EXPECT_EQ(laser.variance_shares[1].second, 0.36);
  EXPECT_EQ(laser.navigation_z, 4.25);
  EXPECT_FALSE(laser.navigation_consistent);

  const CovarianceSummary covariance =
      ReadCovarianceSummary(inputs_.covariance_dir);
  EXPECT_EQ(covariance.gauge, "priors");
  EXPECT_EQ(covariance.pixel_sigma_px, 0.35);
  EXPECT_EQ(covariance.centre_sigma_m.max, 0.031);
  ASSERT_TRUE(covariance.point_sigma_m.has_value());
  EXPECT_EQ(covariance.point_sigma_m->median, 0.009);
  EXPECT_EQ(covariance.num_weak_points, 3);
  EXPECT_EQ(covariance.num_samples, 200);
  EXPECT_EQ(covariance.log_scale_sigma, 0.0705);
  EXPECT_EQ(covariance.warnings.size(), 2u);
  EXPECT_EQ(covariance.cameras.NumRows(), 4u);
  EXPECT_TRUE(covariance.map.has_value());

  const DenseComparisonSummary dense =
      ReadDenseComparison(inputs_.dense_comparison_path);
  EXPECT_EQ(dense.median_distance, 0.0025);
  EXPECT_EQ(dense.coverage, 0.95);
  EXPECT_EQ(dense.reference_from_model_scale, 1.01);

  const std::vector<StageTime> timings = ReadTimings(inputs_.timings_path);
  ASSERT_EQ(timings.size(), 3u);
  EXPECT_EQ(timings[0].stage, "copy the survey");
  EXPECT_EQ(timings[2].seconds, 60.0);
}

TEST_F(ReportInputsTest, ErrorsNameTheFlagFileAndKey) {
  SurveyReportInputs missing = inputs_;
  missing.nav_path = dir_ / "no_nav.csv";
  EXPECT_NE(
      ErrorOf([&] {
        missing.Check();
      }).find("--nav " + (dir_ / "no_nav.csv").string() + ": no such file"),
      std::string::npos);
  missing = inputs_;
  missing.model_path.clear();
  EXPECT_NE(ErrorOf([&] { missing.Check(); }).find("--input_path"),
            std::string::npos);

  WriteTestText(inputs_.ba_report_path,
                R"({"format": "uwmetric-ba-report", "version": 1})");
  EXPECT_NE(ErrorOf([&] {
              ReadBaReport(inputs_.ba_report_path);
            }).find("ba_report.json: missing key \"weight_px_per_m\""),
            std::string::npos);
  WriteTestText(inputs_.dense_comparison_path,
                R"({"format": "uwmetric-model-comparison", "version": 1})");
  EXPECT_NE(ErrorOf([&] {
              ReadDenseComparison(inputs_.dense_comparison_path);
            }).find("compare.json: no dense_surface"),
            std::string::npos);
  WriteTestText(inputs_.laser_report_dir / "scale.json", "{\"format\": 1");
  EXPECT_NE(ErrorOf([&] {
              ReadLaserReport(inputs_.laser_report_dir);
            }).find("scale.json"),
            std::string::npos);
  fs::remove(inputs_.laser_report_dir / "scale.json");
  EXPECT_NE(ErrorOf([&] {
              ReadLaserReport(inputs_.laser_report_dir);
            }).find("scale.json: missing"),
            std::string::npos);
  WriteTestText(inputs_.covariance_dir / "covariance.json",
                R"({"format": "uwmetric-covariance", "version": 1,
 "gauge": "held", "pixel_sigma_px": 0.3, "num_images": 4, "num_points": 1})");
  EXPECT_NE(ErrorOf([&] {
              ReadCovarianceSummary(inputs_.covariance_dir);
            }).find("covariance.json: missing key \"images\""),
            std::string::npos);
  missing = inputs_;
  missing.covariance_dir = dir_ / "no_covariance";
  EXPECT_NE(ErrorOf([&] { missing.Check(); }).find("--covariance "),
            std::string::npos);
  WriteTestText(inputs_.timings_path, "stage,seconds\nx,fast\n");
  EXPECT_NE(ErrorOf([&] {
              ReadTimings(inputs_.timings_path);
            }).find("timings.csv:2: seconds must be a finite number"),
            std::string::npos);
}

}  // namespace
}  // namespace uw
