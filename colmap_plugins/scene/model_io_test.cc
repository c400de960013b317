#include "colmap_plugins/scene/model_io.h"

#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <random>

#include "colmap_plugins/scene/model_stats.h"
#include "common/util/error.h"
#include "common/util/file.h"
#include "tests/support/process.h"

namespace uw {
namespace {

namespace fs = std::filesystem;

fs::path TestDir() { return testing::FreshTestDir("uw_model_io_test"); }

// A small but complete model: two cameras of different models, three
// images with observed and unobserved 2D points, points with tracks, and
// awkward doubles that only survive a round trip with 17 digits.
Reconstruction MakeModel(std::mt19937* rng) {
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Reconstruction model;
  model.AddCamera({3,
                   CameraModelId::kSimpleRadial,
                   640,
                   480,
                   {500.1234567890123, 320.5, 240.25, -0.0123456789}});
  model.AddCamera({1,
                   CameraModelId::kOpenCV,
                   1024,
                   768,
                   {800.0, 801.0, 512.0, 384.0, 0.01, -0.002, 1e-4, -2e-5}});
  for (image_t image_id : {5u, 2u, 9u}) {
    Image image;
    image.image_id = image_id;
    image.camera_id = image_id == 2 ? 1 : 3;
    image.name = "dive1/img_" + std::to_string(image_id) + ".png";
    image.cam_from_world.rotation =
        Eigen::Quaterniond(1.0, 0.1 * uniform(*rng), 0.1 * uniform(*rng),
                           0.1 * uniform(*rng))
            .normalized();
    image.cam_from_world.translation =
        Eigen::Vector3d(uniform(*rng), uniform(*rng), 3.0 + uniform(*rng));
    for (int k = 0; k < 4; ++k) {
      Point2D point2D;
      point2D.xy =
          Eigen::Vector2d(300 + 100 * uniform(*rng), 200 + 100 * uniform(*rng));
      image.points2D.push_back(point2D);
    }
    model.AddImage(image);
  }
  // Point 7 is seen by images 5 and 2, point 4 by 5, 2 and 9.
  const std::vector<std::pair<point3D_t, std::vector<TrackElement>>> tracks = {
      {7, {{5, 0}, {2, 1}}}, {4, {{5, 2}, {2, 3}, {9, 0}}}};
  for (const auto& [point3D_id, track] : tracks) {
    Point3D point3D;
    point3D.point3D_id = point3D_id;
    point3D.xyz = Eigen::Vector3d(uniform(*rng), uniform(*rng), uniform(*rng));
    point3D.color = {12, 200, 255};
    point3D.error = 0.1 + 0.01 * uniform(*rng);
    point3D.track = track;
    for (const TrackElement& element : track) {
      model.Images()[element.image_id == 5   ? 0
                     : element.image_id == 2 ? 1
                                             : 2]
          .points2D[element.point2D_idx]
          .point3D_id = point3D_id;
    }
    model.AddPoint3D(point3D);
  }
  return model;
}

Reconstruction MakeRigModel(std::mt19937* rng) {
  Reconstruction model = MakeModel(rng);
  model.layout = ModelLayout::kColmap4;
  Rig rig;
  rig.rig_id = 1;
  rig.ref_sensor = SensorId{SensorType::kCamera, 3};
  RigSensor second;
  second.sensor_id = {SensorType::kCamera, 1};
  second.sensor_from_rig = Rigid3d{
      Eigen::Quaterniond(0.9999, 0.001, -0.002, 0.003), {-0.19, 0.001, 0.007}};
  rig.non_ref_sensors.push_back(second);
  rig.non_ref_sensors.push_back({{SensorType::kImu, 4}, std::nullopt});
  model.AddRig(rig);
  Frame frame;
  frame.frame_id = 1;
  frame.rig_id = 1;
  frame.rig_from_world = model.Images()[0].cam_from_world;
  frame.data_ids = {{{SensorType::kCamera, 3}, 5},
                    {{SensorType::kCamera, 1}, 2}};
  model.AddFrame(frame);
  // Image 9 in a frame of its own: every image of a 4.x model has a frame.
  frame.frame_id = 2;
  frame.rig_from_world = model.Images()[2].cam_from_world;
  frame.data_ids = {{{SensorType::kCamera, 3}, 9}};
  model.AddFrame(frame);
  return model;
}

void ExpectSameModel(const Reconstruction& a, const Reconstruction& b) {
  EXPECT_EQ(CamerasBinary(a), CamerasBinary(b));
  EXPECT_EQ(ImagesBinary(a), ImagesBinary(b));
  EXPECT_EQ(Points3DBinary(a), Points3DBinary(b));
  EXPECT_EQ(RigsBinary(a), RigsBinary(b));
  EXPECT_EQ(FramesBinary(a), FramesBinary(b));
  EXPECT_EQ(a.layout, b.layout);
}

std::string ErrorOf(const std::function<void()>& body) {
  try {
    body();
  } catch (const Error& error) {
    return error.what();
  }
  return "(no error)";
}

TEST(ModelIo, BinaryRoundTripIsByteIdenticalAndKeepsOrder) {
  std::mt19937 rng(1);
  const Reconstruction model = MakeModel(&rng);
  const fs::path dir = TestDir();
  WriteModel(model, dir, ModelFormat::kBinary);
  const ModelFiles files = DetectModelFiles(dir);
  EXPECT_EQ(files.format, ModelFormat::kBinary);
  EXPECT_EQ(files.layout, ModelLayout::kColmap3);
  const Reconstruction read = ReadModel(dir);
  ExpectSameModel(model, read);
  // File order, not id order.
  EXPECT_EQ(read.Cameras()[0].camera_id, 3u);
  EXPECT_EQ(read.Images()[1].image_id, 2u);
  EXPECT_FALSE(fs::exists(dir / "rigs.bin"));
}

TEST(ModelIo, TextRoundTripKeepsEveryBit) {
  std::mt19937 rng(2);
  const Reconstruction model = MakeModel(&rng);
  const fs::path dir = TestDir();
  WriteModel(model, dir, ModelFormat::kText);
  EXPECT_EQ(DetectModelFiles(dir).format, ModelFormat::kText);
  const Reconstruction read = ReadModel(dir);
  // Quaternions pass through the writer's normalisation, which changes at
  // most the last bits of an already unit quaternion.
  ASSERT_EQ(read.Images().size(), model.Images().size());
  for (size_t i = 0; i < model.Images().size(); ++i) {
    EXPECT_NEAR(read.Images()[i].cam_from_world.rotation.angularDistance(
                    model.Images()[i].cam_from_world.rotation),
                0.0, 1e-15);
    EXPECT_EQ(read.Images()[i].cam_from_world.translation,
              model.Images()[i].cam_from_world.translation);
    EXPECT_EQ(read.Images()[i].name, model.Images()[i].name);
  }
  EXPECT_EQ(CamerasBinary(read), CamerasBinary(model));
  EXPECT_EQ(Points3DBinary(read), Points3DBinary(model));
}

TEST(ModelIo, ColmapFourLayoutRoundTripsInBothFormats) {
  std::mt19937 rng(3);
  const Reconstruction model = MakeRigModel(&rng);
  for (const ModelFormat format : {ModelFormat::kBinary, ModelFormat::kText}) {
    const fs::path dir = TestDir();
    WriteModel(model, dir, format);
    const std::string ext = format == ModelFormat::kBinary ? ".bin" : ".txt";
    EXPECT_TRUE(fs::exists(dir / ("rigs" + ext)));
    EXPECT_TRUE(fs::exists(dir / ("frames" + ext)));
    const Reconstruction read = ReadModel(dir);
    EXPECT_EQ(read.layout, ModelLayout::kColmap4);
    EXPECT_EQ(RigsBinary(read), RigsBinary(model));
    EXPECT_EQ(FramesBinary(read), FramesBinary(model));
  }
}

// The examples of COLMAP's doc/format.rst (HEAD) for the 4.x files.
TEST(ModelIo, ReadsColmapDocumentationExamplesOfRigsAndFrames) {
  const std::string rigs =
      "# Rig calib list with one line of data per calib:\n"
      "#   RIG_ID, NUM_SENSORS, REF_SENSOR_TYPE, REF_SENSOR_ID, SENSORS[] as "
      "(SENSOR_TYPE, SENSOR_ID, HAS_POSE, [QW, QX, QY, QZ, TX, TY, TZ])\n"
      "# Number of rigs: 1\n"
      "1 2 CAMERA 1 CAMERA 2 1 -0.9999701516465348 -0.0011120266840749639 "
      "-0.0075347911527510894 0.0012985125893421306 -0.19316906391350164 "
      "0.00085222218993398979 0.0070758955539026785\n"
      "2 1 CAMERA 3\n";
  const std::string frames =
      "# Frame list with one line of data per frame:\n"
      "# Number of frames: 151\n"
      "1 1 0.99801363919752195 0.040985139360073107 0.041890917712361225 "
      "-0.023111584553400576 -5.2666546897987896 -0.17120007823690631 "
      "0.12300519697527648 2 CAMERA 1 1 CAMERA 2 2\n"
      "2 2 0.99816472047267968 0.037605501383281774 0.043101511724657163 "
      "-0.019881568259519072 -5.1956060695789192 -0.20794508616745555 "
      "0.14967533910764824 1 CAMERA 3 3\n";
  Reconstruction model;
  ParseRigsText(rigs, "rigs.txt", &model);
  ParseFramesText(frames, "frames.txt", &model);
  ASSERT_EQ(model.Rigs().size(), 2u);
  EXPECT_EQ(model.Rigs()[0].NumSensors(), 2u);
  ASSERT_TRUE(model.Rigs()[0].non_ref_sensors[0].sensor_from_rig.has_value());
  EXPECT_DOUBLE_EQ(
      model.Rigs()[0].non_ref_sensors[0].sensor_from_rig->translation.x(),
      -0.19316906391350164);
  EXPECT_EQ(model.Rigs()[1].NumSensors(), 1u);
  ASSERT_EQ(model.Frames().size(), 2u);
  EXPECT_EQ(model.Frames()[0].data_ids.size(), 2u);
  EXPECT_EQ(model.Frames()[1].data_ids[0].id, 3u);
  // Written back, the data lines are the documentation's lines.
  const std::string rigs_out = RigsText(model);
  EXPECT_NE(rigs_out.find("\n2 1 CAMERA 3\n"), std::string::npos);
  EXPECT_NE(
      FramesText(model).find("\n2 2 0.99816472047267968 0.037605501383281774 "
                             "0.043101511724657163 -0.019881568259519072 "
                             "-5.1956060695789192 -0.20794508616745555 "
                             "0.14967533910764824 1 CAMERA 3 3\n"),
      std::string::npos);
}

// Cutting images.bin at every byte must give an error naming the file and a
// byte offset, never a crash or a silently shorter model.
TEST(ModelIo, TruncatedBinaryFilesAreRejectedAtEveryLength) {
  std::mt19937 rng(4);
  const Reconstruction model = MakeRigModel(&rng);
  const std::vector<std::pair<const char*, std::string>> files = {
      {"cameras.bin", CamerasBinary(model)},
      {"images.bin", ImagesBinary(model)},
      {"points3D.bin", Points3DBinary(model)},
      {"rigs.bin", RigsBinary(model)},
      {"frames.bin", FramesBinary(model)}};
  using Parser =
      void (*)(const std::string&, const std::string&, Reconstruction*);
  const std::vector<Parser> parsers = {ParseCamerasBinary, ParseImagesBinary,
                                       ParsePoints3DBinary, ParseRigsBinary,
                                       ParseFramesBinary};
  for (size_t f = 0; f < files.size(); ++f) {
    const std::string& bytes = files[f].second;
    for (size_t length = 0; length < bytes.size(); ++length) {
      Reconstruction partial;
      try {
        parsers[f](bytes.substr(0, length), files[f].first, &partial);
        ADD_FAILURE() << files[f].first << " cut at " << length
                      << " bytes was accepted";
      } catch (const Error& error) {
        const std::string message = error.what();
        EXPECT_EQ(message.rfind(std::string(files[f].first) + ": byte ", 0), 0u)
            << message;
      }
    }
    // Trailing garbage is rejected too.
    Reconstruction extended;
    EXPECT_THROW(parsers[f](bytes + "x", files[f].first, &extended), Error);
  }
}

TEST(ModelIo, BinaryDuplicateIdsAndSensorTypesNameFileAndByte) {
  std::mt19937 rng(10);
  const Reconstruction model = MakeRigModel(&rng);
  const std::string cameras = CamerasBinary(model);
  // Two cameras (SIMPLE_RADIAL first): give the second the first one's id.
  std::string duplicated = cameras;
  std::memcpy(&duplicated[8 + 4 + 4 + 8 + 8 + 4 * 8], &cameras[8], 4);
  Reconstruction read;
  std::string message = ErrorOf(
      [&] { ParseCamerasBinary(duplicated, "sparse/cameras.bin", &read); });
  EXPECT_NE(message.find("sparse/cameras.bin: byte "), std::string::npos)
      << message;
  EXPECT_NE(message.find("duplicate camera id 3"), std::string::npos)
      << message;
  // The reference sensor type of the first rig: after count, id, #sensors.
  std::string rigs = RigsBinary(model);
  const int32_t robot = 5;
  std::memcpy(&rigs[8 + 4 + 4], &robot, 4);
  Reconstruction read_rigs;
  message = ErrorOf([&] { ParseRigsBinary(rigs, "rigs.bin", &read_rigs); });
  EXPECT_NE(message.find("rigs.bin: byte 20: unknown sensor type 5"),
            std::string::npos)
      << message;
}

TEST(ModelIo, ColmapFourModelsNeedEveryImageInExactlyOneFrame) {
  std::mt19937 rng(11);
  Reconstruction model = MakeRigModel(&rng);
  model.Frames()[1].data_ids.clear();
  const fs::path dir = TestDir();
  WriteModel(model, dir / "none", ModelFormat::kBinary);
  EXPECT_NE(ErrorOf([&] {
              ReadModel(dir / "none");
            }).find("image 9 (dive1/img_9.png) is in no frame"),
            std::string::npos);
  model = MakeRigModel(&rng);
  model.Frames()[1].data_ids[0].id = 5;  // image 5 in frames 1 and 2
  WriteModel(model, dir / "twice", ModelFormat::kText);
  EXPECT_NE(ErrorOf([&] {
              ReadModel(dir / "twice");
            }).find("image 5 (dive1/img_5.png) is in frames 1 and 2"),
            std::string::npos);
  model = MakeRigModel(&rng);
  model.Rigs()[0].ref_sensor->id = 77;
  WriteModel(model, dir / "rig", ModelFormat::kBinary);
  EXPECT_NE(
      ErrorOf([&] { ReadModel(dir / "rig"); }).find("rig 1 names camera 77"),
      std::string::npos);
}

TEST(ModelIo, NeverWritesIntoAnotherModelsFolder) {
  std::mt19937 rng(12);
  const fs::path dir = TestDir();
  WriteModel(MakeRigModel(&rng), dir, ModelFormat::kBinary);
  // A 3.x model over a 4.x one would leave rigs.bin and frames.bin behind
  // and be read back as a mixed model.
  const std::string message =
      ErrorOf([&] { WriteModel(MakeModel(&rng), dir, ModelFormat::kBinary); });
  EXPECT_NE(message.find("rigs.bin: belongs to another model"),
            std::string::npos)
      << message;
  EXPECT_EQ(ReadModel(dir).layout, ModelLayout::kColmap4);
  // Text beside binary would be shadowed by it on reading.
  EXPECT_THROW(WriteModel(MakeRigModel(&rng), dir, ModelFormat::kText), Error);
  // Replacing a model of the same layout and format is fine.
  EXPECT_NO_THROW(WriteModel(MakeRigModel(&rng), dir, ModelFormat::kBinary));
}

TEST(ModelIo, CorruptCountIsRejectedBeforeAllocating) {
  std::string bytes(8, '\xff');  // 2^64 - 1 cameras
  Reconstruction model;
  try {
    ParseCamerasBinary(bytes, "cameras.bin", &model);
    FAIL();
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("exceeds the remaining bytes"),
              std::string::npos)
        << error.what();
  }
}

TEST(ModelIo, WrongParameterCountNamesLineModelAndCounts) {
  Reconstruction model;
  const std::string message = ErrorOf([&] {
    ParseCamerasText(
        "# comment\n1 PINHOLE 640 480 500 500 320 240\n"
        "2 SIMPLE_RADIAL 640 480 500 320 240\n",
        "sparse/cameras.txt", &model);
  });
  EXPECT_NE(message.find("sparse/cameras.txt:3:"), std::string::npos)
      << message;
  EXPECT_NE(message.find("SIMPLE_RADIAL expects 4"), std::string::npos)
      << message;
  EXPECT_NE(message.find("got 3"), std::string::npos) << message;
}

TEST(ModelIo, MalformedTextLinesNameFileAndLine) {
  struct Case {
    const char* file;
    std::string text;
    const char* expected;
  };
  const std::vector<Case> cases = {
      {"images.txt", "1 1 0 0 0 0 0 0 1 a.png\n1.0 2.0\n", "images.txt:2:"},
      {"images.txt", "1 1 0 0 0 0 0 x 1 a.png\n\n", "images.txt:1:"},
      {"images.txt", "1 1 0 0 0 0 0 0 1 a.png\n", "missing POINTS2D"},
      {"images.txt", "1 1 0 0 0 nan 0 0 1 a.png\n\n", "not finite"},
      {"points3D.txt", "\n\n1 0 0 0 1 2 300 0.5 1 0\n", "points3D.txt:3:"},
      {"points3D.txt", "1 0 0 0 1 2 3 0.5 1\n", "points3D.txt:1:"},
      {"cameras.txt", "1 NOT_A_MODEL 640 480 1\n", "unknown camera model"},
      {"cameras.txt", "1 PINHOLE 640 480 1 1 1 1\n1 PINHOLE 640 480 1 1 1 1\n",
       "cameras.txt:2: duplicate camera id 1"},
      {"frames.txt", "1 1 1 0 0 0 0 0 0 1 CAMERA 1\n", "frames.txt:1:"},
      {"rigs.txt", "1 2 CAMERA 1 ROBOT 2 0\n", "unknown sensor type"},
  };
  for (const Case& c : cases) {
    Reconstruction model;
    model.AddCamera({1, CameraModelId::kPinhole, 640, 480, {1, 1, 1, 1}});
    const std::string message = ErrorOf([&] {
      const std::string name = c.file;
      if (name == "images.txt") ParseImagesText(c.text, c.file, &model);
      if (name == "points3D.txt") ParsePoints3DText(c.text, c.file, &model);
      if (name == "cameras.txt") {
        Reconstruction empty;
        ParseCamerasText(c.text, c.file, &empty);
      }
      if (name == "frames.txt") ParseFramesText(c.text, c.file, &model);
      if (name == "rigs.txt") ParseRigsText(c.text, c.file, &model);
    });
    EXPECT_NE(message.find(c.expected), std::string::npos)
        << c.file << ": '" << c.text << "' gave: " << message;
  }
}

TEST(ModelIo, BrokenReferencesAreRejectedOnRead) {
  std::mt19937 rng(5);
  Reconstruction model = MakeModel(&rng);
  model.Points3D()[0].track[0].point2D_idx = 3;  // does not observe point 7
  const fs::path dir = TestDir();
  WriteModel(model, dir, ModelFormat::kBinary);
  const std::string message = ErrorOf([&] { ReadModel(dir); });
  EXPECT_NE(message.find("point3D 7 track refers to point2D 3 of image 5"),
            std::string::npos)
      << message;
}

TEST(ModelIo, MissingOrPartialModelIsRejected) {
  const fs::path dir = TestDir();
  EXPECT_THROW(DetectModelFiles(dir / "nope"), Error);
  EXPECT_THROW(DetectModelFiles(dir), Error);
  std::mt19937 rng(6);
  WriteModel(MakeModel(&rng), dir, ModelFormat::kBinary);
  std::ofstream(dir / "rigs.bin") << "";
  EXPECT_NE(ErrorOf([&] { DetectModelFiles(dir); }).find("frames.bin"),
            std::string::npos);
}

TEST(ModelIo, FailedWriteLeavesNothingBehind) {
  std::mt19937 rng(7);
  const Reconstruction model = MakeModel(&rng);
  const fs::path dir = TestDir();
  // A directory where points3D.bin should go: the last file cannot be
  // installed, so none may be.
  fs::create_directories(dir / "points3D.bin");
  EXPECT_THROW(WriteModel(model, dir, ModelFormat::kBinary), Error);
  std::vector<std::string> left;
  for (const auto& entry : fs::directory_iterator(dir)) {
    left.push_back(entry.path().filename().string());
  }
  EXPECT_EQ(left, std::vector<std::string>{"points3D.bin"});
}

TEST(ModelStats, CountsAndMeansFollowColmapDefinitions) {
  std::mt19937 rng(8);
  Reconstruction model = MakeModel(&rng);
  model.Points3D()[1].error = -1.0;  // unknown errors are not averaged
  const ModelStats stats = ComputeModelStats(model);
  EXPECT_EQ(stats.num_cameras, 2u);
  EXPECT_EQ(stats.num_reg_images, 3u);
  EXPECT_EQ(stats.num_points3D, 2u);
  EXPECT_EQ(stats.num_observations, 5u);
  EXPECT_DOUBLE_EQ(stats.mean_track_length, 2.5);
  EXPECT_DOUBLE_EQ(stats.mean_observations_per_image, 5.0 / 3.0);
  EXPECT_DOUBLE_EQ(stats.mean_reprojection_error, model.Points3D()[0].error);
  EXPECT_EQ(FormatModelAnalyzerReport(stats),
            "Cameras: 2\nImages: 3\nRegistered images: 3\nPoints: 2\n"
            "Observations: 5\nMean track length: 2.500000\n"
            "Mean observations per image: 1.666667\n"
            "Mean reprojection error: " +
                std::to_string(model.Points3D()[0].error) + "px\n");
}

TEST(ModelStats, RecomputedErrorsMatchKnownOffsets) {
  // Observations placed at the exact projection plus a known offset must
  // give that offset back as the error.
  std::mt19937 rng(9);
  Reconstruction model = MakeModel(&rng);
  const double offset = 0.25;
  for (Point3D& point3D : model.Points3D()) {
    point3D.xyz = Eigen::Vector3d(0.1, -0.2, 0.3);
    for (const TrackElement& element : point3D.track) {
      for (Image& image : model.Images()) {
        if (image.image_id != element.image_id) continue;
        const Camera& camera = *model.FindCamera(image.camera_id);
        image.points2D[element.point2D_idx].xy =
            camera.ImgFromCam(image.cam_from_world * point3D.xyz) +
            Eigen::Vector2d(0.6 * offset, 0.8 * offset);
      }
    }
    point3D.error = offset;
  }
  const ReprojectionErrors errors = RecomputeReprojectionErrors(model);
  EXPECT_NEAR(errors.mean_point_error, offset, 1e-12);
  EXPECT_NEAR(errors.mean_observation_error, offset, 1e-12);
  EXPECT_LT(errors.max_stored_error_difference, 1e-12);
  EXPECT_EQ(errors.num_observations, 5u);
  EXPECT_EQ(errors.num_behind_camera, 0u);
}

}  // namespace
}  // namespace uw
