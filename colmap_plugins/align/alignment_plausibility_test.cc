#include "colmap_plugins/align/alignment_plausibility.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "common/util/error.h"
#include "common/util/error_testing.h"

namespace uw {
namespace {

// A lawnmower of 5 x 4 down-looking cameras, 1 model unit apart, over 30
// points 2 units below them (none: `with_points` false), each seen by every
// camera.
Reconstruction Survey(bool with_points = true) {
  Reconstruction model;
  image_t id = 1;
  for (int row = 0; row < 4; ++row) {
    for (int column = 0; column < 5; ++column, ++id) {
      Image image;
      image.image_id = id;
      image.camera_id = 1;
      image.name = "img" + std::to_string(id) + ".png";
      image.cam_from_world.translation = -Eigen::Vector3d(column, row, 0.0);
      model.AddImage(image);
    }
  }
  std::mt19937_64 random(3);
  std::uniform_real_distribution<double> uniform(-0.5, 4.5);
  for (point3D_t point_id = 1; with_points && point_id <= 30; ++point_id) {
    Point3D point;
    point.point3D_id = point_id;
    point.xyz = Eigen::Vector3d(uniform(random), uniform(random) * 0.75,
                                2.0 + 0.1 * uniform(random));
    for (image_t image_id = 1; image_id < id; ++image_id) {
      point.track.push_back({image_id, 0});
    }
    model.AddPoint3D(point);
  }
  return model;
}

Sim3d WorldFromModel(double scale) {
  Sim3d world_from_model;
  world_from_model.scale = scale;
  world_from_model.rotation =
      Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()));
  world_from_model.translation = Eigen::Vector3d(12.0, -30.0, -45.0);
  return world_from_model;
}

std::vector<Eigen::Vector3d> Centres(const Reconstruction& model) {
  std::vector<Eigen::Vector3d> centres;
  for (const Image& image : model.Images()) {
    centres.push_back(image.ProjectionCenter());
  }
  return centres;
}

// The centres in the world at `scale`, with noise of `noise_m` per axis.
std::vector<Eigen::Vector3d> References(const Reconstruction& model,
                                        double scale, double noise_m,
                                        uint64_t seed = 7) {
  std::mt19937_64 random(seed);
  std::normal_distribution<double> normal(0.0, noise_m);
  std::vector<Eigen::Vector3d> references;
  for (const Eigen::Vector3d& centre : Centres(model)) {
    references.push_back(
        WorldFromModel(scale) * centre +
        Eigen::Vector3d(normal(random), normal(random), normal(random)));
  }
  return references;
}

struct Checked {
  SimilarityResult similarity;
  AlignmentPlausibility plausibility;
};

Checked Check(const Reconstruction& model,
              const std::vector<Eigen::Vector3d>& references,
              double stated_sigma_m,
              const AlignmentPlausibilityOptions& options = {},
              bool robust = false) {
  SimilarityOptions similarity_options;
  similarity_options.robust = robust;
  const std::vector<Eigen::Matrix3d> covariances(
      references.size(),
      stated_sigma_m * stated_sigma_m * Eigen::Matrix3d::Identity());
  Checked checked;
  checked.similarity = EstimateSimilarity(
      Centres(model), references, stated_sigma_m > 0.0 ? &covariances : nullptr,
      similarity_options);
  checked.plausibility = CheckAlignmentPlausibility(
      model, checked.similarity, references, "nav.csv", options);
  return checked;
}

TEST(AlignmentPlausibility, ASurveyInMetresPasses) {
  const Reconstruction model = Survey();
  // 1 model unit = 0.8 m: the cameras 1.6 m above the scene; 5 cm noise,
  // stated as such.
  const Checked checked = Check(model, References(model, 0.8, 0.05), 0.05);
  const AlignmentPlausibility& result = checked.plausibility;
  ASSERT_TRUE(result.median_range_m.has_value());
  // The points lie 1.56 to 1.96 m below the cameras.
  EXPECT_GT(*result.median_range_m, 1.56);
  EXPECT_LT(*result.median_range_m, 1.96);
  EXPECT_EQ(result.num_depths, 600u);
  EXPECT_GT(result.explained, 0.99);
  ASSERT_TRUE(result.sigma_ratio.has_value());
  EXPECT_GT(*result.sigma_ratio, 0.5);
  EXPECT_LT(*result.sigma_ratio, 1.5);
  EXPECT_TRUE(result.errors.empty());
  EXPECT_TRUE(result.warnings.empty());
  EXPECT_TRUE(PlausibilityWarnings(result, {}, "--accept_implausible").empty());
}

TEST(AlignmentPlausibility, DegreesReadAsMetresAreRefused) {
  const Reconstruction model = Survey();
  // The same survey logged as longitude, latitude (degrees) and depth (m)
  // at 43.1 N, the depth constant: it aligns well, at a scale of 1e-5.
  std::vector<Eigen::Vector3d> references = References(model, 0.8, 0.0);
  const double metres_per_degree = 111320.0;
  for (Eigen::Vector3d& position : references) {
    position = Eigen::Vector3d(
        5.4 + position.x() / (metres_per_degree * std::cos(43.1 * M_PI / 180)),
        43.1 + position.y() / metres_per_degree, -45.0);
  }
  const Checked checked = Check(model, references, 0.0);
  const AlignmentPlausibility& result = checked.plausibility;
  ASSERT_TRUE(result.median_range_m.has_value());
  EXPECT_LT(*result.median_range_m, 1e-4);
  ASSERT_EQ(result.errors.size(), 1u);
  EXPECT_NE(result.errors[0].find("latitude/longitude in degrees"),
            std::string::npos)
      << result.errors[0];
  ExpectErrorContaining(
      [&] { PlausibilityWarnings(result, {}, "--accept_implausible"); },
      "read as metres?\n(--accept_implausible 1 goes on regardless)");
}

TEST(AlignmentPlausibility, MillimetresReadAsMetresAreRefused) {
  const Reconstruction model = Survey();
  const Checked checked = Check(model, References(model, 800.0, 0.0), 0.0);
  ASSERT_EQ(checked.plausibility.errors.size(), 1u);
  EXPECT_NE(checked.plausibility.errors[0].find("millimetres"),
            std::string::npos);
}

TEST(AlignmentPlausibility, NavigationOfAnotherTimeIsRefused) {
  const Reconstruction model = Survey();
  // Each image paired with the position of another (a clock days off lands
  // the images on unrelated parts of the track): stated 5 cm, as logged.
  std::vector<Eigen::Vector3d> references = References(model, 0.8, 0.05);
  std::mt19937_64 random(11);
  std::shuffle(references.begin(), references.end(), random);
  const Checked checked = Check(model, references, 0.05);
  const AlignmentPlausibility& result = checked.plausibility;
  EXPECT_LT(result.explained, 0.5);
  ASSERT_EQ(result.errors.size(), 1u);
  EXPECT_NE(result.errors[0].find("the navigation does not follow these "
                                  "images"),
            std::string::npos)
      << result.errors[0];
  EXPECT_NE(result.errors[0].find("--time_offset"), std::string::npos);
  // Without stated sigmas nothing explains the residuals either.
  EXPECT_EQ(Check(model, references, 0.0).plausibility.errors.size(), 1u);
}

TEST(AlignmentPlausibility, ARobustFitToAFewAgreeingPositionsIsRefused) {
  const Reconstruction model = Survey();
  // 14 of the 20 images paired with the positions of others: RANSAC finds
  // the 6 right ones and calls the rest outliers, which fits them well.
  std::vector<Eigen::Vector3d> references = References(model, 0.8, 0.01);
  std::rotate(references.begin() + 6, references.begin() + 9, references.end());
  const Checked checked = Check(model, references, 0.01, {}, true);
  EXPECT_LT(checked.similarity.num_inliers, 10u);
  EXPECT_GT(checked.plausibility.explained, 0.99);
  ASSERT_EQ(checked.plausibility.errors.size(), 1u);
  EXPECT_NE(checked.plausibility.errors[0].find(fmt::format(
                "only {} of the 20 positions agree with the similarity",
                checked.similarity.num_inliers)),
            std::string::npos)
      << checked.plausibility.errors[0];
  // The robust fit with every position right keeps them all.
  EXPECT_TRUE(Check(model, References(model, 0.8, 0.01), 0.01, {}, true)
                  .plausibility.errors.empty());
}

TEST(AlignmentPlausibility, NoiseTheSigmasStateIsNotAnError) {
  const Reconstruction model = Survey();
  // A USBL whose 1.5 m noise rivals the 3 m survey: the similarity explains
  // little of the spread, but the stated sigma says why.
  const std::vector<Eigen::Vector3d> references =
      References(model, 0.8, 1.5, 5);
  const Checked stated = Check(model, references, 1.5);
  EXPECT_LT(stated.plausibility.explained, 0.5);
  EXPECT_TRUE(stated.plausibility.errors.empty());
  EXPECT_TRUE(stated.plausibility.warnings.empty());
  // Stated as 30 cm (5 sigma): a log noisier than it states, or a wrong
  // pairing; warned, since --Nav.weight auto weights such a log.
  const Checked optimistic = Check(model, references, 0.3);
  EXPECT_TRUE(optimistic.plausibility.errors.empty());
  ASSERT_EQ(optimistic.plausibility.warnings.size(), 1u);
  EXPECT_NE(optimistic.plausibility.warnings[0].find(
                "the navigation is much noisier than it states, or does not "
                "follow these images"),
            std::string::npos)
      << optimistic.plausibility.warnings[0];
  // Stated as 5 cm, the same residuals are 30 sigma: refused.
  EXPECT_EQ(Check(model, references, 0.05).plausibility.errors.size(), 1u);
}

TEST(AlignmentPlausibility, SigmasStatedFarTooLargeAreWarned) {
  const Reconstruction model = Survey();
  const Checked checked = Check(model, References(model, 0.8, 0.01), 100.0);
  const AlignmentPlausibility& result = checked.plausibility;
  EXPECT_TRUE(result.errors.empty());
  ASSERT_EQ(result.warnings.size(), 1u);
  EXPECT_NE(result.warnings[0].find("stated far too large"), std::string::npos);
}

TEST(AlignmentPlausibility, AcceptedErrorsBecomeWarnings) {
  const Reconstruction model = Survey();
  AlignmentPlausibilityOptions options;
  options.accept_implausible = true;
  const Checked checked =
      Check(model, References(model, 800.0, 0.0), 0.0, options);
  const std::vector<std::string> warnings =
      PlausibilityWarnings(checked.plausibility, options, "--Nav.accept");
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("(accepted: --Nav.accept 1)"), std::string::npos);
}

TEST(AlignmentPlausibility, AModelWithoutPointsHasNoRange) {
  const Reconstruction model = Survey(false);
  const Checked checked = Check(model, References(model, 800.0, 0.0), 0.0);
  EXPECT_FALSE(checked.plausibility.median_range_m.has_value());
  EXPECT_TRUE(checked.plausibility.errors.empty());
}

TEST(AlignmentPlausibility, OptionsAreChecked) {
  AlignmentPlausibilityOptions options;
  options.min_range_m = 0.0;
  ExpectErrorContaining([&] { options.Check(); }, "expected 0 < min < max");
  options = {};
  options.min_explained = 1.0;
  ExpectErrorContaining([&] { options.Check(); }, "min_explained 1");
}

}  // namespace
}  // namespace uw
