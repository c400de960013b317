// COLMAP's binary model files: little-endian, counts as uint64, records
// back to back (doc/format.rst "Binary File Format").
#include <cmath>
#include <cstring>

#include "colmap_plugins/scene/model_io.h"
#include "common/util/error.h"

namespace uw {
namespace {

static_assert(sizeof(double) == 8, "COLMAP files store IEEE doubles");

// Sequential reader over a file's bytes. Errors name the file, the byte
// offset and the record being read, e.g.
//   "sparse/0/images.bin: byte 1234: file ends inside image 7 (points2D)".
class ByteReader {
 public:
  ByteReader(const std::string& data, const std::string& source)
      : data_(data), source_(source) {}

  void SetRecord(const char* kind, uint64_t id) {
    record_kind_ = kind;
    record_id_ = id;
  }

  template <typename T>
  T Read(const char* field) {
    if (data_.size() - pos_ < sizeof(T)) {
      throw Fail(field, "file ends inside");
    }
    T value;
    std::memcpy(&value, data_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return value;
  }

  double ReadFinite(const char* field) {
    const size_t at = pos_;
    const double value = Read<double>(field);
    if (!std::isfinite(value)) {
      pos_ = at;
      throw Fail(field, "non-finite value in");
    }
    return value;
  }

  std::string ReadNulTerminated(const char* field) {
    const size_t end = data_.find('\0', pos_);
    if (end == std::string::npos) {
      throw Fail(field, "file ends inside");
    }
    std::string value = data_.substr(pos_, end - pos_);
    pos_ = end + 1;
    return value;
  }

  // A record count must fit in what is left of the file; checking it up
  // front turns a corrupt count into a clear error instead of a huge
  // allocation.
  uint64_t ReadCount(const char* field, size_t min_record_bytes) {
    const size_t at = pos_;
    const uint64_t count = Read<uint64_t>(field);
    if (min_record_bytes > 0 &&
        count > (data_.size() - pos_) / min_record_bytes) {
      pos_ = at;
      throw Fail(field, "count " + std::to_string(count) +
                            " exceeds the remaining bytes in");
    }
    return count;
  }

  Rigid3d ReadRigid3d(const char* field) {
    Rigid3d pose;
    pose.rotation.w() = ReadFinite(field);
    pose.rotation.x() = ReadFinite(field);
    pose.rotation.y() = ReadFinite(field);
    pose.rotation.z() = ReadFinite(field);
    for (int i = 0; i < 3; ++i) pose.translation(i) = ReadFinite(field);
    return pose;
  }

  // An error about the record just read (e.g. a duplicate id), at the
  // position after it.
  Error ErrorHere(const std::string& problem) const {
    return ErrorAt(source_, ": byte ", pos_, ": ", problem);
  }

  void ExpectEnd() const {
    if (pos_ != data_.size()) {
      throw ErrorAt(source_, ": byte ", pos_, ": ", data_.size() - pos_,
                    " unexpected trailing bytes after the last record");
    }
  }

 private:
  Error Fail(const char* field, const std::string& problem) const {
    std::ostringstream where;
    if (record_kind_ != nullptr) {
      where << record_kind_ << " " << record_id_ << " (" << field << ")";
    } else {
      where << field;
    }
    return ErrorAt(source_, ": byte ", pos_, ": ", problem, " ", where.str());
  }

  const std::string& data_;
  const std::string& source_;
  size_t pos_ = 0;
  const char* record_kind_ = nullptr;
  uint64_t record_id_ = 0;
};

class ByteWriter {
 public:
  template <typename T>
  void Write(T value) {
    const size_t at = bytes_.size();
    bytes_.resize(at + sizeof(T));
    std::memcpy(&bytes_[at], &value, sizeof(T));
  }

  void WriteRigid3d(const Rigid3d& pose) {
    Write<double>(pose.rotation.w());
    Write<double>(pose.rotation.x());
    Write<double>(pose.rotation.y());
    Write<double>(pose.rotation.z());
    for (int i = 0; i < 3; ++i) Write<double>(pose.translation(i));
  }

  void WriteNulTerminated(const std::string& text) {
    bytes_ += text;
    bytes_ += '\0';
  }

  std::string Take() { return std::move(bytes_); }

 private:
  std::string bytes_;
};

// Byte sizes of the fixed part of each record, for count plausibility.
constexpr size_t kCameraMinBytes = 4 + 4 + 8 + 8;
constexpr size_t kImageMinBytes = 4 + 7 * 8 + 4 + 1 + 8;
constexpr size_t kPoint2DBytes = 8 + 8 + 8;
constexpr size_t kPoint3DMinBytes = 8 + 3 * 8 + 3 + 8 + 8;
constexpr size_t kTrackElementBytes = 4 + 4;
constexpr size_t kRigMinBytes = 4 + 4;
constexpr size_t kFrameMinBytes = 4 + 4 + 7 * 8 + 4;

SensorId ReadSensorId(ByteReader* reader) {
  SensorId sensor_id;
  const int32_t type = reader->Read<int32_t>("sensor type");
  if (type != static_cast<int32_t>(SensorType::kCamera) &&
      type != static_cast<int32_t>(SensorType::kImu)) {
    throw reader->ErrorHere("unknown sensor type " + std::to_string(type) +
                            " (0 = CAMERA, 1 = IMU)");
  }
  sensor_id.type = static_cast<SensorType>(type);
  sensor_id.id = reader->Read<uint32_t>("sensor id");
  return sensor_id;
}

// Adds a record, turning an id clash into an error at the file position.
template <typename Record>
void AddRecord(void (Reconstruction::*add)(Record), Record record,
               const ByteReader& reader, Reconstruction* reconstruction) {
  try {
    (reconstruction->*add)(std::move(record));
  } catch (const Error& error) {
    throw reader.ErrorHere(error.what());
  }
}

void WriteSensorId(const SensorId& sensor_id, ByteWriter* writer) {
  writer->Write<int32_t>(static_cast<int32_t>(sensor_id.type));
  writer->Write<uint32_t>(sensor_id.id);
}

}  // namespace

void ParseCamerasBinary(const std::string& data, const std::string& source,
                        Reconstruction* reconstruction) {
  ByteReader reader(data, source);
  const uint64_t num_cameras =
      reader.ReadCount("camera count", kCameraMinBytes);
  for (uint64_t i = 0; i < num_cameras; ++i) {
    Camera camera;
    camera.camera_id = reader.Read<uint32_t>("camera id");
    reader.SetRecord("camera", camera.camera_id);
    camera.model_id = static_cast<CameraModelId>(reader.Read<int32_t>("model"));
    const int num_params = CameraModelNumParams(camera.model_id);
    if (num_params < 0) {
      throw ErrorAt(source, ": camera ", camera.camera_id,
                    ": unknown camera model id ",
                    static_cast<int>(camera.model_id));
    }
    camera.width = reader.Read<uint64_t>("width");
    camera.height = reader.Read<uint64_t>("height");
    camera.params.resize(num_params);
    for (double& param : camera.params) param = reader.ReadFinite("params");
    AddRecord(&Reconstruction::AddCamera, std::move(camera), reader,
              reconstruction);
  }
  reader.ExpectEnd();
}

void ParseImagesBinary(const std::string& data, const std::string& source,
                       Reconstruction* reconstruction) {
  ByteReader reader(data, source);
  const uint64_t num_images = reader.ReadCount("image count", kImageMinBytes);
  for (uint64_t i = 0; i < num_images; ++i) {
    Image image;
    image.image_id = reader.Read<uint32_t>("image id");
    reader.SetRecord("image", image.image_id);
    image.cam_from_world = reader.ReadRigid3d("cam_from_world");
    image.camera_id = reader.Read<uint32_t>("camera id");
    image.name = reader.ReadNulTerminated("name");
    const uint64_t num_points2D =
        reader.ReadCount("points2D count", kPoint2DBytes);
    image.points2D.resize(num_points2D);
    for (Point2D& point2D : image.points2D) {
      point2D.xy.x() = reader.ReadFinite("points2D");
      point2D.xy.y() = reader.ReadFinite("points2D");
      point2D.point3D_id = reader.Read<uint64_t>("points2D");
    }
    AddRecord(&Reconstruction::AddImage, std::move(image), reader,
              reconstruction);
  }
  reader.ExpectEnd();
}

void ParsePoints3DBinary(const std::string& data, const std::string& source,
                         Reconstruction* reconstruction) {
  ByteReader reader(data, source);
  const uint64_t num_points3D =
      reader.ReadCount("point3D count", kPoint3DMinBytes);
  for (uint64_t i = 0; i < num_points3D; ++i) {
    Point3D point3D;
    point3D.point3D_id = reader.Read<uint64_t>("point3D id");
    reader.SetRecord("point3D", point3D.point3D_id);
    for (int k = 0; k < 3; ++k) point3D.xyz(k) = reader.ReadFinite("xyz");
    for (int k = 0; k < 3; ++k) point3D.color(k) = reader.Read<uint8_t>("rgb");
    point3D.error = reader.ReadFinite("error");
    const uint64_t track_length =
        reader.ReadCount("track length", kTrackElementBytes);
    point3D.track.resize(track_length);
    for (TrackElement& element : point3D.track) {
      element.image_id = reader.Read<uint32_t>("track");
      element.point2D_idx = reader.Read<uint32_t>("track");
    }
    AddRecord(&Reconstruction::AddPoint3D, std::move(point3D), reader,
              reconstruction);
  }
  reader.ExpectEnd();
}

void ParseRigsBinary(const std::string& data, const std::string& source,
                     Reconstruction* reconstruction) {
  ByteReader reader(data, source);
  const uint64_t num_rigs = reader.ReadCount("rig count", kRigMinBytes);
  for (uint64_t i = 0; i < num_rigs; ++i) {
    Rig rig;
    rig.rig_id = reader.Read<uint32_t>("rig id");
    reader.SetRecord("rig", rig.rig_id);
    const uint32_t num_sensors = reader.Read<uint32_t>("sensor count");
    if (num_sensors > 0) rig.ref_sensor = ReadSensorId(&reader);
    for (uint32_t k = 1; k < num_sensors; ++k) {
      RigSensor sensor;
      sensor.sensor_id = ReadSensorId(&reader);
      if (reader.Read<uint8_t>("has_pose") != 0) {
        sensor.sensor_from_rig = reader.ReadRigid3d("sensor_from_rig");
      }
      rig.non_ref_sensors.push_back(sensor);
    }
    AddRecord(&Reconstruction::AddRig, std::move(rig), reader, reconstruction);
  }
  reader.ExpectEnd();
}

void ParseFramesBinary(const std::string& data, const std::string& source,
                       Reconstruction* reconstruction) {
  ByteReader reader(data, source);
  const uint64_t num_frames = reader.ReadCount("frame count", kFrameMinBytes);
  for (uint64_t i = 0; i < num_frames; ++i) {
    Frame frame;
    frame.frame_id = reader.Read<uint32_t>("frame id");
    reader.SetRecord("frame", frame.frame_id);
    frame.rig_id = reader.Read<uint32_t>("rig id");
    frame.rig_from_world = reader.ReadRigid3d("rig_from_world");
    const uint32_t num_data_ids = reader.Read<uint32_t>("data id count");
    for (uint32_t k = 0; k < num_data_ids; ++k) {
      DataId data_id;
      data_id.sensor_id = ReadSensorId(&reader);
      data_id.id = reader.Read<uint64_t>("data id");
      frame.data_ids.push_back(data_id);
    }
    AddRecord(&Reconstruction::AddFrame, std::move(frame), reader,
              reconstruction);
  }
  reader.ExpectEnd();
}

std::string CamerasBinary(const Reconstruction& reconstruction) {
  ByteWriter writer;
  writer.Write<uint64_t>(reconstruction.Cameras().size());
  for (const Camera& camera : reconstruction.Cameras()) {
    writer.Write<uint32_t>(camera.camera_id);
    writer.Write<int32_t>(static_cast<int32_t>(camera.model_id));
    writer.Write<uint64_t>(camera.width);
    writer.Write<uint64_t>(camera.height);
    for (const double param : camera.params) writer.Write<double>(param);
  }
  return writer.Take();
}

std::string ImagesBinary(const Reconstruction& reconstruction) {
  ByteWriter writer;
  writer.Write<uint64_t>(reconstruction.Images().size());
  for (const Image& image : reconstruction.Images()) {
    writer.Write<uint32_t>(image.image_id);
    writer.WriteRigid3d(image.cam_from_world);
    writer.Write<uint32_t>(image.camera_id);
    writer.WriteNulTerminated(image.name);
    writer.Write<uint64_t>(image.points2D.size());
    for (const Point2D& point2D : image.points2D) {
      writer.Write<double>(point2D.xy.x());
      writer.Write<double>(point2D.xy.y());
      writer.Write<uint64_t>(point2D.point3D_id);
    }
  }
  return writer.Take();
}

std::string Points3DBinary(const Reconstruction& reconstruction) {
  ByteWriter writer;
  writer.Write<uint64_t>(reconstruction.Points3D().size());
  for (const Point3D& point3D : reconstruction.Points3D()) {
    writer.Write<uint64_t>(point3D.point3D_id);
    for (int k = 0; k < 3; ++k) writer.Write<double>(point3D.xyz(k));
    for (int k = 0; k < 3; ++k) writer.Write<uint8_t>(point3D.color(k));
    writer.Write<double>(point3D.error);
    writer.Write<uint64_t>(point3D.track.size());
    for (const TrackElement& element : point3D.track) {
      writer.Write<uint32_t>(element.image_id);
      writer.Write<uint32_t>(element.point2D_idx);
    }
  }
  return writer.Take();
}

std::string RigsBinary(const Reconstruction& reconstruction) {
  ByteWriter writer;
  writer.Write<uint64_t>(reconstruction.Rigs().size());
  for (const Rig& rig : reconstruction.Rigs()) {
    writer.Write<uint32_t>(rig.rig_id);
    writer.Write<uint32_t>(static_cast<uint32_t>(rig.NumSensors()));
    if (rig.ref_sensor) WriteSensorId(*rig.ref_sensor, &writer);
    for (const RigSensor& sensor : rig.non_ref_sensors) {
      WriteSensorId(sensor.sensor_id, &writer);
      writer.Write<uint8_t>(sensor.sensor_from_rig ? 1 : 0);
      if (sensor.sensor_from_rig) writer.WriteRigid3d(*sensor.sensor_from_rig);
    }
  }
  return writer.Take();
}

std::string FramesBinary(const Reconstruction& reconstruction) {
  ByteWriter writer;
  writer.Write<uint64_t>(reconstruction.Frames().size());
  for (const Frame& frame : reconstruction.Frames()) {
    writer.Write<uint32_t>(frame.frame_id);
    writer.Write<uint32_t>(frame.rig_id);
    writer.WriteRigid3d(frame.rig_from_world);
    writer.Write<uint32_t>(static_cast<uint32_t>(frame.data_ids.size()));
    for (const DataId& data_id : frame.data_ids) {
      WriteSensorId(data_id.sensor_id, &writer);
      writer.Write<uint64_t>(data_id.id);
    }
  }
  return writer.Take();
}

}  // namespace uw
