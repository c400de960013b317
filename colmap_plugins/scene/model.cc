#include "colmap_plugins/scene/model.h"

#include "common/util/error.h"

namespace uw {

Eigen::Matrix3d Rigid3d::RotationMatrix() const {
  return rotation.normalized().toRotationMatrix();
}

Eigen::Vector3d Rigid3d::operator*(const Eigen::Vector3d& point_in_a) const {
  return RotationMatrix() * point_in_a + translation;
}

Rigid3d Rigid3d::Inverse() const {
  Rigid3d inverse;
  inverse.rotation = rotation.normalized().inverse();
  inverse.translation = -(inverse.rotation * translation);
  return inverse;
}

Eigen::Vector2d Camera::ImgFromCam(const Eigen::Vector3d& point_in_cam) const {
  return CameraModelImgFromCam(model_id, params.data(), point_in_cam);
}

size_t Image::NumPoints3D() const {
  size_t num_points3D = 0;
  for (const Point2D& point2D : points2D) {
    num_points3D += point2D.HasPoint3D() ? 1 : 0;
  }
  return num_points3D;
}

Eigen::Vector3d Image::ProjectionCenter() const {
  return cam_from_world.Inverse().translation;
}

std::string SensorTypeName(const SensorType type) {
  switch (type) {
    case SensorType::kCamera:
      return "CAMERA";
    case SensorType::kImu:
      return "IMU";
    case SensorType::kInvalid:
      break;
  }
  return "INVALID";
}

SensorType SensorTypeFromName(const std::string& name) {
  if (name == "CAMERA") return SensorType::kCamera;
  if (name == "IMU") return SensorType::kImu;
  return SensorType::kInvalid;
}

size_t Rig::NumSensors() const {
  return (ref_sensor ? 1 : 0) + non_ref_sensors.size();
}

std::string ModelLayoutName(const ModelLayout layout) {
  return layout == ModelLayout::kColmap4
             ? "COLMAP 4.x (rigs, cameras, frames, images, points3D)"
             : "COLMAP 3.x (cameras, images, points3D)";
}

namespace {

template <typename Record, typename Id>
void AddIndexed(Record record, Id id, const char* kind,
                std::vector<Record>* records,
                std::unordered_map<Id, size_t>* index) {
  if (!index->emplace(id, records->size()).second) {
    throw ErrorAt("duplicate ", kind, " id ", id);
  }
  records->push_back(std::move(record));
}

template <typename Record, typename Id>
const Record* FindIndexed(Id id, const std::vector<Record>& records,
                          const std::unordered_map<Id, size_t>& index) {
  const auto it = index.find(id);
  return it == index.end() ? nullptr : &records[it->second];
}

}  // namespace

void Reconstruction::AddCamera(Camera camera) {
  const camera_t id = camera.camera_id;
  AddIndexed(std::move(camera), id, "camera", &cameras_, &camera_index_);
}

void Reconstruction::AddImage(Image image) {
  const image_t id = image.image_id;
  AddIndexed(std::move(image), id, "image", &images_, &image_index_);
}

void Reconstruction::AddPoint3D(Point3D point3D) {
  const point3D_t id = point3D.point3D_id;
  AddIndexed(std::move(point3D), id, "point3D", &points3D_, &point3D_index_);
}

void Reconstruction::AddRig(Rig rig) {
  const rig_t id = rig.rig_id;
  AddIndexed(std::move(rig), id, "rig", &rigs_, &rig_index_);
}

void Reconstruction::AddFrame(Frame frame) {
  const frame_t id = frame.frame_id;
  AddIndexed(std::move(frame), id, "frame", &frames_, &frame_index_);
}

const Camera* Reconstruction::FindCamera(const camera_t camera_id) const {
  return FindIndexed(camera_id, cameras_, camera_index_);
}

const Image* Reconstruction::FindImage(const image_t image_id) const {
  return FindIndexed(image_id, images_, image_index_);
}

const Point3D* Reconstruction::FindPoint3D(const point3D_t point3D_id) const {
  return FindIndexed(point3D_id, points3D_, point3D_index_);
}

void Reconstruction::Check(const std::string& source) const {
  for (const Image& image : images_) {
    if (FindCamera(image.camera_id) == nullptr) {
      throw ErrorAt(source, ": image ", image.image_id, " (", image.name,
                    ") refers to camera ", image.camera_id,
                    " which is not in the model");
    }
    for (size_t idx = 0; idx < image.points2D.size(); ++idx) {
      const point3D_t point3D_id = image.points2D[idx].point3D_id;
      if (image.points2D[idx].HasPoint3D() &&
          FindPoint3D(point3D_id) == nullptr) {
        throw ErrorAt(source, ": image ", image.image_id, " (", image.name,
                      ") point2D ", idx, " refers to point3D ", point3D_id,
                      " which is not in the model");
      }
    }
  }
  for (const Point3D& point3D : points3D_) {
    for (const TrackElement& element : point3D.track) {
      const Image* image = FindImage(element.image_id);
      if (image == nullptr) {
        throw ErrorAt(source, ": point3D ", point3D.point3D_id,
                      " track refers to image ", element.image_id,
                      " which is not in the model");
      }
      if (element.point2D_idx >= image->points2D.size() ||
          image->points2D[element.point2D_idx].point3D_id !=
              point3D.point3D_id) {
        throw ErrorAt(source, ": point3D ", point3D.point3D_id,
                      " track refers to point2D ", element.point2D_idx,
                      " of image ", element.image_id, " (", image->name,
                      ") which does not observe it");
      }
    }
  }
  if (layout == ModelLayout::kColmap4) CheckRigsAndFrames(source);
}

// COLMAP 4.x reads an image's pose through its frame, so every image must be
// exposed in exactly one frame, and every sensor a rig or frame names must
// exist (COLMAP fails on a missing one).
void Reconstruction::CheckRigsAndFrames(const std::string& source) const {
  for (const Rig& rig : rigs_) {
    std::vector<SensorId> sensors;
    if (rig.ref_sensor) sensors.push_back(*rig.ref_sensor);
    for (const RigSensor& sensor : rig.non_ref_sensors) {
      sensors.push_back(sensor.sensor_id);
    }
    for (const SensorId& sensor : sensors) {
      if (sensor.type == SensorType::kCamera &&
          FindCamera(sensor.id) == nullptr) {
        throw ErrorAt(source, ": rig ", rig.rig_id, " names camera ", sensor.id,
                      " which is not in the model");
      }
    }
  }
  std::unordered_map<image_t, frame_t> frame_of_image;
  for (const Frame& frame : frames_) {
    if (rig_index_.count(frame.rig_id) == 0) {
      throw ErrorAt(source, ": frame ", frame.frame_id, " refers to rig ",
                    frame.rig_id, " which is not in the model");
    }
    for (const DataId& data_id : frame.data_ids) {
      if (data_id.sensor_id.type != SensorType::kCamera) continue;
      const Image* image = FindImage(static_cast<image_t>(data_id.id));
      if (image == nullptr || image->camera_id != data_id.sensor_id.id) {
        throw ErrorAt(source, ": frame ", frame.frame_id, " names image ",
                      data_id.id, " of camera ", data_id.sensor_id.id,
                      ", which is not in the model");
      }
      if (!frame_of_image.emplace(image->image_id, frame.frame_id).second) {
        throw ErrorAt(source, ": image ", image->image_id, " (", image->name,
                      ") is in frames ", frame_of_image.at(image->image_id),
                      " and ", frame.frame_id);
      }
    }
  }
  for (const Image& image : images_) {
    if (frame_of_image.count(image.image_id) == 0) {
      throw ErrorAt(source, ": image ", image.image_id, " (", image.name,
                    ") is in no frame; a COLMAP 4.x model needs one");
    }
  }
}

}  // namespace uw
