#include "sim/survey_map.h"

#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include <opencv2/imgcodecs.hpp>

#include "colmap_plugins/scene/model_io.h"
#include "common/mesh/test_meshes.h"
#include "common/util/error.h"
#include "common/util/file.h"
#include "sim/navigation.h"

namespace uw::sim {
namespace {

namespace fs = std::filesystem;

// A 20 x 10 m floor rising 0.1 m per metre eastwards, and two dives of
// three images: dive 1 along y = 2, dive 2 along y = 7. Cameras sit at the
// vehicle positions; the navigation is the truth shifted 1.5 m south.
class SurveyMapTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ =
        fs::path(::testing::TempDir()) /
        ("survey_map_test_" +
         std::string(
             ::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "truth");

    TriangleMesh mesh;
    AddGrid(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(20, 0, 2),
            Eigen::Vector3d(0, 10, 0), 20, 10, &mesh);
    WritePly(mesh, dir_ / "truth" / "mesh.ply", "test world; metres");

    const std::vector<Eigen::Vector3d> positions = {
        {4, 2, 3}, {9, 2, 3}, {14, 2, 3}, {14, 7, 3}, {9, 7, 3}, {4, 7, 3}};
    Reconstruction truth;
    Camera camera;
    camera.camera_id = 1;
    camera.model_id = CameraModelId::kPinhole;
    camera.width = 640;
    camera.height = 480;
    camera.params = {500, 500, 320, 240};
    truth.AddCamera(camera);
    std::vector<NavigationRecord> true_records;
    std::vector<NavigationRecord> records;
    for (size_t i = 0; i < positions.size(); ++i) {
      Image image;
      image.image_id = static_cast<image_t>(i + 1);
      image.camera_id = 1;
      image.name = std::to_string(i) + ".png";
      // Looking down: camera z along world -z.
      image.cam_from_world.rotation =
          Eigen::Quaterniond(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()));
      image.cam_from_world.translation =
          -(image.cam_from_world.rotation * positions[i]);
      truth.AddImage(image);

      NavigationRecord record;
      record.image_name = image.name;
      record.time_s = static_cast<double>(i);
      record.dive = i < 3 ? 1 : 2;
      record.position = positions[i];
      true_records.push_back(record);
      record.position.y() -= 1.5;
      record.position_sigma = Eigen::Vector3d(1.0, 1.0, 0.02);
      records.push_back(record);
    }
    cameras_ = positions;
    WriteModel(truth, dir_ / "truth", ModelFormat::kText);
    WriteText("truth/nav.csv", NavigationCsv(true_records, 100.0));
    WriteText("nav.csv", NavigationCsv(records, 100.0));
  }
  void TearDown() override { fs::remove_all(dir_); }

  void WriteText(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name, std::ios::binary) << text;
  }

  // The message of the uw::Error that reading the folder throws.
  std::string ReadError() {
    try {
      ReadSurveyMapData(dir_);
    } catch (const Error& error) {
      return error.what();
    }
    ADD_FAILURE() << "no error reading " << dir_;
    return "";
  }

  fs::path dir_;
  std::vector<Eigen::Vector3d> cameras_;
};

cv::Vec3b PixelAt(const SurveyMap& map, const Eigen::Vector2d& xy) {
  const Eigen::Vector2d pixel = map.PixelFromWorld(xy);
  return map.image.at<cv::Vec3b>(static_cast<int>(std::lround(pixel.y())),
                                 static_cast<int>(std::lround(pixel.x())));
}

// Whether a pixel within `radius` of the world point has `color`, up to
// `tolerance` per channel (thin anti-aliased lines never cover a pixel
// whole).
bool ColorNear(const SurveyMap& map, const Eigen::Vector2d& xy,
               const cv::Vec3b& color, int radius = 1, int tolerance = 0) {
  const Eigen::Vector2d pixel = map.PixelFromWorld(xy);
  const int column = static_cast<int>(std::lround(pixel.x()));
  const int row = static_cast<int>(std::lround(pixel.y()));
  for (int r = row - radius; r <= row + radius; ++r) {
    for (int c = column - radius; c <= column + radius; ++c) {
      const cv::Vec3b pixel = map.image.at<cv::Vec3b>(r, c);
      if (std::abs(pixel[0] - color[0]) <= tolerance &&
          std::abs(pixel[1] - color[1]) <= tolerance &&
          std::abs(pixel[2] - color[2]) <= tolerance) {
        return true;
      }
    }
  }
  return false;
}

size_t CountColor(const cv::Mat& image, const cv::Vec3b& color) {
  size_t count = 0;
  for (int r = 0; r < image.rows; ++r) {
    for (int c = 0; c < image.cols; ++c) {
      count += image.at<cv::Vec3b>(r, c) == color;
    }
  }
  return count;
}

TEST_F(SurveyMapTest, ReadsTheFolder) {
  const SurveyMapData data = ReadSurveyMapData(dir_);
  EXPECT_EQ(data.mesh.triangles.size(), 400u);
  ASSERT_EQ(data.cameras.size(), 6u);
  ASSERT_EQ(data.true_track.size(), 6u);
  ASSERT_EQ(data.navigation.size(), 6u);
  for (size_t i = 0; i < 6; ++i) {
    EXPECT_EQ(data.cameras[i].image_name, std::to_string(i) + ".png");
    EXPECT_EQ(data.cameras[i].dive, i < 3 ? 1 : 2);
    EXPECT_LT((data.cameras[i].position_in_world - cameras_[i]).norm(), 1e-12);
    EXPECT_EQ(data.true_track[i].position_in_world, cameras_[i]);
    EXPECT_EQ(data.navigation[i].position_in_world.y(), cameras_[i].y() - 1.5);
    EXPECT_EQ(data.navigation[i].dive, i < 3 ? 1 : 2);
  }
}

TEST_F(SurveyMapTest, DotsTracksAndReliefLandWhereTheWorldPointsProject) {
  SurveyMapOptions options;
  options.width_px = 1000;
  const SurveyMap map = DrawSurveyMap(ReadSurveyMapData(dir_), options);
  ASSERT_EQ(map.image.type(), CV_8UC3);
  EXPECT_EQ(map.image.cols, 1000);
  // The map keeps the aspect (20 x 10 m plus margins), fills the width
  // and has the whole mesh; the legend is below it.
  const double aspect =
      static_cast<double>(map.map_area.width) / map.map_area.height;
  EXPECT_GT(aspect, 1.8);
  EXPECT_LT(aspect, 2.0);
  EXPECT_GT(map.map_area.width, 800);
  for (const Eigen::Vector2d& corner :
       {Eigen::Vector2d(0, 0), Eigen::Vector2d(20, 10)}) {
    const Eigen::Vector2d pixel = map.PixelFromWorld(corner);
    EXPECT_TRUE(map.map_area.contains(
        cv::Point(static_cast<int>(pixel.x()), static_cast<int>(pixel.y()))));
  }
  EXPECT_GT(map.image.rows, map.map_area.y + map.map_area.height);
  EXPECT_GT(map.pixels_per_metre, 30.0);

  for (size_t i = 0; i < cameras_.size(); ++i) {
    const cv::Vec3b expected = DiveColor(i < 3 ? 1 : 2);
    EXPECT_EQ(PixelAt(map, cameras_[i].head<2>()), expected) << "camera " << i;
    EXPECT_TRUE(map.map_area.contains(cv::Point(
        static_cast<int>(map.PixelFromWorld(cameras_[i].head<2>()).x()),
        static_cast<int>(map.PixelFromWorld(cameras_[i].head<2>()).y()))));
  }
  ASSERT_NE(DiveColor(1), DiveColor(2));
  // Tracks between consecutive images of a dive, not between dives.
  constexpr int kTolerance = 24;
  for (const size_t i : {0, 1, 3, 4}) {
    const Eigen::Vector2d middle =
        0.5 * (cameras_[i] + cameras_[i + 1]).head<2>();
    EXPECT_TRUE(ColorNear(map, middle, TrueTrackColor(), 1, kTolerance))
        << "segment " << i;
    EXPECT_TRUE(ColorNear(map, middle - Eigen::Vector2d(0, 1.5),
                          NavigationTrackColor(), 1, kTolerance))
        << "segment " << i;
  }
  const Eigen::Vector2d between_dives =
      0.5 * (cameras_[2] + cameras_[3]).head<2>();
  EXPECT_FALSE(
      ColorNear(map, between_dives, TrueTrackColor(), 3, 3 * kTolerance));
  EXPECT_FALSE(ColorNear(map, between_dives - Eigen::Vector2d(0, 1.5),
                         NavigationTrackColor(), 3, 3 * kTolerance));
  // North up and east right, checked without PixelFromWorld: dive 1 (south)
  // in the lower half of the frame, dive 2 (north) in the upper half, and
  // the relief, rising eastwards, lighter on the right.
  const cv::Rect upper(map.map_area.x, map.map_area.y, map.map_area.width,
                       map.map_area.height / 2);
  const cv::Rect lower = upper + cv::Point(0, map.map_area.height / 2);
  EXPECT_GT(CountColor(map.image(lower), DiveColor(1)), 0u);
  EXPECT_EQ(CountColor(map.image(upper), DiveColor(1)), 0u);
  EXPECT_GT(CountColor(map.image(upper), DiveColor(2)), 0u);
  EXPECT_EQ(CountColor(map.image(lower), DiveColor(2)), 0u);
  const int middle_row = map.map_area.y + map.map_area.height / 2;
  const cv::Vec3b left_pixel = map.image.at<cv::Vec3b>(
      middle_row, map.map_area.x + map.map_area.width / 10);
  const cv::Vec3b right_pixel = map.image.at<cv::Vec3b>(
      middle_row, map.map_area.x + 9 * map.map_area.width / 10);
  EXPECT_LT(left_pixel[0] + left_pixel[1] + left_pixel[2],
            right_pixel[0] + right_pixel[1] + right_pixel[2]);
  // Relief: the floor rises eastwards, so the colour ramp changes along x
  // and not along y; outside the mesh the map is plain.
  const cv::Vec3b west = PixelAt(map, {1, 5});
  const cv::Vec3b east = PixelAt(map, {19, 5});
  EXPECT_NE(west, east);
  EXPECT_EQ(PixelAt(map, {1, 0.5}), PixelAt(map, {1, 9.5}));
  EXPECT_NE(PixelAt(map, {1, 5}), PixelAt(map, {-0.3, 5}));
  EXPECT_EQ(PixelAt(map, {-0.3, 5}), PixelAt(map, {20.3, 5}));
  // Nothing but the map's overlays inside the frame: no legend dot there.
  const size_t dive1_pixels = CountColor(map.image(map.map_area), DiveColor(1));
  EXPECT_GT(dive1_pixels, 0u);
  EXPECT_GT(CountColor(map.image, DiveColor(1)), dive1_pixels)
      << "the legend shows the dive colour outside the map";
}

TEST_F(SurveyMapTest, LongWorldKeepsItsAspectAndFitsTheWidth) {
  SurveyMapData data = ReadSurveyMapData(dir_);
  data.mesh = TriangleMesh();
  AddGrid(Eigen::Vector3d(-150, 0, 0), Eigen::Vector3d(300, 0, 0),
          Eigen::Vector3d(0, 12, 10), 60, 4, &data.mesh);
  SurveyMapOptions options;
  options.width_px = 1600;
  const SurveyMap map = DrawSurveyMap(data, options);
  EXPECT_EQ(map.image.cols, 1600);
  EXPECT_LE(map.map_area.x + map.map_area.width, 1600);
  EXPECT_LT(map.image.rows, 800);
  const Eigen::Vector2d west = map.PixelFromWorld({-150, 0});
  const Eigen::Vector2d east = map.PixelFromWorld({150, 0});
  const Eigen::Vector2d north = map.PixelFromWorld({-150, 12});
  EXPECT_NEAR((east - west).norm() / (north - west).norm(), 300.0 / 12.0, 1e-9);
  EXPECT_GE(west.x(), map.map_area.x - 0.5);
  EXPECT_LE(east.x(), map.map_area.x + map.map_area.width - 0.5);
  for (const Eigen::Vector3d& camera : cameras_) {
    EXPECT_EQ(PixelAt(map, camera.head<2>()),
              DiveColor(camera.y() < 5 ? 1 : 2));
  }
}

TEST_F(SurveyMapTest, WritesThePngItDrawsAtomically) {
  SurveyMapOptions options;
  options.width_px = 900;
  options.title = "test survey";
  const fs::path out = dir_ / "maps" / "map.png";
  WriteSurveyMap(dir_, out, options);
  const std::string bytes = ReadFileToString(out);
  const cv::Mat decoded = cv::imdecode(
      std::vector<uchar>(bytes.begin(), bytes.end()), cv::IMREAD_COLOR);
  const SurveyMap map = DrawSurveyMap(ReadSurveyMapData(dir_), options);
  ASSERT_EQ(decoded.size(), map.image.size());
  EXPECT_EQ(decoded.cols, 900);
  EXPECT_EQ(cv::norm(decoded, map.image, cv::NORM_INF), 0.0);
  size_t files = 0;
  for ([[maybe_unused]] const auto& entry :
       fs::directory_iterator(out.parent_path())) {
    ++files;
  }
  EXPECT_EQ(files, 1u);  // no temporary left behind

  const fs::path jpeg = dir_ / "map.JPG";
  WriteSurveyMap(dir_, jpeg, options);
  EXPECT_EQ(ReadFileToString(jpeg).substr(0, 2), "\xFF\xD8");

  try {
    WriteSurveyMap(dir_, dir_ / "map.tif", options);
    ADD_FAILURE() << "no error for .tif";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("map.tif"), std::string::npos);
  }
  EXPECT_FALSE(fs::exists(dir_ / "map.tif"));
  options.width_px = 100;
  EXPECT_THROW(WriteSurveyMap(dir_, dir_ / "small.png", options), Error);
  EXPECT_FALSE(fs::exists(dir_ / "small.png"));
}

TEST_F(SurveyMapTest, MissingFilesAreNamed) {
  for (const std::string name :
       {"nav.csv", "truth/nav.csv", "truth/images.txt", "truth/mesh.ply"}) {
    const fs::path path = dir_ / name;
    const fs::path moved = path.string() + ".away";
    fs::rename(path, moved);
    const std::string message = ReadError();
    EXPECT_NE(message.find(path.string() + ": missing"), std::string::npos)
        << message;
    fs::rename(moved, path);
  }
  fs::remove_all(dir_ / "truth");
  const std::string message = ReadError();
  EXPECT_NE(message.find("truth"), std::string::npos) << message;
  fs::remove_all(dir_);
  EXPECT_NE(ReadError().find("not a folder"), std::string::npos);
}

TEST_F(SurveyMapTest, MalformedNavigationRowsNameFileAndLine) {
  const std::string header =
      "# comment\n"
      "image_name,time,dive,x,y,z,roll,pitch,yaw,std_x,std_y,std_z,std_roll,"
      "std_pitch,std_yaw\n";
  const std::string good = "0.png,0,1,4,2,3,0,0,0,1,1,0.02,0.05,0.05,0.2\n";
  const std::string path = (dir_ / "nav.csv").string();
  const struct {
    std::string text;
    std::string message;
  } cases[] = {
      {header + good + "1.png,1,1,9,2\n",
       path + ":4: expected 15 fields, got 5"},
      {header + good + "\n1.png,1,1,9,abc,3,0,0,0,1,1,0.02,0.05,0.05,0.2\n",
       path + ":5: y must be a finite number, got 'abc'"},
      {header + "1.png,1,1,9,2,nan,0,0,0,1,1,0.02,0.05,0.05,0.2\n",
       path + ":3: z must be a finite number"},
      {header + "1.png,1,0,9,2,3,0,0,0,1,1,0.02,0.05,0.05,0.2\n",
       path + ":3: dive must be an integer >= 1, got '0'"},
      {header + "1.png,1,1.5,9,2,3,0,0,0,1,1,0.02,0.05,0.05,0.2\n",
       path + ":3: dive must be an integer"},
      {header + ",1,1,9,2,3,0,0,0,1,1,0.02,0.05,0.05,0.2\n",
       path + ":3: empty image_name"},
      {header + good + good,
       path + ":4: image '0.png' already has a row at line 3"},
      {"# no header\n" + good, path + ":2: expected the header"},
      {header, path + ": no navigation rows"},
      {"# only comments\n", path + ": no header row"},
  };
  for (const auto& test : cases) {
    WriteText("nav.csv", test.text);
    const std::string message = ReadError();
    EXPECT_NE(message.find(test.message), std::string::npos)
        << "got: " << message << "\nfor:\n"
        << test.text;
  }
  // Blank lines, CRLF and spaces around fields are fine.
  WriteText("nav.csv", "\r\n" + header +
                           " 0.png , 0, 1, 4, 2, 3,0,0,0,1,1,0.02,0.05,"
                           "0.05,0.2\r\n\r\n");
  const SurveyMapData data = ReadSurveyMapData(dir_);
  ASSERT_EQ(data.navigation.size(), 1u);
  EXPECT_EQ(data.navigation[0].image_name, "0.png");
  EXPECT_EQ(data.navigation[0].position_in_world, Eigen::Vector3d(4, 2, 3));
}

TEST_F(SurveyMapTest, ImageWithoutTrueNavigationIsAnError) {
  std::string truth = ReadFileToString(dir_ / "truth" / "nav.csv");
  truth = truth.substr(0, truth.rfind("5.png"));
  WriteText("truth/nav.csv", truth);
  const std::string message = ReadError();
  EXPECT_NE(message.find("images.txt: image '5.png' has no row in"),
            std::string::npos)
      << message;
}

}  // namespace
}  // namespace uw::sim
