#include "colmap_plugins/align/sim3.h"

#include <gtest/gtest.h>

namespace uw {
namespace {

Sim3d ExampleSim3() {
  Sim3d b_from_a;
  b_from_a.scale = 2.5;
  b_from_a.rotation = Eigen::Quaterniond(
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, -2, 0.5).normalized()));
  b_from_a.translation = Eigen::Vector3d(100.0, -20.0, 3.0);
  return b_from_a;
}

TEST(Sim3d, InverseAndCompositionAreConsistent) {
  const Sim3d b_from_a = ExampleSim3();
  const Eigen::Vector3d point_in_a(0.3, -1.2, 4.0);
  const Eigen::Vector3d point_in_b = b_from_a * point_in_a;
  EXPECT_NEAR((point_in_b -
               (2.5 * (b_from_a.rotation * point_in_a) + b_from_a.translation))
                  .norm(),
              0.0, 1e-12);
  EXPECT_NEAR((b_from_a.Inverse() * point_in_b - point_in_a).norm(), 0.0,
              1e-12);
  const Sim3d identity = b_from_a.Inverse() * b_from_a;
  EXPECT_NEAR(identity.scale, 1.0, 1e-15);
  EXPECT_NEAR(identity.rotation.angularDistance(Eigen::Quaterniond::Identity()),
              0.0, 1e-12);
  EXPECT_NEAR(identity.translation.norm(), 0.0, 1e-12);
  EXPECT_NEAR(
      (b_from_a.Matrix() * point_in_a.homogeneous() - point_in_b).norm(), 0.0,
      1e-12);
}

// A two-image model (COLMAP 4.x layout with a rig of two cameras) whose
// images see one point.
Reconstruction ExampleModel() {
  Reconstruction model;
  model.layout = ModelLayout::kColmap4;
  Camera camera;
  camera.camera_id = 1;
  camera.model_id = CameraModelId::kSimplePinhole;
  camera.width = 100;
  camera.height = 100;
  camera.params = {100.0, 50.0, 50.0};
  model.AddCamera(camera);
  Rigid3d rig_from_world;
  rig_from_world.rotation =
      Eigen::Quaterniond(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitY()));
  rig_from_world.translation = Eigen::Vector3d(0.1, 0.2, 5.0);
  Rigid3d cam2_from_rig;
  cam2_from_rig.rotation =
      Eigen::Quaterniond(Eigen::AngleAxisd(-0.1, Eigen::Vector3d::UnitX()));
  cam2_from_rig.translation = Eigen::Vector3d(-0.3, 0.0, 0.0);
  for (image_t image_id : {1u, 2u}) {
    Image image;
    image.image_id = image_id;
    image.camera_id = 1;
    image.name = std::to_string(image_id) + ".png";
    image.cam_from_world = rig_from_world;
    if (image_id == 2) {
      image.cam_from_world.rotation =
          cam2_from_rig.rotation * rig_from_world.rotation;
      image.cam_from_world.translation =
          cam2_from_rig * rig_from_world.translation;
    }
    model.AddImage(image);
  }
  Rig rig;
  rig.rig_id = 1;
  rig.ref_sensor = SensorId{SensorType::kCamera, 1};
  rig.non_ref_sensors.push_back(
      {SensorId{SensorType::kCamera, 2}, cam2_from_rig});
  model.AddRig(rig);
  Frame frame;
  frame.frame_id = 1;
  frame.rig_id = 1;
  frame.rig_from_world = rig_from_world;
  model.AddFrame(frame);
  Point3D point;
  point.point3D_id = 1;
  point.xyz = Eigen::Vector3d(0.5, -0.4, 1.0);
  model.AddPoint3D(point);
  return model;
}

TEST(TransformReconstruction, ImagesSeeTheirPointsWhereTheyDid) {
  const Reconstruction before = ExampleModel();
  Reconstruction after = before;
  const Sim3d b_from_a = ExampleSim3();
  TransformReconstruction(b_from_a, &after);

  const Camera& camera = before.Cameras()[0];
  for (size_t i = 0; i < before.Images().size(); ++i) {
    const Image& image_before = before.Images()[i];
    const Image& image_after = after.Images()[i];
    EXPECT_NEAR((image_after.ProjectionCenter() -
                 b_from_a * image_before.ProjectionCenter())
                    .norm(),
                0.0, 1e-12);
    const Eigen::Vector2d pixel_before = camera.ImgFromCam(
        image_before.cam_from_world * before.Points3D()[0].xyz);
    const Eigen::Vector2d pixel_after =
        camera.ImgFromCam(image_after.cam_from_world * after.Points3D()[0].xyz);
    EXPECT_NEAR((pixel_after - pixel_before).norm(), 0.0, 1e-10);
    EXPECT_NEAR(image_after.cam_from_world.rotation.norm(), 1.0, 1e-15);
  }
  // cam2_from_world = cam2_from_rig * rig_from_world still holds.
  const Rigid3d& rig_from_world = after.Frames()[0].rig_from_world;
  const Rigid3d& cam2_from_rig =
      *after.Rigs()[0].non_ref_sensors[0].sensor_from_rig;
  const Rigid3d& cam2_from_world = after.Images()[1].cam_from_world;
  EXPECT_NEAR((cam2_from_rig * (rig_from_world * Eigen::Vector3d(1, 2, 3)) -
               cam2_from_world * Eigen::Vector3d(1, 2, 3))
                  .norm(),
              0.0, 1e-10);
  EXPECT_NEAR((rig_from_world.translation -
               after.Images()[0].cam_from_world.translation)
                  .norm(),
              0.0, 1e-12);
}

TEST(Sim3d, JsonHoldsScaleRotationTranslationAndMatrix) {
  const Sim3d b_from_a = ExampleSim3();
  const nlohmann::json json = ToJson(b_from_a);
  EXPECT_DOUBLE_EQ(json.at("scale").get<double>(), 2.5);
  EXPECT_DOUBLE_EQ(json.at("qvec")[0].get<double>(), b_from_a.rotation.w());
  EXPECT_DOUBLE_EQ(json.at("tvec")[0].get<double>(), 100.0);
  EXPECT_DOUBLE_EQ(json.at("matrix")[1][3].get<double>(), -20.0);
}

}  // namespace
}  // namespace uw
