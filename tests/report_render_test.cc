// uwcolmap survey_report on the reduced demo's output (the fixture
// demo_reduced: scripts/demo.sh on the survey and laser images of the
// fixtures), rendered by headless Chromium: the page draws, and no image is
// missing (issue 7, the report).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <regex>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "common/util/file.h"
#include "common/util/html.h"
#include "common/util/subprocess.h"
#include "tests/support/process.h"
#include "tests/support/svg_ticks.h"

namespace uw {
namespace {

namespace fs = std::filesystem;
using testing::FreshTestDir;
using testing::Quoted;

const fs::path kDemoDir = UW_DEMO_DIR;
const fs::path kBinDir = fs::path(UW_BUILD_DIR) / "bin";
constexpr int kWidth = 1400;
constexpr int kHeight = 5000;

// Headless Chromium as root in a container: no sandbox, no GPU, no
// /dev/shm; the virtual time budget lets every image load before the
// screenshot or the DOM dump.
std::string Chromium(const std::string& action, const fs::path& page) {
  return "timeout 180 chromium --headless --no-sandbox --disable-gpu "
         "--disable-dev-shm-usage --hide-scrollbars --window-size=" +
         std::to_string(kWidth) + "," + std::to_string(kHeight) +
         " --virtual-time-budget=10000 " + action + " " +
         Quoted("file://" + fs::absolute(page).string());
}

size_t CountImgTags(const std::string& html) {
  size_t count = 0;
  for (size_t at = html.find("<img"); at != std::string::npos;
       at = html.find("<img", at + 1)) {
    ++count;
  }
  return count;
}

TEST(ReportRender, DemoReportRendersWithEveryImage) {
  // A failure, not a skip: without a browser the report is unchecked.
  ASSERT_EQ(RunProcess("command -v chromium", false).exit_code, 0)
      << "chromium is not installed (scripts/setup.sh installs the Debian "
         "package chromium)";
  const fs::path& out = kDemoDir;
  // The demo ends with both reports' paths.
  const std::string demo_output = ReadFileToString(out.string() + ".log");
  EXPECT_NE(demo_output.find("Survey report: " +
                             (out / "report" / "index.html").string()),
            std::string::npos)
      << demo_output;
  EXPECT_NE(demo_output.find("Laser report: "), std::string::npos);
  EXPECT_TRUE(fs::is_regular_file(out / "report" / "index.html"));

  // The command itself, every input explicit, into a folder of its own.
  const fs::path report = FreshTestDir("uw_report_render_test") / "report";
  const fs::path model = out / "compare" / "ours_prior_auto";
  const fs::path chain = out / "compare" / "chain" / "ours_prior_auto";
  const auto command = RunProcess(
      Quoted(kBinDir / "uwcolmap") + " survey_report --input_path " +
          Quoted(model) + " --ba_report " + Quoted(model / "ba_report.json") +
          " --nav " + Quoted(out / "sim" / "nav.csv") + " --laser_report " +
          Quoted(chain / "report") + " --compare_table " +
          Quoted(out / "compare" / "table.csv") + " --dense_comparison " +
          Quoted(chain / "compare.json") + " --mesh " +
          Quoted(chain / "mesh.ply") + " --timings " +
          Quoted(out / "timings.csv") + " --truth_dir " + Quoted(out / "sim") +
          " --covariance " + Quoted(model / "covariance") + " --output_path " +
          Quoted(report),
      true);
  ASSERT_EQ(command.exit_code, 0) << command.output;
  std::cout << command.output;
  EXPECT_EQ(command.output.find("left out"), std::string::npos)
      << "every input was given";

  // Statically: every src is a file of the folder that decodes.
  const fs::path index = report / "index.html";
  const std::string html = ReadFileToString(index);
  const std::vector<std::string> sources = ImageSources(html);
  const size_t num_img = CountImgTags(html);
  EXPECT_EQ(sources.size(), num_img);
  EXPECT_GE(num_img, 5u);
  for (const std::string& source : sources) {
    EXPECT_FALSE(fs::path(source).is_absolute()) << source;
    EXPECT_EQ(source.find(".."), std::string::npos) << source;
    EXPECT_FALSE(cv::imread((report / source).string()).empty()) << source;
  }
  EXPECT_EQ(html.find("http://"), std::string::npos);
  EXPECT_EQ(html.find("https://"), std::string::npos);
  EXPECT_TRUE(fs::is_regular_file(report / "report.json"));

  // Acceptance 5 (issue 17): every figure has an SVG beside its PNG, and
  // every SVG's axes can be read: 1-2-5 steps or decades without offsets,
  // per-image axes by the images' names.
  std::vector<std::string> with_svg;
  for (const auto& entry : fs::recursive_directory_iterator(report)) {
    if (entry.path().extension() != ".svg") continue;
    const std::string name =
        fs::relative(entry.path(), report).replace_extension().string();
    with_svg.push_back(name);
    const std::string svg = ReadFileToString(entry.path());
    EXPECT_EQ(TickProblem(SvgTickLabels(svg, 'y')), "") << name;
    const std::vector<std::string> x = SvgTickLabels(svg, 'x');
    const bool images =
        !x.empty() && std::all_of(x.begin(), x.end(), [](const std::string& l) {
          return IsImageFile(l);
        });
    if (!images) {
      EXPECT_EQ(TickProblem(x), "") << name;
    }
    std::printf("[ figure ] %s: x %s ... %s, y %zu ticks\n", name.c_str(),
                x.empty() ? "-" : x.front().c_str(),
                x.empty() ? "-" : x.back().c_str(),
                SvgTickLabels(svg, 'y').size());
  }
  for (const char* figure :
       {"prior_residuals", "prior_mahalanobis", "dense_distance_histogram",
        "laser/scales", "laser/histogram", "laser/convergence",
        "uncertainty/uncertainty_map"}) {
    EXPECT_NE(std::find(with_svg.begin(), with_svg.end(), figure),
              with_svg.end())
        << figure;
  }

  // In the browser: a screenshot of the page's size that is not blank.
  const fs::path shot = report / "shot.png";
  const auto screenshot =
      RunProcess(Chromium("--screenshot=" + Quoted(shot), index), true);
  ASSERT_EQ(screenshot.exit_code, 0) << screenshot.output;
  const cv::Mat image = cv::imread(shot.string(), cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(image.empty()) << screenshot.output;
  EXPECT_EQ(image.cols, kWidth);
  EXPECT_EQ(image.rows, kHeight);
  cv::Scalar mean, std_dev;
  cv::meanStdDev(image, mean, std_dev);
  EXPECT_GT(std_dev[0], 10.0);

  // ...and every image loaded: the page's script writes loaded/total.
  const auto dom = RunProcess(Chromium("--dump-dom", index), false);
  ASSERT_EQ(dom.exit_code, 0);
  std::smatch match;
  const std::regex images_ok("data-images-ok=\"(\\d+)/(\\d+)\"");
  ASSERT_TRUE(std::regex_search(dom.output, match, images_ok))
      << dom.output.substr(0, 2000);
  const size_t loaded = std::stoul(match[1].str());
  const size_t total = std::stoul(match[2].str());
  std::printf(
      "[ figures ] %zu <img> in index.html, %zu/%zu loaded in Chromium; "
      "screenshot %dx%d, pixel std-dev %.1f\n",
      num_img, loaded, total, image.cols, image.rows, std_dev[0]);
  EXPECT_EQ(total, num_img);
  EXPECT_EQ(loaded, total);
}

}  // namespace
}  // namespace uw
