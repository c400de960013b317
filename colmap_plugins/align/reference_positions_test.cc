#include "colmap_plugins/align/reference_positions.h"

#include <gtest/gtest.h>

#include <fstream>

#include "common/util/error.h"
#include "tests/support/process.h"

namespace uw {
namespace {

namespace fs = std::filesystem;

fs::path WriteFile(const std::string& text) {
  const fs::path path =
      testing::FreshTestDir("uw_reference_positions_test") / "ref.txt";
  std::ofstream(path) << text;
  return path;
}

std::string ErrorOf(const fs::path& path) {
  try {
    ReadReferencePositions(path);
  } catch (const Error& error) {
    return error.what();
  }
  return "no error";
}

TEST(ReadReferencePositions, ReadsColmapsFormat) {
  const fs::path path = WriteFile(
      "# name x y z\n00000.png 1 2 3\n\n  00001.png\t-1.5e2 0 4.25  \n");
  const std::vector<ReferencePosition> references =
      ReadReferencePositions(path);
  ASSERT_EQ(references.size(), 2u);
  EXPECT_EQ(references[1].image_name, "00001.png");
  EXPECT_EQ(references[1].position, Eigen::Vector3d(-150, 0, 4.25));
  EXPECT_FALSE(references[0].covariance.has_value());
}

TEST(ReadReferencePositions, NamesTheLineOfABadRecord) {
  EXPECT_NE(ErrorOf(WriteFile("a.png 1 2 3\nb.png 1 2\n"))
                .find(":2: expected 'image_name x y z', got 3 fields"),
            std::string::npos);
  EXPECT_NE(ErrorOf(WriteFile("a.png 1 2 nan\n"))
                .find(":1: 'nan' is not a finite number"),
            std::string::npos);
  EXPECT_NE(ErrorOf(WriteFile("a.png 1 2 3x\n")).find("'3x' is not a finite"),
            std::string::npos);
  EXPECT_NE(ErrorOf(WriteFile("a.png 1 2 3\na.png 1 2 3\n"))
                .find(":2: image 'a.png' is listed twice"),
            std::string::npos);
  EXPECT_NE(ErrorOf("/nonexistent/ref.txt").find("/nonexistent/ref.txt"),
            std::string::npos);
}

Reconstruction ThreeImages() {
  Reconstruction model;
  for (image_t id = 1; id <= 4; ++id) {
    Image image;
    image.image_id = id;
    image.name = "img" + std::to_string(5 - id) + ".png";
    image.cam_from_world.translation = Eigen::Vector3d(id, 0, 0);
    model.AddImage(image);
  }
  return model;
}

TEST(MatchReferencePositions, PairsByNameInNameOrder) {
  std::vector<ReferencePosition> references = {
      {"img1.png", {1, 0, 0}, Eigen::Matrix3d::Identity()},
      {"other.png", {2, 0, 0}, std::nullopt},
      {"img3.png", {3, 0, 0}, Eigen::Matrix3d::Identity()},
      {"img2.png", {4, 0, 0}, Eigen::Matrix3d::Identity()}};
  ReferenceMatch match =
      MatchReferencePositions(ThreeImages(), references, "ref.txt");
  EXPECT_EQ(match.image_names,
            (std::vector<std::string>{"img1.png", "img2.png", "img3.png"}));
  EXPECT_EQ(match.reference_positions[1], Eigen::Vector3d(4, 0, 0));
  // img1.png is image 4: centre -(4, 0, 0).
  EXPECT_EQ(match.model_centres[0], Eigen::Vector3d(-4, 0, 0));
  EXPECT_EQ(match.unknown_names, std::vector<std::string>{"other.png"});
  EXPECT_EQ(match.covariances.size(), 3u);
  // One singular covariance: no weighting at all.
  references[3].covariance = Eigen::Matrix3d::Zero();
  match = MatchReferencePositions(ThreeImages(), references, "ref.txt");
  EXPECT_TRUE(match.covariances.empty());
  EXPECT_EQ(match.num_without_covariance, 1u);
}

TEST(MatchReferencePositions, FewerThanThreeMatchesIsAnError) {
  const std::vector<ReferencePosition> references = {
      {"images/img1.png", {1, 0, 0}, std::nullopt},
      {"images/img2.png", {2, 0, 0}, std::nullopt},
      {"img3.png", {3, 0, 0}, std::nullopt}};
  try {
    MatchReferencePositions(ThreeImages(), references, "ref.txt");
    ADD_FAILURE() << "no error";
  } catch (const Error& error) {
    EXPECT_EQ(std::string(error.what()),
              "ref.txt: 1 of its 3 positions name an image of the model (4 "
              "images); at least 3 are needed (e.g. reference "
              "'images/img1.png', model 'img1.png')");
  }
}

}  // namespace
}  // namespace uw
