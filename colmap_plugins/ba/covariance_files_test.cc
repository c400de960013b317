#include "colmap_plugins/ba/covariance_files.h"

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "colmap_plugins/ba/test_scene.h"
#include "common/util/error_testing.h"
#include "common/util/file.h"
#include "tests/support/process.h"

namespace uw {
namespace {

namespace fs = std::filesystem;

class CovarianceFilesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    test::TestSceneOptions options;
    options.num_lines = 2;
    options.images_per_line = 5;
    options.num_points = 300;
    scene_ = test::MakeTestScene(options);
    model_ = scene_.observed;
    AdjustWithNavigation(test::FixedIntrinsics(), scene_.priors, nullptr, {},
                         &model_);
    covariance_ = EstimateBundleCovariance(
        test::FixedIntrinsics(), scene_.priors, nullptr, {}, model_, {});
    folder_ = testing::FreshTestDir("covariance_files_test") / "cov";
  }

  test::TestScene scene_;
  Reconstruction model_;
  BundleCovariance covariance_;
  fs::path folder_;
};

TEST_F(CovarianceFilesTest, WritesTheFiveFilesAndReadsTheSidecarBack) {
  WriteCovarianceFiles(covariance_, model_, folder_);
  for (const char* name : {"covariance.bin", "covariance.json", "cameras.csv",
                           "points.ply", "uncertainty_map.png"}) {
    EXPECT_TRUE(fs::is_regular_file(folder_ / name)) << name;
  }
  const std::string csv = ReadFileToString(folder_ / "cameras.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'),
            static_cast<long>(model_.Images().size()) + 1);
  const std::string ply = ReadFileToString(folder_ / "points.ply");
  EXPECT_NE(ply.find("element vertex " +
                     std::to_string(covariance_.points.size()) + "\n"),
            std::string::npos);
  const BundleCovariance back =
      ReadCovarianceSidecar(folder_ / "covariance.bin", model_);
  ASSERT_EQ(back.images.size(), covariance_.images.size());
  ASSERT_EQ(back.points.size(), covariance_.points.size());
  EXPECT_EQ(back.images[3].rotation_center,
            covariance_.images[3].rotation_center);
  EXPECT_EQ(back.points[9].xyz, covariance_.points[9].xyz);
  EXPECT_EQ(back.pixel_sigma_px, covariance_.pixel_sigma_px);
}

TEST_F(CovarianceFilesTest, ASidecarOfAnotherModelIsRefused) {
  WriteCovarianceFiles(covariance_, model_, folder_);
  const fs::path sidecar = folder_ / "covariance.bin";
  // Another model: fewer points.
  Reconstruction other = model_;
  other.Points3D().pop_back();
  ExpectErrorContaining([&] { ReadCovarianceSidecar(sidecar, other); },
                        "belongs to another model");
  // The same model moved since (adjusted again).
  Reconstruction moved = model_;
  moved.Images()[2].cam_from_world.translation.x() += 0.01;
  ExpectErrorContaining([&] { ReadCovarianceSidecar(sidecar, moved); },
                        "image 3 is not where the covariance was computed");
  std::ofstream(folder_ / "not.bin") << "hello";
  ExpectErrorContaining(
      [&] { ReadCovarianceSidecar(folder_ / "not.bin", model_); },
      "not a uwmetric covariance sidecar");
}

TEST_F(CovarianceFilesTest, MeasuresOfAPointCovariance) {
  const Eigen::Matrix3d covariance =
      Eigen::Vector3d(4e-6, 1e-6, 9e-6).asDiagonal();
  EXPECT_NEAR(LargestAxisSigma(covariance), 3e-3, 1e-12);
  // (4/3) pi chi2^(3/2) sigma_x sigma_y sigma_z.
  EXPECT_NEAR(EllipsoidVolume95(covariance),
              4.0 / 3.0 * M_PI * std::pow(7.814727903251178, 1.5) * 6e-9,
              1e-18);
}

}  // namespace
}  // namespace uw
