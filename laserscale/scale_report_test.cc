#include "laserscale/scale_report.h"

#include <cmath>
#include <filesystem>

#include <gtest/gtest.h>

#include "common/util/error.h"
#include "common/util/file.h"
#include "common/util/random.h"
#include "tests/support/svg_ticks.h"

namespace uw {
namespace {

// An accepted image whose Monte Carlo is `scale` + sigma z_n + shared c_n:
// z independent per image, c common to every image (the calibration).
ImageEstimate MakeImage(const std::string& name, double scale, double sigma,
                        double shared_sigma, uint64_t seed,
                        const Eigen::Vector3d& centroid) {
  SplitMix64Stream own(seed);
  SplitMix64Stream shared(12345);
  ImageScaleResult result;
  result.image = name;
  result.accepted = true;
  result.nominal = scale;
  for (int n = 0; n < 4000; ++n) {
    const double s =
        scale + sigma * own.Gaussian() + shared_sigma * shared.Gaussian();
    result.per_iteration.push_back(s);
    result.samples.push_back(s);
  }
  result.monte_carlo = Summarize(result.samples);
  ImageEstimate estimate;
  estimate.name = name;
  estimate.result = result;
  estimate.hit_centroid = centroid;
  return estimate;
}

TEST(CombineImages, WeightsByVarianceAndKeepsSharedErrors) {
  std::vector<ImageEstimate> images;
  images.push_back(MakeImage("a", 1.000, 0.010, 0.0, 1, {0, 0, 0}));
  images.push_back(MakeImage("b", 1.002, 0.005, 0.0, 2, {0.2, 0, 0}));
  ImageEstimate rejected = MakeImage("c", 1.5, 0.01, 0.0, 3, {0, 0, 0});
  rejected.result->accepted = false;
  images.push_back(rejected);
  ImageEstimate missing;
  missing.name = "d";
  missing.problem = "not localized";
  images.push_back(missing);
  const ModelScaleReport report = CombineImages(
      images, ScaleMethod::kFum, MonteCarloOptions(), CombineOptions());
  ASSERT_TRUE(report.model.nominal);
  EXPECT_EQ(report.model.images.size(), 2u);
  // Weights 1/σ²: b counts 4 times a.
  const double expected = (1.000 * 1.0 + 1.002 * 4.0) / 5.0;
  EXPECT_NEAR(*report.model.nominal, expected, 1e-4);
  // Independent errors average: σ = 1 / sqrt(1/0.01² + 1/0.005²).
  EXPECT_NEAR(report.model.monte_carlo.std_dev, 0.004472, 0.0003);
  EXPECT_LT(report.model.ci95_low, expected);
  EXPECT_GT(report.model.ci95_high, expected);

  // A shared (calibration) error of 0.01 in every image does not average.
  std::vector<ImageEstimate> correlated;
  for (int i = 0; i < 6; ++i) {
    correlated.push_back(
        MakeImage("i" + std::to_string(i), 1.0, 0.01, 0.01, 10 + i, {0, 0, 0}));
  }
  const ModelScaleReport shared = CombineImages(
      correlated, ScaleMethod::kFum, MonteCarloOptions(), CombineOptions());
  // sqrt(0.01² / 6 + 0.01²) = 0.0108.
  EXPECT_NEAR(shared.model.monte_carlo.std_dev, 0.0108, 0.0008);
}

TEST(CombineImages, WidensTheIntervalWhenImagesDisagree) {
  std::vector<ImageEstimate> images;
  // Two images 10 σ apart: Birge ratio ~ 7.
  images.push_back(MakeImage("a", 1.00, 0.001, 0.0, 1, {0, 0, 0}));
  images.push_back(MakeImage("b", 1.01, 0.001, 0.0, 2, {0, 0, 0}));
  const ModelScaleReport report = CombineImages(
      images, ScaleMethod::kFum, MonteCarloOptions(), CombineOptions());
  EXPECT_NEAR(report.model.birge_ratio, 7.07, 0.1);
  EXPECT_GT(report.model.ci95_high - report.model.ci95_low, 0.012);
  EXPECT_NEAR(report.model.sigma,
              report.model.birge_ratio * report.model.monte_carlo.std_dev,
              1e-12);
}

TEST(CombineImages, SegmentsGroupImagesWithinTheRadius) {
  std::vector<ImageEstimate> images;
  images.push_back(MakeImage("a", 1.00, 0.01, 0.0, 1, {0, 0, 0}));
  images.push_back(MakeImage("b", 1.00, 0.01, 0.0, 2, {0.5, 0, 0}));
  images.push_back(MakeImage("c", 0.98, 0.01, 0.0, 3, {5, 0, 0}));
  const ModelScaleReport report = CombineImages(
      images, ScaleMethod::kFum, MonteCarloOptions(), CombineOptions());
  ASSERT_EQ(report.segments.size(), 2u);
  EXPECT_EQ(report.segments[0].scale.images.size(), 2u);
  EXPECT_NEAR(report.segments[0].centre.x(), 0.25, 1e-12);
  EXPECT_NEAR(*report.segments[1].scale.nominal, 0.98, 1e-12);
}

TEST(WriteScaleReport, WritesEveryFileAndApplyReadsTheScale) {
  const std::filesystem::path dir =
      std::filesystem::path(::testing::TempDir()) / "scale_report_test";
  std::filesystem::remove_all(dir);
  std::vector<ImageEstimate> images;
  images.push_back(MakeImage("L1.png", 0.99, 0.01, 0.0, 1, {0, 0, 0}));
  const ModelScaleReport report = CombineImages(
      images, ScaleMethod::kFum, MonteCarloOptions(), CombineOptions());
  WriteScaleReport(report, dir);
  for (const char* file :
       {"scale.json", "images.csv", "items.csv", "segments.csv", "index.html",
        "scales.png", "histogram.png", "convergence.png", "scales.svg",
        "histogram.svg", "convergence.svg"}) {
    EXPECT_TRUE(std::filesystem::exists(dir / file)) << file;
  }
  // Readable axes: the images by name, scales at 1-2-5 steps.
  const std::string scales = ReadFileToString(dir / "scales.svg");
  EXPECT_EQ(SvgTickLabels(scales, 'x'), std::vector<std::string>{"L1.png"});
  EXPECT_EQ(TickProblem(SvgTickLabels(scales, 'y')), "");
  for (const char* figure : {"histogram.svg", "convergence.svg"}) {
    const std::string svg = ReadFileToString(dir / figure);
    EXPECT_EQ(TickProblem(SvgTickLabels(svg, 'x')), "") << figure;
    EXPECT_EQ(TickProblem(SvgTickLabels(svg, 'y')), "") << figure;
  }
  EXPECT_NEAR(ReadScaleFromJson(dir / "scale.json").scale, 0.99, 1e-12);

  // No accepted image: no scale, and apply refuses.
  images[0].result->accepted = false;
  const std::filesystem::path empty_dir = dir / "empty";
  WriteScaleReport(CombineImages(images, ScaleMethod::kFum, MonteCarloOptions(),
                                 CombineOptions()),
                   empty_dir);
  EXPECT_THROW(ReadScaleFromJson(empty_dir / "scale.json"), Error);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace uw
