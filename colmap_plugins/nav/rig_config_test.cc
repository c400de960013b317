#include "colmap_plugins/nav/rig_config.h"

#include <fstream>

#include <gtest/gtest.h>
#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "common/util/error.h"
#include "tests/support/process.h"

namespace uw {
namespace {

namespace fs = std::filesystem;

RigConfig ThreeCameras() {
  RigConfig rig;
  rig.cameras.resize(3);
  rig.cameras[0].camera_id = 1;
  rig.cameras[0].image_prefix = "cam1/";
  rig.cameras[1].camera_id = 2;
  rig.cameras[1].image_prefix = "cam2/";
  rig.cameras[1].cam_from_rig.rotation = Eigen::Quaterniond(
      Eigen::AngleAxisd(0.1, Eigen::Vector3d(1, 2, 3).normalized()));
  rig.cameras[1].cam_from_rig.translation = Eigen::Vector3d(-0.3, 0.01, 0);
  rig.cameras[1].rotation_sigma_deg = 0.05;
  rig.cameras[1].translation_sigma_m = 0.002;
  rig.cameras[1].time_offset_s = 0.02;
  rig.cameras[2].camera_id = 7;
  rig.cameras[2].image_prefix = "left/cam3_";
  rig.cameras[2].time_offset_s = -0.045;
  return rig;
}

class RigConfigTest : public ::testing::Test {
 protected:
  void SetUp() override {
    path_ = testing::FreshTestDir("uw_rig_config_test") / "rig.json";
  }

  RigConfig Read(const nlohmann::json& json) {
    std::ofstream(path_) << json.dump(1);
    return ReadRigConfig(path_);
  }

  std::string Error(const nlohmann::json& json) {
    try {
      Read(json);
    } catch (const uw::Error& error) {
      return error.what();
    }
    return "no error";
  }

  fs::path path_;
};

TEST_F(RigConfigTest, WrittenTextReadsBack) {
  const RigConfig rig = ThreeCameras();
  const std::string text = RigConfigJsonText(rig);
  std::ofstream(path_) << text;
  const RigConfig read = ReadRigConfig(path_);
  ASSERT_EQ(read.cameras.size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    const RigCameraConfig& a = rig.cameras[i];
    const RigCameraConfig& b = read.cameras[i];
    EXPECT_EQ(a.camera_id, b.camera_id);
    EXPECT_EQ(a.image_prefix, b.image_prefix);
    EXPECT_LT(a.cam_from_rig.rotation.angularDistance(b.cam_from_rig.rotation),
              1e-15);
    EXPECT_EQ(a.cam_from_rig.translation, b.cam_from_rig.translation);
    EXPECT_EQ(a.rotation_sigma_deg, b.rotation_sigma_deg);
    EXPECT_EQ(a.translation_sigma_m, b.translation_sigma_m);
    EXPECT_EQ(a.time_offset_s, b.time_offset_s);
  }
  EXPECT_EQ(RigConfigJsonText(read), text);
  EXPECT_EQ(text.back(), '\n');
  EXPECT_EQ(nlohmann::json::parse(text).at("format"), "uwmetric-rig");
}

TEST_F(RigConfigTest, ImagesBelongToTheCameraOfTheirPrefix) {
  const RigConfig rig = ThreeCameras();
  EXPECT_EQ(rig.CameraOfImage("cam2/00001.png"), &rig.cameras[1]);
  EXPECT_EQ(rig.CameraOfImage("left/cam3_00001.png"), &rig.cameras[2]);
  EXPECT_EQ(rig.CameraOfImage("cam3/00001.png"), nullptr);
  EXPECT_EQ(rig.CameraOfImage("cam"), nullptr);
}

TEST_F(RigConfigTest, OptionalKeysDefaultToZero) {
  const RigConfig rig = Read(
      {{"format", "uwmetric-rig"},
       {"version", 1},
       {"cameras",
        {{{"camera_id", 3},
          {"image_prefix", "a/"},
          {"cam_from_rig", {{"qvec", {1, 0, 0, 0}}, {"tvec", {0, 0, 0}}}}}}}});
  ASSERT_EQ(rig.cameras.size(), 1u);
  EXPECT_EQ(rig.cameras[0].camera_id, 3u);
  EXPECT_EQ(rig.cameras[0].time_offset_s, 0.0);
}

TEST_F(RigConfigTest, BadFilesAreRefusedNamingFileAndKey) {
  const nlohmann::json good =
      nlohmann::json::parse(RigConfigJsonText(ThreeCameras()));
  const std::string file = path_.string();
  const auto with = [&](const std::function<void(nlohmann::json&)>& edit) {
    nlohmann::json json = good;
    edit(json);
    return json;
  };
  const struct {
    nlohmann::json json;
    std::string message;
  } cases[] = {
      {with([](auto& j) { j["extra"] = 1; }), file + ": unknown key \"extra\""},
      {with([](auto& j) { j["format"] = "uwmetric-lasers"; }),
       file + ": format \"uwmetric-lasers\" version 1 is not \"uwmetric-rig\" "
              "version 1"},
      {with([](auto& j) { j["version"] = 2; }), file + ": format"},
      {with([](auto& j) { j.erase("cameras"); }),
       file + ": missing key \"cameras\""},
      {with([](auto& j) { j["cameras"] = nlohmann::json::array(); }),
       file + ": no cameras"},
      {with([](auto& j) { j["cameras"][1]["time_offset"] = 0.1; }),
       file + ": cameras[1]: unknown key \"time_offset\""},
      {with([](auto& j) { j["cameras"][1]["cam_from_rig"]["t"] = 0; }),
       file + ": cameras[1].cam_from_rig: unknown key \"t\""},
      {with([](auto& j) {
         j["cameras"][1]["cam_from_rig"]["qvec"] = {1, 0.01, 0, 0};
       }),
       file + ": cameras[1].cam_from_rig.qvec: norm 1.00005 is not 1"},
      {with([](auto& j) {
         j["cameras"][1]["cam_from_rig"]["qvec"] = {1, 0, 0};
       }),
       file + ": cameras[1].cam_from_rig.qvec: expected 4 numbers"},
      {with([](auto& j) { j["cameras"][2]["camera_id"] = 2; }),
       file + ": cameras[2].camera_id = 2: cameras[1] has the same id"},
      {with([](auto& j) { j["cameras"][2]["camera_id"] = 0; }),
       file + ": cameras[2].camera_id: expected a COLMAP camera id"},
      {with([](auto& j) { j["cameras"][2]["camera_id"] = 1.5; }),
       file + ": cameras[2].camera_id: expected a COLMAP camera id"},
      {with([](auto& j) { j["cameras"][2]["camera_id"] = "7"; }),
       file + ": cameras[2].camera_id: expected a COLMAP camera id"},
      {with([](auto& j) { j["cameras"][2]["image_prefix"] = "cam2/"; }),
       file + ": cameras[2].image_prefix 'cam2/' and cameras[1].image_prefix "
              "'cam2/': one starts the other"},
      {with([](auto& j) { j["cameras"][2]["image_prefix"] = "cam"; }),
       file + ": cameras[2].image_prefix 'cam' and cameras[0]"},
      {with([](auto& j) { j["cameras"][2]["image_prefix"] = ""; }),
       file + ": cameras[2].image_prefix: must not be empty"},
      {with([](auto& j) { j["cameras"][1]["rotation_sigma_deg"] = -0.1; }),
       file + ": cameras[1].rotation_sigma_deg = -0.1: must be finite and >= "
              "0"},
      {with([](auto& j) { j["cameras"][0]["time_offset_s"] = 0.01; }),
       file + ": cameras[0] is the reference camera"},
      {with([](auto& j) {
         j["cameras"][0]["cam_from_rig"]["tvec"] = {0.1, 0, 0};
       }),
       file + ": cameras[0] is the reference camera"},
  };
  for (const auto& test : cases) {
    const std::string message = Error(test.json);
    EXPECT_EQ(message.substr(0, test.message.size()), test.message)
        << test.json.dump();
  }
  std::ofstream(path_) << "{\"format\": ";
  try {
    ReadRigConfig(path_);
    ADD_FAILURE() << "no error";
  } catch (const uw::Error& error) {
    EXPECT_EQ(std::string(error.what()).substr(0, file.size() + 17),
              file + ": not valid JSON:");
  }
}

TEST(RigConfig, CheckRefusesWhatTheReaderRefuses) {
  RigConfig rig = ThreeCameras();
  EXPECT_NO_THROW(rig.Check());
  rig.cameras[1].cam_from_rig.rotation.coeffs() *= 1.1;
  EXPECT_THROW(rig.Check(), Error);
  EXPECT_THROW(RigConfigJsonText(rig), Error);
  rig = ThreeCameras();
  rig.cameras[2].time_offset_s = NAN;
  EXPECT_THROW(rig.Check(), Error);
  EXPECT_THROW(RigConfig().Check(), Error);
}

}  // namespace
}  // namespace uw
