#include "laserscale/laser_image_detection.h"

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "common/util/error.h"
#include "common/util/error_testing.h"
#include "laserscale/laser_setup.h"
#include "laserscale/spot_detector_testing.h"

namespace uw {
namespace {

namespace fs = std::filesystem;

fs::path MakeFolder(const std::string& name,
                    const std::vector<std::string>& files) {
  const fs::path dir = fs::path(::testing::TempDir()) / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  for (const std::string& file : files) std::ofstream(dir / file) << "x";
  return dir;
}

TEST(AuxiliaryImages, TheAutoConventionIsTheImageBesideElseTheNextOne) {
  const fs::path dir =
      MakeFolder("aux_auto", {"a.png", "a_aux.png", "b.png", "c.png"});
  const AuxiliaryImages aux(dir, {"a.png", "b.png", "c.png"}, "auto");
  EXPECT_EQ(aux.For(0), dir / "a_aux.png");
  EXPECT_EQ(aux.For(1), dir / "c.png");
  EXPECT_EQ(aux.For(2), dir / "b.png");  // the last: the previous one
}

TEST(AuxiliaryImages, ASingleImageWithoutItsAuxHasNone) {
  const fs::path dir = MakeFolder("aux_single", {"a.png"});
  EXPECT_TRUE(AuxiliaryImages(dir, {"a.png"}, "auto").For(0).empty());
  EXPECT_TRUE(AuxiliaryImages(dir, {"a.png"}, "none").For(0).empty());
}

TEST(AuxiliaryImages, ACsvNamesEachImagesAux) {
  const fs::path dir = MakeFolder("aux_csv", {"a.png", "b.png"});
  const fs::path csv = dir / "aux.csv";
  std::ofstream(csv) << "a.png,b.png\r\n\nb.png,a.png\n";
  const AuxiliaryImages aux(dir, {"a.png", "b.png", "c.png"}, csv.string());
  EXPECT_EQ(aux.For(0), dir / "b.png");
  EXPECT_EQ(aux.For(1), dir / "a.png");
  EXPECT_EQ(ErrorOf([&] { aux.For(2); }),
            csv.string() + ": no auxiliary image for c.png");
}

TEST(AuxiliaryImages, ABadCsvNamesTheFileAndLine) {
  const fs::path dir = MakeFolder("aux_bad_csv", {});
  const fs::path csv = dir / "aux.csv";
  std::ofstream(csv) << "a.png,b.png\nb.png\n";
  EXPECT_EQ(ErrorOf([&] { AuxiliaryImages(dir, {"a.png"}, csv.string()); }),
            csv.string() + ":2: expected image,aux");
  const std::string missing = (dir / "missing.csv").string();
  EXPECT_EQ(ErrorOf([&] { AuxiliaryImages(dir, {"a.png"}, missing); }),
            missing + ": cannot open the auxiliary list");
}

TEST(AuxiliaryImages, AuxNamesEndInAux) {
  EXPECT_TRUE(IsAuxiliaryImageName("L00002_aux.png"));
  EXPECT_TRUE(IsAuxiliaryImageName("dir/x_aux.jpg"));
  EXPECT_FALSE(IsAuxiliaryImageName("_aux.png"));
  EXPECT_FALSE(IsAuxiliaryImageName("L00002.png"));
  EXPECT_FALSE(IsAuxiliaryImageName("aux_L00002.png"));
}

TEST(LaserImageDetectionOptions, NeedsACamera) {
  LaserImageDetectionOptions options;
  EXPECT_EQ(ErrorOf([&] { options.Check(); }),
            "give --input_path or --camera_model and --camera_params");
  options.camera_model = "PINHOLE";
  options.camera_params = {500, 500, 160, 120};
  EXPECT_NO_THROW(options.Check());
  options.detector.min_detection_rate = 2.0;
  EXPECT_THROW(options.Check(), Error);
}

TEST(DetectLaserImages, NamesTheMissingSetUpAndTheBadCameraModel) {
  const fs::path dir = MakeFolder("detect_bad_inputs", {});
  const fs::path lasers = dir / "lasers.json";
  std::ofstream(lasers) << LasersJsonText({OneLaser()});
  LaserImageDetectionOptions options;
  options.images_dir = dir.string();
  options.lasers_path = lasers.string();
  options.setup_name = "no such set-up";
  options.camera_model = "FISHEYE_X";
  options.camera_params = {1.0};
  EXPECT_EQ(ErrorOf([&] { DetectLaserImages(options); }),
            lasers.string() + ": choose a set-up with --setup (1 set-ups)");
  options.setup_name.clear();
  EXPECT_EQ(ErrorOf([&] { DetectLaserImages(options); }),
            "--camera_model: unknown model 'FISHEYE_X'");
}

}  // namespace
}  // namespace uw
