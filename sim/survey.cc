#include "sim/survey.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <random>

#include <fmt/format.h>
#include <Eigen/Geometry>

#include "colmap_plugins/nav/camera_mount.h"
#include "common/mesh/ray_caster.h"
#include "common/util/error.h"
#include "common/util/json_fields.h"
#include "sim/world.h"

namespace uw::sim {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

bool IsFinitePositive(double value) {
  return std::isfinite(value) && value > 0.0;
}

void CheckFraction(double value, const char* name, double min, double max) {
  if (!(value >= min && value <= max)) {
    throw ErrorAt("survey option ", name, " = ", value, " must be in [", min,
                  ", ", max, "]");
  }
}

// Whether the camera looks down (floor) or sideways (wall) follows from how
// steep the survey plane is.
bool IsWallSurvey(const World& world) {
  return std::abs(world.survey_normal.z()) < 0.7;
}

CameraMount MountOf(bool wall) {
  return wall ? CameraMount::kStarboard : CameraMount::kDown;
}

// Image footprint (m) along the camera's x and y axes at distance d.
Eigen::Vector2d Footprint(const Camera& camera, double distance) {
  const double w = static_cast<double>(camera.width);
  const double h = static_cast<double>(camera.height);
  const auto ray = [&](double x, double y) {
    return CameraModelCamFromImg(camera.model_id, camera.params.data(),
                                 Eigen::Vector2d(x, y));
  };
  return distance * Eigen::Vector2d(ray(w, 0.5 * h).x() - ray(0, 0.5 * h).x(),
                                    ray(0.5 * w, h).y() - ray(0.5 * w, 0).y());
}

// Positions of `count` stations spread evenly over [-half, half].
std::vector<double> Spread(double half, double spacing) {
  const int count =
      std::max(1, static_cast<int>(std::floor(2.0 * half / spacing)) + 1);
  std::vector<double> positions;
  const double start = -0.5 * spacing * (count - 1);
  for (int i = 0; i < count; ++i) positions.push_back(start + i * spacing);
  return positions;
}

}  // namespace

std::string SurveyKindName(SurveyKind kind) {
  switch (kind) {
    case SurveyKind::kLawnmower:
      return "lawnmower";
    case SurveyKind::kSinglePass:
      return "single_pass";
    case SurveyKind::kMultiDive:
      return "multi_dive";
    case SurveyKind::kVideo:
      return "video";
    case SurveyKind::kViews:
      return "views";
  }
  throw ErrorAt("invalid SurveyKind ", static_cast<int>(kind));
}

SurveyKind SurveyKindFromName(const std::string& name) {
  std::string available;
  for (const SurveyKind kind :
       {SurveyKind::kLawnmower, SurveyKind::kSinglePass, SurveyKind::kMultiDive,
        SurveyKind::kVideo, SurveyKind::kViews}) {
    if (name == SurveyKindName(kind)) return kind;
    available += (available.empty() ? "" : ", ") + SurveyKindName(kind);
  }
  throw ErrorAt("unknown survey '", name, "' (available: ", available, ")");
}

void SurveyOptions::Check() const {
  if (!IsFinitePositive(distance_m)) {
    throw ErrorAt("survey option distance_m = ", distance_m,
                  " must be positive");
  }
  CheckFraction(forward_overlap, "forward_overlap", 0.0, 0.95);
  CheckFraction(side_overlap, "side_overlap", 0.0, 0.95);
  CheckFraction(coverage_along, "coverage_along", 0.01, 1.0);
  CheckFraction(coverage_across, "coverage_across", 0.0, 1.0);
  if (!IsFinitePositive(speed_m_per_s)) {
    throw ErrorAt("survey option speed_m_per_s = ", speed_m_per_s,
                  " must be positive");
  }
  CheckFraction(attitude_jitter_deg, "attitude_jitter_deg", 0.0, 30.0);
  CheckFraction(position_jitter_m, "position_jitter_m", 0.0, distance_m / 2);
  if (!lever_arm_m.allFinite() || !boresight_deg.allFinite()) {
    throw ErrorAt(
        "survey options lever_arm_m and boresight_deg must be "
        "finite");
  }
  if (max_images < 0) {
    throw ErrorAt("survey option max_images = ", max_images, " must be >= 0");
  }
  if (num_dives < 2 || num_dives > 5) {
    throw ErrorAt("survey option num_dives = ", num_dives,
                  " must be in [2, 5]");
  }
  CheckFraction(dive_overlap, "dive_overlap", 0.05, 0.95);
  if (!(std::isfinite(dive_gap_s) && dive_gap_s >= 0.0)) {
    throw ErrorAt("survey option dive_gap_s = ", dive_gap_s,
                  " must be finite and >= 0");
  }
  CheckFraction(frame_rate_hz, "frame_rate_hz", 0.01, 100.0);
  if (!IsFinitePositive(views_distance_m)) {
    throw ErrorAt("survey option views_distance_m = ", views_distance_m,
                  " must be positive");
  }
  CheckFraction(views_max_angle_deg, "views_max_angle_deg", 0.0, 80.0);
  CheckFraction(views_step_deg, "views_step_deg", 0.01, 80.0);
  const double half_count = views_max_angle_deg / views_step_deg;
  if (std::abs(half_count - std::round(half_count)) > 1e-9) {
    throw ErrorAt(
        "survey option views_max_angle_deg = ", views_max_angle_deg,
        " must be a whole number of views_step_deg = ", views_step_deg);
  }
  if (!IsFinitePositive(views_normal_radius_m)) {
    throw ErrorAt("survey option views_normal_radius_m = ",
                  views_normal_radius_m, " must be positive");
  }
  if (views_target.has_value() && !views_target->allFinite()) {
    throw ErrorAt("survey option views_target must be finite");
  }
}

void to_json(nlohmann::json& json, const SurveyOptions& options) {
  json = {{"distance_m", options.distance_m},
          {"forward_overlap", options.forward_overlap},
          {"side_overlap", options.side_overlap},
          {"coverage_along", options.coverage_along},
          {"coverage_across", options.coverage_across},
          {"speed_m_per_s", options.speed_m_per_s},
          {"attitude_jitter_deg", options.attitude_jitter_deg},
          {"position_jitter_m", options.position_jitter_m},
          {"lever_arm_m", ToJson(options.lever_arm_m)},
          {"boresight_deg", ToJson(options.boresight_deg)},
          {"max_images", options.max_images},
          {"num_dives", options.num_dives},
          {"dive_overlap", options.dive_overlap},
          {"dive_gap_s", options.dive_gap_s},
          {"frame_rate_hz", options.frame_rate_hz},
          {"views_distance_m", options.views_distance_m},
          {"views_max_angle_deg", options.views_max_angle_deg},
          {"views_step_deg", options.views_step_deg},
          {"views_normal_radius_m", options.views_normal_radius_m},
          {"views_target", options.views_target.has_value()
                               ? ToJson(*options.views_target)
                               : nlohmann::json()},
          {"views_jitter", options.views_jitter}};
}

void from_json(const nlohmann::json& json, SurveyOptions& options) {
  JsonFields fields(json, "survey_options");
  fields.Read("distance_m", &options.distance_m);
  fields.Read("forward_overlap", &options.forward_overlap);
  fields.Read("side_overlap", &options.side_overlap);
  fields.Read("coverage_along", &options.coverage_along);
  fields.Read("coverage_across", &options.coverage_across);
  fields.Read("speed_m_per_s", &options.speed_m_per_s);
  fields.Read("attitude_jitter_deg", &options.attitude_jitter_deg);
  fields.Read("position_jitter_m", &options.position_jitter_m);
  fields.Read("lever_arm_m", &options.lever_arm_m);
  fields.Read("boresight_deg", &options.boresight_deg);
  fields.Read("max_images", &options.max_images);
  fields.Read("num_dives", &options.num_dives);
  fields.Read("dive_overlap", &options.dive_overlap);
  fields.Read("dive_gap_s", &options.dive_gap_s);
  fields.Read("frame_rate_hz", &options.frame_rate_hz);
  fields.Read("views_distance_m", &options.views_distance_m);
  fields.Read("views_max_angle_deg", &options.views_max_angle_deg);
  fields.Read("views_step_deg", &options.views_step_deg);
  fields.Read("views_normal_radius_m", &options.views_normal_radius_m);
  // null, as written when unset, unsets the target.
  fields.Read("views_target", &options.views_target);
  fields.Read("views_jitter", &options.views_jitter);
  fields.RejectUnknown();
}

CameraMount SurveyCameraMount(const World& world) {
  return MountOf(IsWallSurvey(world));
}

Rigid3d VehicleFromCam(const World& world, const SurveyOptions& options) {
  NavToCameraOptions camera;
  camera.mount = SurveyCameraMount(world);
  camera.lever_arm_m = options.lever_arm_m;
  camera.boresight_deg = options.boresight_deg;
  return uw::VehicleFromCam(camera);
}

namespace {

// The survey plane and the camera's footprint on it. A point of the plane
// is (u, v): u along survey_along, v along across = survey_normal x along.
struct SurveyFrame {
  SurveyFrame(const World& world, const Camera& camera,
              const SurveyOptions& options)
      : wall(IsWallSurvey(world)),
        origin(world.survey_origin),
        normal(world.survey_normal.normalized()),
        along(world.survey_along.normalized()),
        across(normal.cross(along)),
        footprint(Footprint(camera, options.distance_m)),
        distance(options.distance_m) {}

  // The camera centre over the plane point (u, v).
  Eigen::Vector3d CameraCentre(double u, double v) const {
    return origin + u * along + v * across + distance * normal;
  }
  // Footprint along a line flown along v (lines_across) or along u, and
  // across it. Down-looking, the image's y axis runs along the vehicle's
  // track; side-looking, image x runs along the wall and y up it.
  double LineFootprint(bool lines_across) const {
    return wall && !lines_across ? footprint.x() : footprint.y();
  }
  double PassFootprint(bool lines_across) const {
    return wall && !lines_across ? footprint.y() : footprint.x();
  }
  // A vehicle imaging a wall keeps it to starboard: it heads along the wall.
  Eigen::Vector3d WallHeading() const {
    return Eigen::Vector3d::UnitZ().cross(-normal).normalized();
  }

  bool wall;
  Eigen::Vector3d origin;
  Eigen::Vector3d normal;
  Eigen::Vector3d along;
  Eigen::Vector3d across;
  Eigen::Vector2d footprint;
  double distance;
};

// The stations as they are planned: the jitter's random stream, the clock
// and the image numbering run on across lines and dives.
class StationList {
 public:
  StationList(const SurveyOptions& options, const Rigid3d& vehicle_from_cam,
              uint64_t seed)
      : options_(options), vehicle_from_cam_(vehicle_from_cam), rng_(seed) {}

  bool Full() const {
    return options_.max_images > 0 &&
           static_cast<int>(stations_.size()) >= options_.max_images;
  }

  // Adds the image taken with the camera at `camera_centre` while the
  // vehicle has attitude `rpy`; with `jitter`, the options' noise turns the
  // vehicle about the camera and then moves it. Without `time_s`, the image
  // is taken the vehicle's travel at speed_m_per_s after the previous one,
  // or dive_gap_s after it for the first image of a dive.
  void Add(const Eigen::Vector3d& camera_centre, Eigen::Vector3d rpy,
           bool jitter, int dive, int pass,
           std::optional<double> time_s = std::nullopt) {
    if (jitter) rpy += options_.attitude_jitter_deg * kDegToRad * Gaussian3();
    const Eigen::Matrix3d world_from_vehicle = WorldFromVehicleRotation(rpy);
    Eigen::Vector3d vehicle_position =
        camera_centre - world_from_vehicle * vehicle_from_cam_.translation;
    if (jitter) vehicle_position += options_.position_jitter_m * Gaussian3();
    if (time_s.has_value()) {
      time_ = *time_s;
    } else if (!stations_.empty()) {
      time_ +=
          dive != stations_.back().dive
              ? options_.dive_gap_s
              : (vehicle_position - stations_.back().vehicle_position).norm() /
                    options_.speed_m_per_s;
    }

    SurveyStation station;
    station.image_name = fmt::format("{:05d}", stations_.size());
    station.time_s = time_;
    station.dive = dive;
    station.pass = pass;
    station.vehicle_rpy = rpy;
    station.vehicle_position = vehicle_position;
    Rigid3d world_from_cam;
    world_from_cam.rotation =
        Eigen::Quaterniond(world_from_vehicle) * vehicle_from_cam_.rotation;
    world_from_cam.translation =
        world_from_vehicle * vehicle_from_cam_.translation + vehicle_position;
    station.cam_from_world = world_from_cam.Inverse();
    stations_.push_back(station);
  }

  std::vector<SurveyStation> Release() { return std::move(stations_); }

 private:
  Eigen::Vector3d Gaussian3() {
    return Eigen::Vector3d(normal01_(rng_), normal01_(rng_), normal01_(rng_));
  }

  const SurveyOptions& options_;
  const Rigid3d vehicle_from_cam_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> normal01_{0.0, 1.0};
  double time_ = 0.0;
  std::vector<SurveyStation> stations_;
};

double Yaw(const Eigen::Vector3d& heading) {
  return std::atan2(heading.y(), heading.x());
}

// A rectangle of the survey plane: centre and extent in (u, v).
struct PlaneArea {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  Eigen::Vector2d extent = Eigen::Vector2d::Zero();
};

PlaneArea CoveredArea(const World& world, const SurveyOptions& options) {
  PlaneArea area;
  area.extent = Eigen::Vector2d(options.coverage_along * world.survey_length,
                                options.coverage_across * world.survey_width);
  return area;
}

// Lines over `area` along v (lines_across) or along u, spaced by the
// footprint and overlaps; only the middle one with `single_line`. Over a
// floor the lines run back and forth; along a wall, whose camera looks to
// starboard, all run one way (the vehicle's heading), and across a wall up
// and down with the heading kept.
void FlyLines(const SurveyFrame& frame, const SurveyOptions& options,
              const PlaneArea& area, bool lines_across, bool single_line,
              int dive, StationList* list) {
  const int line_axis = lines_across ? 1 : 0;
  const double footprint_line = frame.LineFootprint(lines_across);
  const double footprint_pass = frame.PassFootprint(lines_across);
  const double half_line =
      0.5 * std::max(0.0, area.extent(line_axis) - footprint_line);
  const double half_pass =
      0.5 * std::max(0.0, area.extent(1 - line_axis) - footprint_pass);
  const std::vector<double> stations =
      Spread(half_line, footprint_line * (1.0 - options.forward_overlap));
  std::vector<double> passes = {0.0};
  if (!single_line) {
    passes = Spread(half_pass, footprint_pass * (1.0 - options.side_overlap));
  }
  const Eigen::Vector3d line_direction =
      lines_across ? frame.across : frame.along;
  for (size_t p = 0; p < passes.size(); ++p) {
    Eigen::Vector3d heading = line_direction;
    bool reversed = p % 2 == 1;
    if (frame.wall) {
      heading = frame.WallHeading();
      if (!lines_across) reversed = heading.dot(frame.along) < 0.0;
    } else if (reversed) {
      heading = -heading;
    }
    for (size_t s = 0; s < stations.size(); ++s) {
      if (list->Full()) return;
      const double position = stations[reversed ? stations.size() - 1 - s : s];
      const double u = area.centre.x() + (lines_across ? passes[p] : position);
      const double v = area.centre.y() + (lines_across ? position : passes[p]);
      list->Add(frame.CameraCentre(u, v),
                Eigen::Vector3d(0.0, 0.0, Yaw(heading)), true, dive,
                static_cast<int>(p));
    }
  }
}

// The covered area cut along its longer axis into num_dives parts, each
// sharing dive_overlap of its area with the next: with parts of length L
// and N dives, the whole is L (N - (N - 1) overlap) long.
void FlyMultiDive(const World& world, const SurveyFrame& frame,
                  const SurveyOptions& options, StationList* list) {
  const PlaneArea whole = CoveredArea(world, options);
  const int cut_axis = whole.extent.x() >= whole.extent.y() ? 0 : 1;
  const int num_dives = options.num_dives;
  const double part = whole.extent(cut_axis) /
                      (num_dives - (num_dives - 1) * options.dive_overlap);
  for (int k = 0; k < num_dives; ++k) {
    PlaneArea area = whole;
    area.extent(cut_axis) = part;
    area.centre(cut_axis) = -0.5 * whole.extent(cut_axis) +
                            (0.5 + k * (1.0 - options.dive_overlap)) * part;
    FlyLines(frame, options, area, k % 2 == 1, false, k + 1, list);
  }
}

// A piece of the video track in the survey plane: a straight line, or an
// arc of `radius` turning counter-clockwise (turn = +1) or clockwise (-1)
// in (u, v).
struct TrackPiece {
  Eigen::Vector2d start = Eigen::Vector2d::Zero();
  Eigen::Vector2d direction = Eigen::Vector2d::UnitX();  // at the start
  double length = 0.0;
  double radius = 0.0;  // 0: straight
  double turn = 1.0;
  int pass = 0;

  // The point at arc length s and the unit tangent there.
  Eigen::Vector2d At(double s, Eigen::Vector2d* tangent) const {
    if (radius == 0.0) {
      *tangent = direction;
      return start + s * direction;
    }
    const Eigen::Vector2d left(-direction.y(), direction.x());
    const Eigen::Vector2d centre = start + turn * radius * left;
    const Eigen::Rotation2Dd rotation(turn * s / radius);
    *tangent = rotation * direction;
    return centre + rotation * (start - centre);
  }
};

// The lawnmower's lines over the covered area, each as long as the area
// less one footprint, joined into one track: half-circle turns over a
// floor; over a wall straight moves up it, the vehicle then reversing along
// the next line so that its camera stays on the wall.
std::vector<TrackPiece> VideoTrack(const World& world, const SurveyFrame& frame,
                                   const SurveyOptions& options) {
  const PlaneArea area = CoveredArea(world, options);
  const double footprint_line = frame.LineFootprint(false);
  const double footprint_pass = frame.PassFootprint(false);
  const double half_line =
      0.5 * std::max(0.0, area.extent.x() - footprint_line);
  const double half_pass =
      0.5 * std::max(0.0, area.extent.y() - footprint_pass);
  const std::vector<double> passes =
      Spread(half_pass, footprint_pass * (1.0 - options.side_overlap));
  const double first_direction =
      frame.wall && frame.WallHeading().dot(frame.along) < 0.0 ? -1.0 : 1.0;

  std::vector<TrackPiece> track;
  for (size_t p = 0; p < passes.size(); ++p) {
    const double direction = p % 2 == 0 ? first_direction : -first_direction;
    TrackPiece line;
    line.start = Eigen::Vector2d(-direction * half_line, passes[p]);
    line.direction = Eigen::Vector2d(direction, 0.0);
    line.length = 2.0 * half_line;
    line.pass = static_cast<int>(p);
    track.push_back(line);
    if (p + 1 == passes.size()) break;
    const double step = passes[p + 1] - passes[p];
    TrackPiece join;
    join.start = Eigen::Vector2d(direction * half_line, passes[p]);
    join.pass = line.pass;
    if (frame.wall) {
      join.direction = Eigen::Vector2d(0.0, step > 0.0 ? 1.0 : -1.0);
      join.length = std::abs(step);
    } else {
      join.direction = line.direction;
      join.radius = 0.5 * std::abs(step);
      join.length = M_PI * join.radius;
      // Towards the next line: left of the travel when it lies at +v for a
      // line along +u.
      join.turn = direction * step > 0.0 ? 1.0 : -1.0;
    }
    track.push_back(join);
  }
  return track;
}

void FlyVideo(const World& world, const SurveyFrame& frame,
              const SurveyOptions& options, StationList* list) {
  const std::vector<TrackPiece> track = VideoTrack(world, frame, options);
  double track_length = 0.0;
  for (const TrackPiece& piece : track) track_length += piece.length;
  const double frame_spacing = options.speed_m_per_s / options.frame_rate_hz;
  // Arc lengths are k * spacing, not a running sum, so that frames stay
  // exactly spaced; the tolerance keeps a frame that ends the track.
  const double end = track_length * (1.0 + 1e-12) + 1e-12;
  for (int k = 0; k * frame_spacing <= end; ++k) {
    if (list->Full()) return;
    double s = k * frame_spacing;
    size_t i = 0;
    while (i + 1 < track.size() && s > track[i].length) {
      s -= track[i].length;
      ++i;
    }
    Eigen::Vector2d tangent;
    const Eigen::Vector2d point =
        track[i].At(std::min(s, track[i].length), &tangent);
    const Eigen::Vector3d heading =
        frame.wall ? frame.WallHeading()
                   : Eigen::Vector3d(tangent.x() * frame.along +
                                     tangent.y() * frame.across);
    list->Add(frame.CameraCentre(point.x(), point.y()),
              Eigen::Vector3d(0.0, 0.0, Yaw(heading)), true, 1, track[i].pass,
              k / options.frame_rate_hz);
  }
}

std::string FormatPoint(const Eigen::Vector3d& point) {
  return fmt::format("({:.6g}, {:.6g}, {:.6g})", point.x(), point.y(),
                     point.z());
}

struct ViewTarget {
  Eigen::Vector3d point;
  Eigen::Vector3d normal;  // unit, into the water
};

// The surface point the views look at and the mean normal around it.
ViewTarget FindViewTarget(const World& world, const SurveyOptions& options) {
  const TriangleMesh& mesh = world.mesh;
  if (mesh.triangles.empty()) {
    throw ErrorAt("views survey of world '", world.name,
                  "': the mesh has no triangles");
  }
  const Eigen::Vector3d survey_normal = world.survey_normal.normalized();
  ViewTarget target;
  if (options.views_target.has_value()) {
    target.point = *options.views_target;
  } else {
    Eigen::AlignedBox3d bounds;
    for (const Eigen::Vector3d& vertex : mesh.vertices) bounds.extend(vertex);
    // From outside the mesh's bounds, the first surface met is the one a
    // survey over the plane sees.
    const double back_off = bounds.diagonal().norm() +
                            (world.survey_origin - bounds.center()).norm() +
                            1.0;
    const RayCaster caster(mesh);
    const auto hit = caster.Intersect(
        world.survey_origin + back_off * survey_normal, -survey_normal);
    if (!hit.has_value()) {
      throw ErrorAt("views survey of world '", world.name,
                    "': the line through survey_origin ",
                    FormatPoint(world.survey_origin),
                    " along the survey normal misses the mesh; set "
                    "survey_options.views_target");
    }
    target.point = hit->point_in_world;
  }
  // The mean over a neighbourhood, not the normal of the facet hit: at the
  // mesh's cm scale a facet's normal follows the roughness, and the views
  // are of the scene around the point.
  const double radius_squared =
      options.views_normal_radius_m * options.views_normal_radius_m;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3i& triangle : mesh.triangles) {
    const Eigen::Vector3d& a = mesh.vertices[triangle[0]];
    const Eigen::Vector3d& b = mesh.vertices[triangle[1]];
    const Eigen::Vector3d& c = mesh.vertices[triangle[2]];
    if (((a + b + c) / 3.0 - target.point).squaredNorm() > radius_squared) {
      continue;
    }
    // Twice the area times the unit normal: an area-weighted sum.
    const Eigen::Vector3d area_normal = (b - a).cross(c - a);
    if (area_normal.dot(survey_normal) > 0.0) sum += area_normal;
  }
  if (!(sum.norm() > 0.0)) {
    throw ErrorAt("views survey of world '", world.name,
                  "': no triangle facing the survey side has its centroid "
                  "within views_normal_radius_m = ",
                  options.views_normal_radius_m, " m of the target ",
                  FormatPoint(target.point));
  }
  target.normal = sum.normalized();
  return target;
}

void FlyViews(const World& world, const SurveyFrame& frame,
              const SurveyOptions& options, const Rigid3d& vehicle_from_cam,
              StationList* list) {
  const ViewTarget target = FindViewTarget(world, options);
  // The vehicle whose nominal mount looks along -survey_normal (heading
  // along the survey axis over a floor, along the wall at a wall), turned
  // so that it looks along -target.normal.
  Eigen::Matrix3d world_from_vehicle_0;
  if (frame.wall) {
    world_from_vehicle_0.col(0) = frame.WallHeading();
    world_from_vehicle_0.col(1) = frame.normal;
  } else {
    world_from_vehicle_0.col(0) =
        (frame.along - frame.along.dot(frame.normal) * frame.normal)
            .normalized();
    world_from_vehicle_0.col(1) =
        frame.normal.cross(world_from_vehicle_0.col(0));
  }
  world_from_vehicle_0.col(2) =
      world_from_vehicle_0.col(0).cross(world_from_vehicle_0.col(1));
  const Eigen::Matrix3d world_from_cam_0 =
      Eigen::Quaterniond::FromTwoVectors(frame.normal, target.normal)
          .toRotationMatrix() *
      world_from_vehicle_0 * NominalVehicleFromCamRotation(MountOf(frame.wall));

  const Eigen::Matrix3d cam_from_vehicle =
      vehicle_from_cam.RotationMatrix().transpose();
  const int half_count = static_cast<int>(
      std::lround(options.views_max_angle_deg / options.views_step_deg));
  const double step = options.views_step_deg * kDegToRad;
  for (int i = -half_count; i <= half_count; ++i) {
    const int pass = i + half_count;
    for (int j = -half_count; j <= half_count; ++j) {
      if (list->Full()) return;
      const double pitch = i * step;
      const double roll = (pass % 2 == 0 ? j : -j) * step;
      const Eigen::Matrix3d world_from_cam =
          world_from_cam_0 *
          Eigen::AngleAxisd(pitch, -Eigen::Vector3d::UnitX())
              .toRotationMatrix() *
          Eigen::AngleAxisd(roll, -Eigen::Vector3d::UnitY()).toRotationMatrix();
      const Eigen::Matrix3d world_from_vehicle =
          world_from_cam * cam_from_vehicle;
      // Roll and yaw become one near pitch +-90 deg: the attitude written
      // to nav.csv would lose its precision.
      if (std::abs(world_from_vehicle(2, 0)) > std::sin(85.0 * kDegToRad)) {
        throw ErrorAt(
            "views survey of world '", world.name, "': at view pitch ",
            pitch / kDegToRad, " deg, roll ", roll / kDegToRad,
            " deg the vehicle would pitch beyond 85 deg (the "
            "surface normal at the target ",
            FormatPoint(target.point), " is ",
            std::acos(std::clamp(target.normal.dot(frame.normal), -1.0, 1.0)) /
                kDegToRad,
            " deg from the survey normal); choose another "
            "views_target or a smaller views_max_angle_deg");
      }
      list->Add(target.point - options.views_distance_m * world_from_cam.col(2),
                RollPitchYawFromRotation(world_from_vehicle),
                options.views_jitter, 1, pass);
    }
  }
}

}  // namespace

std::vector<SurveyStation> PlanSurvey(SurveyKind kind, const World& world,
                                      const Camera& camera,
                                      const SurveyOptions& options,
                                      uint64_t seed) {
  options.Check();
  const SurveyFrame frame(world, camera, options);
  const Rigid3d vehicle_from_cam = VehicleFromCam(world, options);
  StationList list(options, vehicle_from_cam, seed);
  switch (kind) {
    case SurveyKind::kLawnmower:
    case SurveyKind::kSinglePass:
      FlyLines(frame, options, CoveredArea(world, options), false,
               kind == SurveyKind::kSinglePass, 1, &list);
      break;
    case SurveyKind::kMultiDive:
      FlyMultiDive(world, frame, options, &list);
      break;
    case SurveyKind::kVideo:
      FlyVideo(world, frame, options, &list);
      break;
    case SurveyKind::kViews:
      FlyViews(world, frame, options, vehicle_from_cam, &list);
      break;
  }
  return list.Release();
}

}  // namespace uw::sim
