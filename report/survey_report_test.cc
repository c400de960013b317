#include "report/survey_report.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "common/util/error.h"
#include "common/util/file.h"
#include "common/util/html.h"
#include "report/test_report_inputs.h"

namespace uw {
namespace {

namespace fs = std::filesystem;

class SurveyReportTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ =
        fs::path(::testing::TempDir()) /
        ("survey_report_test_" +
         std::string(
             ::testing::UnitTest::GetInstance()->current_test_info()->name()));
    inputs_ = WriteTestReportInputs(dir_ / "inputs");
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path dir_;
  SurveyReportInputs inputs_;
};

// Every <img> of the page is a file of the folder that decodes.
void ExpectImagesInFolder(const fs::path& out, size_t expected) {
  const std::string html = ReadFileToString(out / "index.html");
  const std::vector<std::string> sources = ImageSources(html);
  EXPECT_EQ(sources.size(), expected);
  for (const std::string& source : sources) {
    EXPECT_EQ(source.find(".."), std::string::npos) << source;
    EXPECT_FALSE(fs::path(source).is_absolute()) << source;
    EXPECT_FALSE(cv::imread((out / source).string()).empty()) << source;
  }
}

TEST_F(SurveyReportTest, WritesEverySectionFromEveryInput) {
  const fs::path out = dir_ / "report";
  const SurveyReportResult result =
      WriteSurveyReport(inputs_, SurveyReportOptions(), out);
  EXPECT_EQ(result.index_path, out / "index.html");
  EXPECT_TRUE(result.omitted.empty());
  // The map, 3 laser plots, 2 thumbnails, 2 prior plots, the uncertainty
  // map.
  EXPECT_EQ(result.num_images, 9u);
  ExpectImagesInFolder(out, 9);
  for (const std::string& name : result.files) {
    EXPECT_TRUE(fs::is_regular_file(out / name)) << name;
  }
  for (const auto& entry : fs::recursive_directory_iterator(out)) {
    EXPECT_EQ(entry.path().string().find(".tmp-"), std::string::npos)
        << entry.path();
  }
  // Thumbnails link to the full overlays, which are copied.
  const std::string html = ReadFileToString(out / "index.html");
  EXPECT_NE(html.find("<a href=\"overlays/L0.png\"><img "
                      "src=\"overlays/thumbs/L0.jpg\""),
            std::string::npos);
  EXPECT_EQ(cv::imread((out / "overlays/thumbs/L0.jpg").string()).cols, 240);
  EXPECT_EQ(cv::imread((out / "overlays/L0.png").string()).cols, 640);
  // The figures come from the inputs.
  for (const char* text :
       {"1.01250", "[1.00750, 1.01750]",
        "4 registered of 5 images in the navigation", "0.4077 px/m", "L0-L1",
        "2.50 mm", "95.0 %", "Total time", "60 s",
        "colmap BA + model_aligner (camera centres)", "(+0.250, -0.500, ",
        // The uncertainty section and the laser scale's model sampling.
        "gauge <b>priors</b>", "0.0310", "3 weak points",
        "navigation sigmas as stated &times; 1.420 (as the adjustment "
        "weighted them: lambda 0.4 px/m)",
        "image 3.png sees 4 points only", "spreads by 7.05 %",
        "200 draws of its covariance", "calibration 64 %, model 36 %",
        "z = +4.25: beyond 3 &sigma;",
        // The adjuster's warnings.
        "<p class=\"bad\">navigation positions on one pass: the 4 camera "
        "centres lie nearly on one line</p>"}) {
    EXPECT_NE(html.find(text), std::string::npos) << text;
  }
  // The adjuster's warning, which the covariance repeats, shown once.
  const std::string one_pass = "navigation positions on one pass";
  EXPECT_EQ(html.find(one_pass), html.rfind(one_pass));
  // The least certain image first.
  const size_t worst = html.find("Least certain images");
  ASSERT_NE(worst, std::string::npos);
  EXPECT_LT(html.find("<td>2.png</td>", worst),
            html.find("<td>0.png</td>", worst));
  EXPECT_TRUE(fs::is_regular_file(out / "uncertainty/cameras.csv"));
  // Per laser / pair: L0 has 2 images with a scale, mean 1.02.
  EXPECT_NE(html.find("<td>L0</td><td>2</td><td>1.02000</td>"),
            std::string::npos);
  const nlohmann::json report =
      nlohmann::json::parse(ReadFileToString(out / "report.json"));
  EXPECT_EQ(report.at("format"), "uwmetric-survey-report");
  EXPECT_EQ(report.at("scale").at("scale").get<double>(), 1.0125);
  EXPECT_EQ(report.at("images").at("registered").get<int>(), 4);
  EXPECT_EQ(report.at("navigation").at("num_mahalanobis_above_95").get<int>(),
            1);
  EXPECT_EQ(report.at("navigation").at("warnings").size(), 1u);
  EXPECT_EQ(report.at("total_time_s").get<double>(), 60.0);
  EXPECT_EQ(report.at("dense_surface").at("coverage").get<double>(), 0.95);
  EXPECT_EQ(report.at("num_images_in_index").get<size_t>(), 9u);
  EXPECT_EQ(report.at("uncertainty").at("gauge"), "priors");
  EXPECT_EQ(report.at("uncertainty").at("num_samples"), 200);
  EXPECT_EQ(report.at("uncertainty").at("nav_sigma_scale").get<double>(), 1.42);
  EXPECT_EQ(report.at("scale").at("navigation_z").get<double>(), 4.25);
  const std::string residuals = ReadFileToString(out / "prior_residuals.csv");
  EXPECT_EQ(residuals.rfind("image,dive,error_x_m", 0), 0u);
  EXPECT_NE(residuals.find("3.png,2,0.000000,0.500000,0.000000,0.500000,"
                           "3.500000\n"),
            std::string::npos);
}

TEST_F(SurveyReportTest, LeavesOutSectionsWithoutInputsAndSaysSo) {
  SurveyReportInputs model_only;
  model_only.model_path = inputs_.model_path;
  const fs::path out = dir_ / "report";
  const SurveyReportResult result =
      WriteSurveyReport(model_only, SurveyReportOptions(), out);
  EXPECT_EQ(result.num_images, 0u);
  EXPECT_GE(result.omitted.size(), 6u);
  const std::string html = ReadFileToString(out / "index.html");
  for (const char* flag : {"--mesh", "--laser_report", "--ba_report",
                           "--compare_table", "--timings", "--covariance"}) {
    EXPECT_NE(html.find(flag), std::string::npos) << flag;
  }
  EXPECT_NE(html.find("4 registered"), std::string::npos);
  ExpectImagesInFolder(out, 0);
}

// Acceptance 5 (issue 17): a model that no --ba_report says was fused with
// the navigation (stock colmap: its own frame and units) is not labelled
// in metres, east or north, and the tracks of another frame are not drawn;
// with the adjuster's report it is the navigation's frame, as before.
TEST_F(SurveyReportTest, AModelInItsOwnFrameIsNotLabelledMetric) {
  SurveyReportInputs unfused = inputs_;
  unfused.ba_report_path.clear();
  unfused.covariance_dir.clear();
  const fs::path out = dir_ / "report";
  WriteSurveyReport(unfused, SurveyReportOptions(), out);
  const std::string html = ReadFileToString(out / "index.html");
  const size_t map = html.find("<h2 id=\"map\">");
  ASSERT_NE(map, std::string::npos);
  const std::string map_section =
      html.substr(map, html.find("<h2", map + 4) - map);
  EXPECT_NE(map_section.find("in its units (not metres, no north"),
            std::string::npos)
      << map_section;
  EXPECT_NE(map_section.find("seen from above along the up its cameras give"),
            std::string::npos)
      << map_section;
  EXPECT_NE(map_section.find("not drawn"), std::string::npos);
  EXPECT_EQ(map_section.find("x east"), std::string::npos);
  EXPECT_EQ(map_section.find("navigation track"), std::string::npos);
  const nlohmann::json report =
      nlohmann::json::parse(ReadFileToString(out / "report.json"));
  EXPECT_EQ(report["map_frame"], "model units");

  const fs::path fused = dir_ / "fused";
  WriteSurveyReport(inputs_, SurveyReportOptions(), fused);
  EXPECT_EQ(nlohmann::json::parse(
                ReadFileToString(fused / "report.json"))["map_frame"],
            "east-north-up metres");
  EXPECT_NE(ReadFileToString(fused / "index.html")
                .find("(x east, y north, "
                      "metres)"),
            std::string::npos);
}

// A log sampled at its own rate names no images: its rows are samples, and
// the report does not count them as images.
TEST_F(SurveyReportTest, ALogOfSamplesIsNotCountedAsImages) {
  SurveyReportInputs with_samples;
  with_samples.model_path = inputs_.model_path;
  with_samples.nav_path = dir_ / "samples.csv";
  std::string samples =
      "time,dive,x,y,z,roll,pitch,yaw,std_x,std_y,std_z,std_roll,std_pitch,"
      "std_yaw\n";
  for (int i = 0; i < 40; ++i) {
    samples += std::to_string(0.1 * i) + ",1," + std::to_string(1.0 + 0.2 * i) +
               ",2,2.5,0,0,0,0.5,0.5,0.05,0.01,0.01,0.05\n";
  }
  WriteTestText(with_samples.nav_path, samples);
  const fs::path out = dir_ / "report";
  WriteSurveyReport(with_samples, SurveyReportOptions(), out);
  const std::string html = ReadFileToString(out / "index.html");
  EXPECT_NE(html.find("4 registered; the navigation: 40 samples, no image "
                      "names"),
            std::string::npos);
  EXPECT_EQ(html.find("registered of"), std::string::npos);
  const nlohmann::json report =
      nlohmann::json::parse(ReadFileToString(out / "report.json"));
  EXPECT_EQ(report["images"]["navigation_rows"], 40);
  EXPECT_EQ(report["images"]["navigation_images"], 0);
}

TEST_F(SurveyReportTest, ABadInputIsNamedAndNothingIsWritten) {
  const fs::path out = dir_ / "report";
  WriteTestText(inputs_.compare_table_path, "method,time_s\n\"open,1\n");
  try {
    WriteSurveyReport(inputs_, SurveyReportOptions(), out);
    ADD_FAILURE() << "no error";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("table.csv:2"), std::string::npos)
        << error.what();
  }
  EXPECT_FALSE(fs::exists(out / "index.html"));
  inputs_.mesh_path = dir_ / "missing.ply";
  try {
    WriteSurveyReport(inputs_, SurveyReportOptions(), out);
    ADD_FAILURE() << "no error";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("--mesh "), std::string::npos)
        << error.what();
  }
  SurveyReportOptions options;
  options.thumbnail_width_px = 0;
  EXPECT_THROW(options.Check(), Error);
}

}  // namespace
}  // namespace uw
