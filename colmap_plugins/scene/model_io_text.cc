// COLMAP's text model files (doc/format.rst "Text Format"). Writers format
// numbers exactly as COLMAP's own writer does (C++ streams, precision 17,
// classic locale) so that our files and `colmap model_converter` output can
// be compared record for record.
#include <charconv>
#include <cmath>
#include <locale>
#include <sstream>

#include "colmap_plugins/scene/model_io.h"
#include "colmap_plugins/scene/model_stats.h"
#include "common/util/error.h"

namespace uw {
namespace {

// An error message builder that throws as a uw::Error with "file:line: ".
class Failure {
 public:
  explicit Failure(std::string prefix) { message_ << prefix; }
  template <typename T>
  Failure& operator<<(const T& value) {
    message_ << value;
    return *this;
  }
  operator Error() const { return Error(message_.str()); }

 private:
  std::ostringstream message_;
};

[[noreturn]] void Throw(const Failure& failure) { throw Error(failure); }

// Splits a text file into data lines (comments and blank lines skipped,
// except where the format needs a blank line: the POINTS2D line of an
// image) and parses tokens strictly, naming "file:line" in every error.
class LineReader {
 public:
  LineReader(const std::string& data, const std::string& source)
      : data_(data), source_(source) {}

  // Next non-comment, non-blank line; false at end of file.
  bool NextDataLine() {
    while (NextRawLine()) {
      const size_t first = line_.find_first_not_of(" \t\r");
      if (first != std::string::npos && line_[first] != '#') return true;
    }
    return false;
  }

  // Next physical line, whatever it holds; false at end of file.
  bool NextRawLine() {
    if (pos_ >= data_.size()) return false;
    size_t end = data_.find('\n', pos_);
    if (end == std::string::npos) end = data_.size();
    line_ = data_.substr(pos_, end - pos_);
    if (!line_.empty() && line_.back() == '\r') line_.pop_back();
    pos_ = end + 1;
    ++line_number_;
    Tokenize();
    return true;
  }

  size_t NumTokens() const { return tokens_.size(); }
  const std::string& Line() const { return line_; }
  size_t LineNumber() const { return line_number_; }

  const std::string& Token(size_t index, const char* what) const {
    if (index >= tokens_.size()) {
      Throw(Fail() << "expected " << what << " as field " << index + 1
                   << ", but the line has only " << tokens_.size()
                   << " fields");
    }
    return tokens_[index];
  }

  template <typename T>
  T Integer(size_t index, const char* what) const {
    const std::string& token = Token(index, what);
    T value{};
    const auto [end, ec] =
        std::from_chars(token.data(), token.data() + token.size(), value);
    if (ec != std::errc() || end != token.data() + token.size()) {
      Throw(Fail() << "expected " << what << " (integer) as field " << index + 1
                   << ", got '" << token << "'");
    }
    return value;
  }

  double Double(size_t index, const char* what) const {
    const std::string& token = Token(index, what);
    double value = 0.0;
    const auto [end, ec] =
        std::from_chars(token.data(), token.data() + token.size(), value);
    if (ec != std::errc() || end != token.data() + token.size()) {
      Throw(Fail() << "expected " << what << " (number) as field " << index + 1
                   << ", got '" << token << "'");
    }
    if (!std::isfinite(value)) {
      Throw(Fail() << what << " as field " << index + 1 << " is not finite ('"
                   << token << "')");
    }
    return value;
  }

  Rigid3d Pose(size_t index, const char* what) const {
    Rigid3d pose;
    pose.rotation.w() = Double(index, what);
    pose.rotation.x() = Double(index + 1, what);
    pose.rotation.y() = Double(index + 2, what);
    pose.rotation.z() = Double(index + 3, what);
    for (int k = 0; k < 3; ++k)
      pose.translation(k) = Double(index + 4 + k, what);
    return pose;
  }

  SensorType Sensor(size_t index) const {
    const std::string& token = Token(index, "sensor type");
    const SensorType type = SensorTypeFromName(token);
    if (type == SensorType::kInvalid) {
      Throw(Fail() << "unknown sensor type '" << token << "' as field "
                   << index + 1);
    }
    return type;
  }

  void ExpectTokens(size_t count, const char* layout) const {
    if (tokens_.size() != count) {
      Throw(Fail() << "expected " << count << " fields (" << layout << "), got "
                   << tokens_.size());
    }
  }

  Failure Fail() const {
    return Failure(source_ + ":" + std::to_string(line_number_) + ": ");
  }

 private:
  void Tokenize() {
    tokens_.clear();
    size_t start = line_.find_first_not_of(" \t\r");
    while (start != std::string::npos) {
      const size_t end = line_.find_first_of(" \t\r", start);
      tokens_.push_back(line_.substr(start, end - start));
      start = end == std::string::npos ? end
                                       : line_.find_first_not_of(" \t\r", end);
    }
  }

  const std::string& data_;
  const std::string& source_;
  size_t pos_ = 0;
  size_t line_number_ = 0;
  std::string line_;
  std::vector<std::string> tokens_;
};

// A stream configured as COLMAP configures its text writers.
class TextStream : public std::ostringstream {
 public:
  TextStream() {
    imbue(std::locale::classic());
    precision(17);
  }
};

// COLMAP writes a line's fields each followed by a space and then drops the
// last character of the line; reproduce that, including its effect on a
// line with no fields.
std::string DropLastChar(const std::string& line) {
  return line.substr(0, line.size() - 1);
}

// COLMAP 3.8's NormalizeQuaternion: a division of (w, x, y, z) as a
// 4-vector by its norm.
Eigen::Vector4d NormalizedWxyz(const Eigen::Vector4d& wxyz) {
  const double norm = wxyz.norm();
  return norm == 0.0 ? Eigen::Vector4d(1.0, wxyz(1), wxyz(2), wxyz(3))
                     : Eigen::Vector4d(wxyz / norm);
}

// COLMAP normalises an image's quaternion when it reads a model and again
// when it writes text; the second division changes the last bits of a
// quaternion that was not unit, so both steps are needed for identical text.
Eigen::Quaterniond QuaternionAsColmapWritesText(
    const Eigen::Quaterniond& rotation) {
  const Eigen::Vector4d wxyz = NormalizedWxyz(NormalizedWxyz(
      Eigen::Vector4d(rotation.w(), rotation.x(), rotation.y(), rotation.z())));
  return Eigen::Quaterniond(wxyz(0), wxyz(1), wxyz(2), wxyz(3));
}

void WritePose(const Rigid3d& pose, std::ostream& line) {
  line << pose.rotation.w() << " " << pose.rotation.x() << " "
       << pose.rotation.y() << " " << pose.rotation.z() << " "
       << pose.translation.x() << " " << pose.translation.y() << " "
       << pose.translation.z() << " ";
}

}  // namespace

void ParseCamerasText(const std::string& data, const std::string& source,
                      Reconstruction* reconstruction) {
  LineReader reader(data, source);
  while (reader.NextDataLine()) {
    Camera camera;
    camera.camera_id = reader.Integer<uint32_t>(0, "CAMERA_ID");
    const std::string& model_name = reader.Token(1, "MODEL");
    camera.model_id = CameraModelNameToId(model_name);
    if (camera.model_id == CameraModelId::kInvalid) {
      Throw(reader.Fail() << "unknown camera model '" << model_name << "'");
    }
    camera.width = reader.Integer<uint64_t>(2, "WIDTH");
    camera.height = reader.Integer<uint64_t>(3, "HEIGHT");
    const size_t num_params = reader.NumTokens() - 4;
    const int expected = CameraModelNumParams(camera.model_id);
    if (num_params != static_cast<size_t>(expected)) {
      Throw(reader.Fail() << "camera " << camera.camera_id << ": model "
                          << model_name << " expects " << expected
                          << " parameters ("
                          << CameraModelParamsInfo(camera.model_id) << "), got "
                          << num_params);
    }
    for (size_t k = 0; k < num_params; ++k) {
      camera.params.push_back(reader.Double(4 + k, "PARAMS"));
    }
    try {
      reconstruction->AddCamera(std::move(camera));
    } catch (const Error& error) {
      Throw(reader.Fail() << error.what());
    }
  }
}

void ParseImagesText(const std::string& data, const std::string& source,
                     Reconstruction* reconstruction) {
  LineReader reader(data, source);
  while (reader.NextDataLine()) {
    Image image;
    if (reader.NumTokens() < 10) {
      Throw(reader.Fail() << "expected IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, "
                             "CAMERA_ID, NAME; got "
                          << reader.NumTokens() << " fields");
    }
    image.image_id = reader.Integer<uint32_t>(0, "IMAGE_ID");
    image.cam_from_world = reader.Pose(1, "pose (QW..TZ)");
    image.camera_id = reader.Integer<uint32_t>(8, "CAMERA_ID");
    // The name is the rest of the line, so names with spaces survive.
    const std::string& line = reader.Line();
    size_t name_start = 0;
    for (int field = 0; field < 9; ++field) {
      name_start = line.find_first_not_of(" \t", name_start);
      name_start = line.find_first_of(" \t", name_start);
    }
    name_start = line.find_first_not_of(" \t", name_start);
    image.name = line.substr(name_start);
    while (!image.name.empty() &&
           (image.name.back() == ' ' || image.name.back() == '\t')) {
      image.name.pop_back();
    }

    if (!reader.NextRawLine()) {
      Throw(reader.Fail() << "image " << image.image_id << " (" << image.name
                          << "): missing POINTS2D line (the file ends)");
    }
    if (reader.NumTokens() % 3 != 0) {
      Throw(reader.Fail() << "image " << image.image_id << " (" << image.name
                          << "): POINTS2D must be triples X Y POINT3D_ID, got "
                          << reader.NumTokens() << " fields");
    }
    for (size_t k = 0; k < reader.NumTokens(); k += 3) {
      Point2D point2D;
      point2D.xy.x() = reader.Double(k, "X");
      point2D.xy.y() = reader.Double(k + 1, "Y");
      const int64_t id = reader.Integer<int64_t>(k + 2, "POINT3D_ID");
      if (id < -1) {
        Throw(reader.Fail() << "POINT3D_ID " << id << " as field " << k + 3
                            << " is negative (only -1 means none)");
      }
      point2D.point3D_id =
          id == -1 ? kInvalidPoint3DId : static_cast<point3D_t>(id);
      image.points2D.push_back(point2D);
    }
    try {
      reconstruction->AddImage(std::move(image));
    } catch (const Error& error) {
      Throw(reader.Fail() << error.what());
    }
  }
}

void ParsePoints3DText(const std::string& data, const std::string& source,
                       Reconstruction* reconstruction) {
  LineReader reader(data, source);
  while (reader.NextDataLine()) {
    Point3D point3D;
    if (reader.NumTokens() < 8 || (reader.NumTokens() - 8) % 2 != 0) {
      Throw(reader.Fail() << "expected POINT3D_ID, X, Y, Z, R, G, B, ERROR "
                             "and (IMAGE_ID, POINT2D_IDX) pairs; got "
                          << reader.NumTokens() << " fields");
    }
    point3D.point3D_id = reader.Integer<uint64_t>(0, "POINT3D_ID");
    for (int k = 0; k < 3; ++k) point3D.xyz(k) = reader.Double(1 + k, "XYZ");
    for (int k = 0; k < 3; ++k) {
      const int channel = reader.Integer<int>(4 + k, "RGB");
      if (channel < 0 || channel > 255) {
        Throw(reader.Fail()
              << "colour channel " << channel << " is outside 0..255");
      }
      point3D.color(k) = static_cast<uint8_t>(channel);
    }
    point3D.error = reader.Double(7, "ERROR");
    for (size_t k = 8; k < reader.NumTokens(); k += 2) {
      TrackElement element;
      element.image_id = reader.Integer<uint32_t>(k, "IMAGE_ID");
      element.point2D_idx = reader.Integer<uint32_t>(k + 1, "POINT2D_IDX");
      point3D.track.push_back(element);
    }
    try {
      reconstruction->AddPoint3D(std::move(point3D));
    } catch (const Error& error) {
      Throw(reader.Fail() << error.what());
    }
  }
}

void ParseRigsText(const std::string& data, const std::string& source,
                   Reconstruction* reconstruction) {
  LineReader reader(data, source);
  while (reader.NextDataLine()) {
    Rig rig;
    rig.rig_id = reader.Integer<uint32_t>(0, "RIG_ID");
    const uint32_t num_sensors = reader.Integer<uint32_t>(1, "NUM_SENSORS");
    size_t field = 2;
    if (num_sensors > 0) {
      rig.ref_sensor =
          SensorId{reader.Sensor(field),
                   reader.Integer<uint32_t>(field + 1, "REF_SENSOR_ID")};
      field += 2;
    }
    for (uint32_t k = 1; k < num_sensors; ++k) {
      RigSensor sensor;
      sensor.sensor_id.type = reader.Sensor(field);
      sensor.sensor_id.id = reader.Integer<uint32_t>(field + 1, "SENSOR_ID");
      const int has_pose = reader.Integer<int>(field + 2, "HAS_POSE");
      field += 3;
      if (has_pose == 1) {
        sensor.sensor_from_rig = reader.Pose(field, "sensor_from_rig");
        field += 7;
      } else if (has_pose != 0) {
        Throw(reader.Fail() << "HAS_POSE must be 0 or 1, got " << has_pose);
      }
      rig.non_ref_sensors.push_back(sensor);
    }
    reader.ExpectTokens(field, "RIG_ID, NUM_SENSORS, sensors");
    try {
      reconstruction->AddRig(std::move(rig));
    } catch (const Error& error) {
      Throw(reader.Fail() << error.what());
    }
  }
}

void ParseFramesText(const std::string& data, const std::string& source,
                     Reconstruction* reconstruction) {
  LineReader reader(data, source);
  while (reader.NextDataLine()) {
    Frame frame;
    frame.frame_id = reader.Integer<uint32_t>(0, "FRAME_ID");
    frame.rig_id = reader.Integer<uint32_t>(1, "RIG_ID");
    frame.rig_from_world = reader.Pose(2, "rig_from_world");
    const uint32_t num_data_ids = reader.Integer<uint32_t>(9, "NUM_DATA_IDS");
    reader.ExpectTokens(10 + 3 * static_cast<size_t>(num_data_ids),
                        "FRAME_ID, RIG_ID, pose, NUM_DATA_IDS, data ids");
    for (uint32_t k = 0; k < num_data_ids; ++k) {
      DataId data_id;
      data_id.sensor_id.type = reader.Sensor(10 + 3 * k);
      data_id.sensor_id.id = reader.Integer<uint32_t>(11 + 3 * k, "SENSOR_ID");
      data_id.id = reader.Integer<uint64_t>(12 + 3 * k, "DATA_ID");
      frame.data_ids.push_back(data_id);
    }
    try {
      reconstruction->AddFrame(std::move(frame));
    } catch (const Error& error) {
      Throw(reader.Fail() << error.what());
    }
  }
}

std::string CamerasText(const Reconstruction& reconstruction) {
  TextStream file;
  file << "# Camera list with one line of data per camera:\n"
       << "#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n"
       << "# Number of cameras: " << reconstruction.Cameras().size() << "\n";
  for (const Camera& camera : reconstruction.Cameras()) {
    TextStream line;
    line << camera.camera_id << " " << camera.ModelName() << " " << camera.width
         << " " << camera.height << " ";
    for (const double param : camera.params) line << param << " ";
    file << DropLastChar(line.str()) << "\n";
  }
  return file.str();
}

std::string ImagesText(const Reconstruction& reconstruction) {
  const size_t num_images = reconstruction.Images().size();
  const double mean_observations =
      num_images == 0 ? 0.0
                      : ComputeModelStats(reconstruction).num_observations /
                            static_cast<double>(num_images);
  TextStream file;
  file << "# Image list with two lines of data per image:\n"
       << "#   IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, CAMERA_ID, NAME\n"
       << "#   POINTS2D[] as (X, Y, POINT3D_ID)\n"
       << "# Number of images: " << num_images
       << ", mean observations per image: " << mean_observations << "\n";
  for (const Image& image : reconstruction.Images()) {
    Rigid3d cam_from_world = image.cam_from_world;
    cam_from_world.rotation =
        QuaternionAsColmapWritesText(image.cam_from_world.rotation);
    TextStream line;
    line << image.image_id << " ";
    WritePose(cam_from_world, line);
    line << image.camera_id << " " << image.name;
    file << line.str() << "\n";

    TextStream points;
    for (const Point2D& point2D : image.points2D) {
      points << point2D.xy.x() << " " << point2D.xy.y() << " ";
      if (point2D.HasPoint3D()) {
        points << point2D.point3D_id << " ";
      } else {
        points << -1 << " ";
      }
    }
    file << DropLastChar(points.str()) << "\n";
  }
  return file.str();
}

std::string Points3DText(const Reconstruction& reconstruction) {
  const size_t num_points = reconstruction.Points3D().size();
  const double mean_track_length =
      num_points == 0 ? 0.0
                      : ComputeModelStats(reconstruction).num_observations /
                            static_cast<double>(num_points);
  TextStream file;
  file << "# 3D point list with one line of data per point:\n"
       << "#   POINT3D_ID, X, Y, Z, R, G, B, ERROR, TRACK[] as (IMAGE_ID, "
          "POINT2D_IDX)\n"
       << "# Number of points: " << num_points
       << ", mean track length: " << mean_track_length << "\n";
  for (const Point3D& point3D : reconstruction.Points3D()) {
    file << point3D.point3D_id << " " << point3D.xyz(0) << " " << point3D.xyz(1)
         << " " << point3D.xyz(2) << " " << static_cast<int>(point3D.color(0))
         << " " << static_cast<int>(point3D.color(1)) << " "
         << static_cast<int>(point3D.color(2)) << " " << point3D.error << " ";
    TextStream track;
    for (const TrackElement& element : point3D.track) {
      track << element.image_id << " " << element.point2D_idx << " ";
    }
    file << DropLastChar(track.str()) << "\n";
  }
  return file.str();
}

std::string RigsText(const Reconstruction& reconstruction) {
  TextStream file;
  file << "# Rig calib list with one line of data per calib:\n"
       << "#   RIG_ID, NUM_SENSORS, REF_SENSOR_TYPE, REF_SENSOR_ID, SENSORS[] "
          "as (SENSOR_TYPE, SENSOR_ID, HAS_POSE, [QW, QX, QY, QZ, TX, TY, "
          "TZ])\n"
       << "# Number of rigs: " << reconstruction.Rigs().size() << "\n";
  for (const Rig& rig : reconstruction.Rigs()) {
    TextStream line;
    line << rig.rig_id << " " << rig.NumSensors() << " ";
    if (rig.ref_sensor) {
      line << SensorTypeName(rig.ref_sensor->type) << " " << rig.ref_sensor->id
           << " ";
    }
    for (const RigSensor& sensor : rig.non_ref_sensors) {
      line << SensorTypeName(sensor.sensor_id.type) << " "
           << sensor.sensor_id.id << " ";
      if (sensor.sensor_from_rig) {
        line << "1 ";
        WritePose(*sensor.sensor_from_rig, line);
      } else {
        line << "0 ";
      }
    }
    file << DropLastChar(line.str()) << "\n";
  }
  return file.str();
}

std::string FramesText(const Reconstruction& reconstruction) {
  TextStream file;
  file << "# Frame list with one line of data per frame:\n"
       << "#   FRAME_ID, RIG_ID, RIG_FROM_WORLD[QW, QX, QY, QZ, TX, TY, TZ], "
          "NUM_DATA_IDS, DATA_IDS[] as (SENSOR_TYPE, SENSOR_ID, DATA_ID)\n"
       << "# Number of frames: " << reconstruction.Frames().size() << "\n";
  for (const Frame& frame : reconstruction.Frames()) {
    file << frame.frame_id << " " << frame.rig_id << " ";
    WritePose(frame.rig_from_world, file);
    file << frame.data_ids.size();
    for (const DataId& data_id : frame.data_ids) {
      file << " " << SensorTypeName(data_id.sensor_id.type) << " "
           << data_id.sensor_id.id << " " << data_id.id;
    }
    file << "\n";
  }
  return file.str();
}

}  // namespace uw
