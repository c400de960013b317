// A COLMAP sparse model (cameras, images, points3D; and the rigs and frames
// of the COLMAP 4.x layout) as it is stored on disk.
//
// Records are kept in the order they were read, so that a model read and
// written back is byte-identical: COLMAP's own writer emits records in
// hash-map order, so two `colmap model_converter` runs may differ byte-wise,
// while we never reorder a user's file. Values are kept exactly as stored
// (quaternions are not re-normalised) for the same reason.
#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "colmap_plugins/cameras/camera_models.h"

namespace uw {

using camera_t = uint32_t;
using image_t = uint32_t;
using point2D_t = uint32_t;
using point3D_t = uint64_t;
using rig_t = uint32_t;
using frame_t = uint32_t;

// COLMAP marks a 2D point without a 3D point by the largest uint64 in .bin
// files and by -1 in .txt files.
constexpr point3D_t kInvalidPoint3DId = std::numeric_limits<point3D_t>::max();

// A rigid transform b_from_a: x_b = rotation * x_a + translation. The
// quaternion is Hamilton (w, x, y, z), as COLMAP stores it.
struct Rigid3d {
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();

  // Normalises the rotation on use, as COLMAP does when it reads a model.
  Eigen::Matrix3d RotationMatrix() const;
  Eigen::Vector3d operator*(const Eigen::Vector3d& point_in_a) const;
  Rigid3d Inverse() const;
};

struct Camera {
  camera_t camera_id = 0;
  CameraModelId model_id = CameraModelId::kInvalid;
  uint64_t width = 0;
  uint64_t height = 0;
  std::vector<double> params;

  std::string ModelName() const { return CameraModelIdToName(model_id); }
  Eigen::Vector2d ImgFromCam(const Eigen::Vector3d& point_in_cam) const;
};

struct Point2D {
  Eigen::Vector2d xy = Eigen::Vector2d::Zero();
  point3D_t point3D_id = kInvalidPoint3DId;

  bool HasPoint3D() const { return point3D_id != kInvalidPoint3DId; }
};

struct Image {
  image_t image_id = 0;
  Rigid3d cam_from_world;
  camera_t camera_id = 0;
  std::string name;
  std::vector<Point2D> points2D;

  // Number of 2D points that observe a 3D point.
  size_t NumPoints3D() const;
  Eigen::Vector3d ProjectionCenter() const;
};

struct TrackElement {
  image_t image_id = 0;
  point2D_t point2D_idx = 0;
};

struct Point3D {
  point3D_t point3D_id = 0;
  Eigen::Vector3d xyz = Eigen::Vector3d::Zero();
  Eigen::Matrix<uint8_t, 3, 1> color = Eigen::Matrix<uint8_t, 3, 1>::Zero();
  // Mean reprojection error over the track in pixels; -1 when unknown.
  double error = -1.0;
  std::vector<TrackElement> track;

  bool HasError() const { return error != -1.0; }
};

// Sensor vocabulary of the COLMAP 4.x layout (integer values are COLMAP's).
enum class SensorType : int { kInvalid = -1, kCamera = 0, kImu = 1 };
std::string SensorTypeName(SensorType type);
SensorType SensorTypeFromName(const std::string& name);  // kInvalid if none

struct SensorId {
  SensorType type = SensorType::kInvalid;
  uint32_t id = 0;
};

struct RigSensor {
  SensorId sensor_id;
  std::optional<Rigid3d> sensor_from_rig;
};

struct Rig {
  rig_t rig_id = 0;
  std::optional<SensorId> ref_sensor;  // Absent only for a rig of 0 sensors.
  std::vector<RigSensor> non_ref_sensors;

  size_t NumSensors() const;
};

struct DataId {
  SensorId sensor_id;
  uint64_t id = 0;  // For a camera sensor, the image id.
};

struct Frame {
  frame_t frame_id = 0;
  rig_t rig_id = 0;
  Rigid3d rig_from_world;
  std::vector<DataId> data_ids;
};

// Which files make up a model on disk.
enum class ModelLayout {
  kColmap3,  // cameras, images, points3D (COLMAP <= 3.11)
  kColmap4,  // + rigs and frames (COLMAP 3.12 and 4.x)
};
std::string ModelLayoutName(ModelLayout layout);

enum class ModelFormat { kBinary, kText };

class Reconstruction {
 public:
  ModelLayout layout = ModelLayout::kColmap3;

  // Records in file order. Use the Add* functions to keep the id index
  // in sync; the vectors may be edited in place otherwise.
  const std::vector<Camera>& Cameras() const { return cameras_; }
  const std::vector<Image>& Images() const { return images_; }
  const std::vector<Point3D>& Points3D() const { return points3D_; }
  const std::vector<Rig>& Rigs() const { return rigs_; }
  const std::vector<Frame>& Frames() const { return frames_; }
  std::vector<Camera>& Cameras() { return cameras_; }
  std::vector<Image>& Images() { return images_; }
  std::vector<Point3D>& Points3D() { return points3D_; }
  std::vector<Rig>& Rigs() { return rigs_; }
  std::vector<Frame>& Frames() { return frames_; }

  // Throw uw::Error on a duplicate id.
  void AddCamera(Camera camera);
  void AddImage(Image image);
  void AddPoint3D(Point3D point3D);
  void AddRig(Rig rig);
  void AddFrame(Frame frame);

  // nullptr when absent.
  const Camera* FindCamera(camera_t camera_id) const;
  const Image* FindImage(image_t image_id) const;
  const Point3D* FindPoint3D(point3D_t point3D_id) const;

  // Cross-checks references (an image's camera, a track's image and 2D
  // point, a 2D point's 3D point, a frame's rig) and throws uw::Error naming
  // `source` and the offending record.
  void Check(const std::string& source) const;

 private:
  void CheckRigsAndFrames(const std::string& source) const;

  std::vector<Camera> cameras_;
  std::vector<Image> images_;
  std::vector<Point3D> points3D_;
  std::vector<Rig> rigs_;
  std::vector<Frame> frames_;
  std::unordered_map<camera_t, size_t> camera_index_;
  std::unordered_map<image_t, size_t> image_index_;
  std::unordered_map<point3D_t, size_t> point3D_index_;
  std::unordered_map<rig_t, size_t> rig_index_;
  std::unordered_map<frame_t, size_t> frame_index_;
};

}  // namespace uw
