#include "colmap_plugins/align/model_alignment.h"

#include <fstream>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "common/util/error.h"
#include "common/util/error_testing.h"
#include "tests/support/process.h"

namespace uw {
namespace {

namespace fs = std::filesystem;

// Five cameras (not on a line) with their centres at `centres`.
const std::vector<Eigen::Vector3d> kCentres = {
    {0, 0, 0}, {1, 0, 0}, {2, 0.5, 0}, {3, 0, 0.2}, {1.5, 2, 0}};

Reconstruction ImagesAt(const std::vector<Eigen::Vector3d>& centres) {
  Reconstruction model;
  for (size_t k = 0; k < centres.size(); ++k) {
    Image image;
    image.image_id = static_cast<image_t>(k + 1);
    image.camera_id = 1;
    image.name = fmt::format("img{}.png", k);
    image.cam_from_world.translation = -centres[k];
    model.AddImage(image);
  }
  return model;
}

Reconstruction FiveImages() { return ImagesAt(kCentres); }

// The references: the centres scaled by 2 and moved by (10, 20, 30).
Eigen::Vector3d ReferenceOf(const Eigen::Vector3d& centre) {
  return 2.0 * centre + Eigen::Vector3d(10, 20, 30);
}

// ref.txt in `dir`: "img<k>.png x y z", the references of `centres`.
std::string WriteReferences(const fs::path& dir,
                            const std::vector<Eigen::Vector3d>& centres) {
  const std::string path = (dir / "ref.txt").string();
  std::ofstream ref(path);
  for (size_t k = 0; k < centres.size(); ++k) {
    const Eigen::Vector3d position = ReferenceOf(centres[k]);
    ref << fmt::format("img{}.png {} {} {}\n", k, position.x(), position.y(),
                       position.z());
  }
  return path;
}

// nav.csv of a down-looking camera at the vehicle's reference point: one
// row per image of the model and one of an image the model lacks.
fs::path WriteNav(const fs::path& dir) {
  const fs::path path = dir / "nav.csv";
  std::ofstream out(path);
  out << "image_name,time,dive,x,y,z,roll,pitch,yaw,std_x,std_y,std_z,"
         "std_roll,std_pitch,std_yaw\n";
  for (size_t k = 0; k <= kCentres.size(); ++k) {
    const bool in_model = k < kCentres.size();
    const Eigen::Vector3d position =
        ReferenceOf(in_model ? kCentres[k] : Eigen::Vector3d(5, 5, 0));
    out << fmt::format(
        "{},{},1,{},{},{},0,0,0,0.1,0.1,0.1,1,1,1\n",
        in_model ? fmt::format("img{}.png", k) : "unregistered.png", k,
        position.x(), position.y(), position.z());
  }
  return path;
}

TEST(ModelAlignment, CheckHoldsTheRulesBetweenOptions) {
  ModelAlignmentOptions options;
  ExpectErrorContaining([&] { options.Check(); },
                        "give exactly one of --ref_images_path, "
                        "--database_path and --nav (got 0)");
  options.ref_images_path = "ref.txt";
  EXPECT_NO_THROW(options.Check());
  options.nav.nav_path = "nav.csv";
  ExpectErrorContaining([&] { options.Check(); }, "(got 2)");
  options.nav.nav_path.clear();
  options.associate = ReferenceAssociation::kClosestPoint;
  ExpectErrorContaining([&] { options.Check(); },
                        "--associate closest_point needs --nav");
  options.associate = ReferenceAssociation::kName;
  options.min_common_images = 2;
  ExpectErrorContaining([&] { options.Check(); },
                        "--min_common_images 2: a similarity needs at least 3");

  for (const ReferenceAssociation association :
       {ReferenceAssociation::kName, ReferenceAssociation::kClosestPoint}) {
    EXPECT_EQ(
        ReferenceAssociationFromName(ReferenceAssociationName(association)),
        association);
  }
  ExpectErrorContaining([] { ReferenceAssociationFromName("time"); },
                        "--associate time: expected name or closest_point");
}

// A log with rows of images the model did not register: the aligner leaves
// them out and says how many.
TEST(ModelAlignment, NavigationRowsOfOtherImagesAreNoError) {
  const fs::path dir = testing::FreshTestDir("uw_model_alignment_nav");
  ModelAlignmentOptions options;
  options.nav.nav_path = WriteNav(dir);
  const Reconstruction model = FiveImages();
  const NavigationReferenceSet navigation =
      NavigationReferences(options.nav, model);
  const std::vector<ReferencePosition>& references = navigation.references;
  ASSERT_EQ(references.size(), 5u);
  EXPECT_EQ(navigation.other_images,
            std::vector<std::string>{"unregistered.png"});
  ASSERT_TRUE(references.front().covariance);
  EXPECT_NEAR((*references.front().covariance)(0, 0), 0.01, 1e-12);

  const ModelAlignment alignment = AlignModel(options, model);
  EXPECT_EQ(alignment.reference, options.nav.nav_path.string());
  ASSERT_TRUE(alignment.world_frame);
  EXPECT_EQ(WorldFrameText(*alignment.world_frame), "the log's x,y,z (m)");
  EXPECT_EQ(ModelAlignmentJson(alignment)["world_frame"],
            "the log's x,y,z (m)");
  EXPECT_EQ(alignment.image_names.size(), 5u);
  EXPECT_EQ(alignment.num_references, 6u);
  EXPECT_EQ(alignment.unknown_names,
            std::vector<std::string>{"unregistered.png"});
  EXPECT_TRUE(alignment.covariance_weighted);
  EXPECT_NEAR(alignment.similarity.b_from_a.scale, 2.0, 1e-9);
  for (size_t k = 0; k < kCentres.size(); ++k) {
    EXPECT_LT(
        (alignment.similarity.b_from_a * kCentres[k] - ReferenceOf(kCentres[k]))
            .norm(),
        1e-9);
  }

  const std::string text = FormatModelAlignment(alignment);
  EXPECT_EQ(text.rfind(fmt::format("Reference: {}\nWorld frame: the log's "
                                   "x,y,z (m)\nImages with a reference "
                                   "position: 5 (of 6 positions)\nReference "
                                   "positions of no model image: 1 (e.g. "
                                   "unregistered.png)\nWeighting: by the "
                                   "reference covariances\n",
                                   options.nav.nav_path.string()),
                       0),
            0u)
      << text;
  EXPECT_NE(text.find("Inliers: 5 of 5\nTransform reference_from_model: "
                      "scale 2, rotation (qw qx qy qz) 1 "),
            std::string::npos)
      << text;

  const nlohmann::json json = ModelAlignmentJson(alignment);
  EXPECT_EQ(json["association"], "name");
  EXPECT_EQ(json["num_images"], 5);
  EXPECT_EQ(json["images"].size(), 5u);
  EXPECT_FALSE(json.contains("iterations"));
  // The references are exact and stated at 10 cm: the only warning says so.
  ASSERT_EQ(alignment.warnings.size(), 1u);
  EXPECT_NE(alignment.warnings[0].find("the sigmas are stated far too large"),
            std::string::npos);
  EXPECT_EQ(json["warnings"].size(), 1u);
  EXPECT_NEAR(json["plausibility"]["explained"].get<double>(), 1.0, 1e-12);
  // FiveImages has no points: no range to judge.
  EXPECT_TRUE(json["plausibility"]["median_range_m"].is_null());
}

// A single survey pass: 21 centres 4 cm RMS off a 10 m line. Only that
// scatter fixes the model's rotation about the line (against the noise of
// real references), which a user aligning such a model must be told.
TEST(ModelAlignment, WarnsWhenTheCentresLieOnOneLine) {
  const fs::path dir = testing::FreshTestDir("uw_model_alignment_line");
  std::vector<Eigen::Vector3d> centres;
  for (int k = 0; k <= 20; ++k) {
    centres.emplace_back(0.5 * k, k % 2 == 0 ? 0.04 : -0.04,
                         k % 3 == 0 ? 0.03 : 0.0);
  }
  ModelAlignmentOptions options;
  options.ref_images_path = WriteReferences(dir, centres);
  const ModelAlignment alignment = AlignModel(options, ImagesAt(centres));
  ASSERT_EQ(alignment.warnings.size(), 1u);
  EXPECT_NE(alignment.warnings[0].find("21 camera centres lie nearly on one "
                                       "line (RMS 0.0"),
            std::string::npos)
      << alignment.warnings[0];
  EXPECT_NE(alignment.warnings[0].find("--Nav.use_attitude 1"),
            std::string::npos);
  EXPECT_EQ(ModelAlignmentJson(alignment)["warnings"].size(), 1u);
}

TEST(ModelAlignment, TooFewCommonImagesIsAnError) {
  const fs::path dir = testing::FreshTestDir("uw_model_alignment_ref");
  ModelAlignmentOptions options;
  options.ref_images_path = WriteReferences(dir, kCentres);
  options.similarity.robust = false;
  const ModelAlignment alignment = AlignModel(options, FiveImages());
  EXPECT_FALSE(alignment.covariance_weighted);
  EXPECT_NE(FormatModelAlignment(alignment).find(
                "Robust: no (least squares over every image)\n"),
            std::string::npos);
  options.min_common_images = 6;
  ExpectErrorContaining(
      [&] { AlignModel(options, FiveImages()); },
      options.ref_images_path +
          ": 5 images of the model have a reference; --min_common_images is "
          "6");
}

// References without covariances (ref_images.txt) are weighted by
// --position_sigma, and the plausibility checks then see their noise: a
// log whose 3 m noise rivals this 6 m survey is noisy, not wrong.
TEST(ModelAlignment, PositionSigmaWeightsReferencesWithoutCovariances) {
  const fs::path dir = testing::FreshTestDir("uw_model_alignment_sigma");
  const std::vector<Eigen::Vector3d> centres = {
      {0, 0, 0},   {1, 0, 0},       {2, 0.5, 0},   {3, 0, 0.2},
      {1.5, 2, 0}, {0.5, 1.5, 0.1}, {2.5, 1.8, 0}, {3, 1, 0.1}};
  const Reconstruction model = ImagesAt(centres);
  // Each reference 3 m per axis off (1.5 model units, scaled by
  // ReferenceOf), in a fixed pattern.
  std::vector<Eigen::Vector3d> noisy;
  for (size_t k = 0; k < centres.size(); ++k) {
    noisy.push_back(centres[k] + 1.5 * Eigen::Vector3d(k % 2 == 0 ? 1 : -1,
                                                       k % 3 == 0 ? -1 : 1,
                                                       k % 4 < 2 ? 1 : -1));
  }
  ModelAlignmentOptions options;
  options.ref_images_path = WriteReferences(dir, noisy);
  options.similarity.robust = false;
  const std::string refused = ErrorOf([&] { AlignModel(options, model); });
  EXPECT_NE(refused.find("Or is the positions' noise, which they do not "
                         "state, as large as the survey?"),
            std::string::npos)
      << refused;
  options.position_sigma_m = 3.0;
  const ModelAlignment alignment = AlignModel(options, model);
  EXPECT_TRUE(alignment.covariance_weighted);
  ASSERT_TRUE(alignment.plausibility.sigma_ratio.has_value());
  EXPECT_LT(*alignment.plausibility.sigma_ratio, 3.0);
  EXPECT_TRUE(alignment.warnings.empty());
  options.associate = ReferenceAssociation::kClosestPoint;
  options.ref_images_path.clear();
  options.nav.nav_path = "nav.csv";
  ExpectErrorContaining([&] { options.Check(); },
                        "--position_sigma applies to references paired by "
                        "name");
}

}  // namespace
}  // namespace uw
