// Priors from uwsim's own files — truth/nav.csv, image_times.csv,
// truth/rig.json and the mount, lever arm and boresight of truth/sim.json —
// against uwsim's true camera poses (truth/images.txt). uwsim moves the
// vehicle linearly with a slerped attitude between stations, as the
// importer interpolates, so the priors are the true poses to rounding;
// except where uwsim extrapolates a pass beyond its end while the log,
// which knows no passes, interpolates across the turn to the next.
#include <cmath>
#include <fstream>
#include <iostream>
#include <map>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <Eigen/Geometry>
#include <GeographicLib/UTMUPS.hpp>
#include <nlohmann/json.hpp>

#include "colmap_plugins/nav/camera_prior.h"
#include "colmap_plugins/nav/nav_log.h"
#include "colmap_plugins/scene/model_io.h"
#include "common/util/file.h"
#include "common/util/time_text.h"
#include "sim/generate.h"
#include "sim/test_sim_config.h"
#include "tests/support/process.h"

namespace uw {
namespace {

namespace fs = std::filesystem;

// The rig of the acceptance tests: 30 and -45 ms time offsets.
sim::RigOptions TestRig() {
  sim::RigOptions rig;
  sim::RigCameraOptions right;
  right.camera.model_id = CameraModelId::kPinhole;
  right.camera.width = 160;
  right.camera.height = 120;
  right.camera.params = {140.0, 140.0, 80.0, 60.0};
  right.cam_from_rig.rotation =
      Eigen::Quaterniond(Eigen::AngleAxisd(0.05, Eigen::Vector3d::UnitY()));
  right.cam_from_rig.translation = Eigen::Vector3d(-0.3, 0.0, 0.0);
  right.time_offset_s = 0.03;
  sim::RigCameraOptions left = right;
  left.cam_from_rig.rotation =
      Eigen::Quaterniond(Eigen::AngleAxisd(-0.04, Eigen::Vector3d::UnitX()));
  left.cam_from_rig.translation = Eigen::Vector3d(0.3, 0.05, 0.0);
  left.time_offset_s = -0.045;
  rig.cameras = {right, left};
  return rig;
}

// The stations a camera firing dt after station i is interpolated between:
// uwsim's rule (sim/rig.cc: within the station's pass) or, with
// `within_pass` false, the log's (within the dive).
std::pair<size_t, size_t> Segment(const std::vector<sim::SurveyStation>& s,
                                  size_t i, double dt, bool within_pass) {
  const auto same = [&](size_t j) {
    return s[j].dive == s[i].dive && (!within_pass || s[j].pass == s[i].pass);
  };
  if (dt >= 0.0 && i + 1 < s.size() && same(i + 1)) return {i, i + 1};
  if (i > 0 && same(i - 1)) return {i - 1, i};
  if (i + 1 < s.size() && same(i + 1)) return {i, i + 1};
  return {i, i};
}

// Largest centre (m) and rotation (rad) differences of a set of images.
struct Difference {
  double centre = 0.0;
  double angle = 0.0;
  size_t count = 0;

  void Add(double centre_m, double angle_rad) {
    centre = std::max(centre, centre_m);
    angle = std::max(angle, angle_rad);
    ++count;
  }
};

std::ostream& operator<<(std::ostream& out, const Difference& difference) {
  return out << difference.centre << " m, " << difference.angle << " rad ("
             << difference.count << " images)";
}

struct Errors {
  Difference reference;  // the reference camera
  Difference rig;        // rig cameras, interpolated as uwsim does
  Difference pass_end;   // rig cameras past the end of a pass
};

// The camera on the vehicle uwsim used (truth/sim.json of `sim_dir`).
NavToCameraOptions CameraOnVehicle(const fs::path& sim_dir, CameraMount mount) {
  const nlohmann::json sim_json =
      nlohmann::json::parse(ReadFileToString(sim_dir / "truth" / "sim.json"));
  NavToCameraOptions options;
  options.mount = mount;
  for (int k = 0; k < 3; ++k) {
    options.lever_arm_m(k) = sim_json["survey_options"]["lever_arm_m"][k];
    options.boresight_deg(k) = sim_json["survey_options"]["boresight_deg"][k];
  }
  return options;
}

// Generates `config` into a fresh folder, computes the priors from its
// files and compares them with truth/images.txt.
Errors PriorsAgainstTruth(const sim::SimConfig& config, CameraMount mount,
                          const std::string& suite) {
  const fs::path out = testing::FreshTestDir(suite) / "sim";
  sim::Generate(config, out);
  NavToCameraOptions options = CameraOnVehicle(out, mount);
  const std::vector<NavRecord> nav =
      ReadNavigationCsv(out / "truth" / "nav.csv");
  const std::vector<ImageTime> times =
      ReadImageTimesCsv(out / "image_times.csv");
  const bool has_rig = !config.rig.cameras.empty();
  RigConfig rig;
  if (has_rig) rig = ReadRigConfig(out / "truth" / "rig.json");
  const std::vector<CameraPrior> priors = CameraPriorsFromNavigation(
      nav, &times, options, has_rig ? &rig : nullptr);
  EXPECT_EQ(priors.size(), times.size());

  // The same from the log's names and the rig's delays.
  std::vector<std::string> names;
  for (const ImageTime& time : times) names.push_back(time.image_name);
  const std::vector<ImageTime> rig_times =
      has_rig ? RigImageTimes(nav, rig, names) : std::vector<ImageTime>();
  const std::vector<CameraPrior> by_name = CameraPriorsFromNavigation(
      nav, has_rig ? &rig_times : nullptr, options, has_rig ? &rig : nullptr);
  EXPECT_EQ(by_name.size(), priors.size());
  for (size_t i = 0; i < std::min(by_name.size(), priors.size()); ++i) {
    EXPECT_EQ(by_name[i].image_name, priors[i].image_name);
    EXPECT_EQ(by_name[i].position, priors[i].position) << priors[i].image_name;
  }

  const std::vector<sim::SurveyStation> stations = sim::PlanSurvey(
      config.survey,
      sim::MakeWorld(config.world, config.world_options, config.seed),
      config.camera, config.survey_options, config.seed);
  const Reconstruction truth = ReadModel(out / "truth");
  std::map<std::string, const Image*> truth_of_name;
  for (const Image& image : truth.Images()) truth_of_name[image.name] = &image;
  Errors errors;
  for (const CameraPrior& prior : priors) {
    const Image& image = *truth_of_name.at(prior.image_name);
    const double centre_error =
        (prior.position - image.ProjectionCenter()).norm();
    const double angle_error = prior.cam_from_world_rotation->angularDistance(
        image.cam_from_world.rotation.normalized());
    const RigCameraConfig* camera =
        has_rig ? rig.CameraOfImage(prior.image_name) : nullptr;
    if (camera == nullptr || camera->time_offset_s == 0.0) {
      errors.reference.Add(centre_error, angle_error);
      continue;
    }
    const size_t station =
        std::stoul(prior.image_name.substr(camera->image_prefix.size(), 5));
    if (Segment(stations, station, camera->time_offset_s, true) ==
        Segment(stations, station, camera->time_offset_s, false)) {
      errors.rig.Add(centre_error, angle_error);
    } else {
      errors.pass_end.Add(centre_error, angle_error);
    }
  }
  std::cout << "[ figures ] " << suite << ": " << priors.size()
            << " priors vs truth/images.txt, largest differences: reference "
               "camera "
            << errors.reference << "; rig cameras interpolated as uwsim "
            << errors.rig << "; rig cameras past a pass end " << errors.pass_end
            << "\n";
  return errors;
}

// The acceptance bound: uwsim's poses to 1e-9 m and 1e-9 rad.
void ExpectExact(const Difference& difference) {
  EXPECT_LT(difference.centre, 1e-9);
  EXPECT_LT(difference.angle, 1e-9);
}

TEST(CameraPriorUwsim, FloorSurveyWithAnUnsynchronisedRig) {
  sim::SimConfig config = sim::SmallSimConfig();
  config.survey_options.max_images = 16;
  config.lasers.every_nth_image = 0;
  config.rig = TestRig();
  const Errors errors =
      PriorsAgainstTruth(config, CameraMount::kDown, "uw_prior_uwsim_floor");
  ExpectExact(errors.reference);
  ExpectExact(errors.rig);
  EXPECT_EQ(errors.reference.count + errors.rig.count + errors.pass_end.count,
            48u);
  // Where a pass ends, the camera firing after the last station (+30 ms)
  // or before the first (-45 ms) is placed by uwsim on the pass extended,
  // by the log on the way to the next pass (turning round): centimetres
  // and a few degrees apart.
  EXPECT_GT(errors.pass_end.count, 0u);
  EXPECT_LT(errors.pass_end.centre, 0.1);
}

TEST(CameraPriorUwsim, WallSurveyWithAnUnsynchronisedRig) {
  sim::SimConfig config = sim::SmallSimConfig();
  config.world = sim::WorldKind::kScarp;
  config.survey = sim::SurveyKind::kSinglePass;
  config.world_options.scarp.length_m = 30.0;
  config.world_options.scarp.vertex_spacing_m = 0.25;
  config.survey_options.max_images = 8;
  config.lasers.every_nth_image = 0;
  config.rig = TestRig();
  const Errors errors = PriorsAgainstTruth(config, CameraMount::kStarboard,
                                           "uw_prior_uwsim_wall");
  ExpectExact(errors.reference);
  ExpectExact(errors.rig);
  EXPECT_EQ(errors.rig.count, 16u);
  EXPECT_EQ(errors.pass_end.count, 0u);
}

// Dives an hour apart: image_times.csv has no dive column, the span of each
// dive's log places every image.
TEST(CameraPriorUwsim, MultiDiveImagesFindTheirDives) {
  sim::SimConfig config = sim::SmallSimConfig();
  config.survey = sim::SurveyKind::kMultiDive;
  config.camera.width = 128;
  config.camera.height = 96;
  config.camera.params = {106.0, 64.0, 48.0, -0.04};
  config.lasers.every_nth_image = 0;
  const Errors errors = PriorsAgainstTruth(config, CameraMount::kDown,
                                           "uw_prior_uwsim_multi_dive");
  ExpectExact(errors.reference);
  EXPECT_EQ(errors.reference.count, 24u);
}

// uwsim's local log as a WGS84 one (lat,lon,depth or UTM), as a USBL or a
// GPS writes it: each fix's heading is taken clockwise from its own north.
void WriteGeographicLog(const std::vector<NavRecord>& nav,
                        const LocalEnu& local, bool utm, const fs::path& path) {
  std::string text =
      std::string("image_name,time,dive,") +
      (utm ? "easting,northing,zone" : "lat,lon") +
      ",depth,roll,pitch,heading,std_x,std_y,std_z,std_roll,std_pitch,"
      "std_heading\n";
  constexpr double kRadToDeg = 180.0 / M_PI;
  for (const NavRecord& record : nav) {
    const Eigen::Vector3d fix = local.ToGeodetic(record.position);
    std::string where = fmt::format("{:.17g},{:.17g}", fix(0), fix(1));
    if (utm) {
      int zone = 0;
      bool north = true;
      double easting = 0.0;
      double northing = 0.0;
      GeographicLib::UTMUPS::Forward(fix(0), fix(1), zone, north, easting,
                                     northing);
      where = fmt::format("{:.17g},{:.17g},{}{}", easting, northing, zone,
                          north ? "n" : "s");
    }
    const double heading =
        local.HeadingFromYaw(record.rpy_rad(2) * kRadToDeg, record.position);
    text += fmt::format(
        "{},{:.17g},{},{},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},"
        "{:.17g},{:.17g},{:.17g},{:.17g}\n",
        record.image_name, record.time_s, record.dive, where, -fix(2),
        record.rpy_rad(0) * kRadToDeg, record.rpy_rad(1) * kRadToDeg, heading,
        record.position_sigma(0), record.position_sigma(1),
        record.position_sigma(2), record.rpy_sigma_rad(0) * kRadToDeg,
        record.rpy_sigma_rad(1) * kRadToDeg,
        record.rpy_sigma_rad(2) * kRadToDeg);
  }
  std::ofstream(path, std::ios::binary) << text;
}

// Acceptance 1 (issue 17): a survey's log written as WGS84 lat,lon,depth and
// as UTM, read at the origin it was written at, gives the priors of its
// local log to < 1 mm and 1e-6 rad (here, to rounding). The origin is put
// far from the equator and the survey 20 km east of it, so that north at
// the fixes is turned by the meridians' convergence (0.2 deg at 60 deg N).
TEST(CameraPriorUwsim, AGeographicLogGivesTheLocalLogsPriors) {
  sim::SimConfig config = sim::SmallSimConfig();
  config.survey_options.max_images = 16;
  config.lasers.every_nth_image = 0;
  config.rig = TestRig();
  const fs::path dir = testing::FreshTestDir("uw_prior_uwsim_geographic");
  sim::Generate(config, dir / "sim");
  NavToCameraOptions options = CameraOnVehicle(dir / "sim", CameraMount::kDown);
  const std::vector<ImageTime> times =
      ReadImageTimesCsv(dir / "sim" / "image_times.csv");
  const RigConfig rig = ReadRigConfig(dir / "sim" / "truth" / "rig.json");
  std::vector<NavRecord> nav =
      ReadNavigationCsv(dir / "sim" / "truth" / "nav.csv");
  for (NavRecord& record : nav) record.position.x() += 20000.0;
  const std::vector<CameraPrior> local_priors =
      CameraPriorsFromNavigation(nav, &times, options, &rig);

  const GeoOrigin origin{60.25, 5.125, 0.0};
  const LocalEnu local(origin);
  for (const bool utm : {false, true}) {
    const fs::path path = dir / (utm ? "nav_utm.csv" : "nav_latlon.csv");
    WriteGeographicLog(nav, local, utm, path);
    NavLogFrame frame;
    const std::vector<NavRecord> geographic =
        ReadNavigationCsv(path, origin, &frame);
    EXPECT_EQ(frame.position_columns,
              utm ? "easting,northing,zone,depth" : "lat,lon,depth");
    ASSERT_TRUE(frame.origin);
    EXPECT_FALSE(frame.origin_automatic);
    const std::vector<CameraPrior> priors =
        CameraPriorsFromNavigation(geographic, &times, options, &rig);
    ASSERT_EQ(priors.size(), local_priors.size());
    double centre = 0.0;
    double angle = 0.0;
    double covariance = 0.0;
    for (size_t i = 0; i < priors.size(); ++i) {
      centre = std::max(centre,
                        (priors[i].position - local_priors[i].position).norm());
      angle =
          std::max(angle, priors[i].cam_from_world_rotation->angularDistance(
                              *local_priors[i].cam_from_world_rotation));
      covariance = std::max(covariance, (priors[i].position_covariance -
                                         local_priors[i].position_covariance)
                                            .norm());
    }
    std::cout << "[ figures ] " << path.filename().string() << ": "
              << priors.size() << " priors, largest differences from the "
              << "local log's: centre " << centre << " m, rotation " << angle
              << " rad, position covariance " << covariance << " m^2\n";
    EXPECT_LT(centre, 1e-3);
    EXPECT_LT(angle, 1e-6);
    EXPECT_LT(covariance, 1e-9);
  }
}

// The same survey as a GPS/USBL logger's NMEA: GGA fixes (minutes to 1e-8,
// 0.02 mm), an HDT heading before each, the date from ZDA, the survey's
// clock starting at 12:00Z. NMEA has no roll, pitch or sigmas, so the local
// log is compared with those dropped too; the priors agree to < 1 mm.
TEST(CameraPriorUwsim, AnNmeaLogGivesTheLocalLogsPriors) {
  sim::SimConfig config = sim::SmallSimConfig();
  config.survey_options.max_images = 16;
  config.lasers.every_nth_image = 0;
  const fs::path dir = testing::FreshTestDir("uw_prior_uwsim_nmea");
  sim::Generate(config, dir / "sim");
  NavToCameraOptions options = CameraOnVehicle(dir / "sim", CameraMount::kDown);
  const std::vector<ImageTime> times =
      ReadImageTimesCsv(dir / "sim" / "image_times.csv");
  std::vector<NavRecord> nav =
      ReadNavigationCsv(dir / "sim" / "truth" / "nav.csv");
  for (NavRecord& record : nav) {
    record.image_name.clear();
    record.has_roll_pitch = false;
    record.rpy_rad.head<2>().setZero();
    record.rpy_sigma_rad.setZero();
    record.position_sigma.setZero();
  }
  const std::vector<CameraPrior> local_priors =
      CameraPriorsFromNavigation(nav, &times, options, nullptr);

  const GeoOrigin origin{-12.25, 130.75, 0.0};
  const LocalEnu local(origin);
  const double start = *UnixTimeOfDay(2024, 10, 8) + 12 * 3600.0;
  std::string text = "# uwsim's survey as NMEA\n";
  const auto sentence = [&](const std::string& body) {
    unsigned checksum = 0;
    for (const char c : body) checksum ^= static_cast<unsigned char>(c);
    text += fmt::format("${}*{:02X}\n", body, checksum);
  };
  sentence("GPZDA,120000.000000,08,10,2024,00,00");
  for (const NavRecord& record : nav) {
    const Eigen::Vector3d fix = local.ToGeodetic(record.position);
    const double t = 12 * 3600.0 + record.time_s;
    const int hours = static_cast<int>(t / 3600.0);
    const int minutes = static_cast<int>((t - 3600.0 * hours) / 60.0);
    const double seconds = t - 3600.0 * hours - 60.0 * minutes;
    const auto dm = [](double degrees) {
      const double whole = std::floor(std::abs(degrees));
      return 100.0 * whole + (std::abs(degrees) - whole) * 60.0;
    };
    sentence(fmt::format("HEHDT,{:.8f},T",
                         local.HeadingFromYaw(record.rpy_rad(2) * 180.0 / M_PI,
                                              record.position)));
    sentence(fmt::format(
        "GPGGA,{:02d}{:02d}{:09.6f},{:013.8f},{},{:014.8f},{},1,12,0.8,{:.6f},"
        "M,0.0,M,,",
        hours, minutes, seconds, dm(fix(0)), fix(0) < 0 ? "S" : "N", dm(fix(1)),
        fix(1) < 0 ? "W" : "E", fix(2)));
  }
  std::ofstream(dir / "nav.nmea", std::ios::binary) << text;
  NavLogOptions log;
  log.origin = origin;
  NavLogFrame frame;
  const std::vector<NavRecord> nmea =
      ReadNavigationLog(dir / "nav.nmea", log, &frame);
  EXPECT_EQ(frame.position_columns, "NMEA GGA");
  ASSERT_EQ(nmea.size(), nav.size());
  EXPECT_EQ(nmea.front().time_s, start + nav.front().time_s);
  options.time_offset_s = start;
  const std::vector<CameraPrior> priors =
      CameraPriorsFromNavigation(nmea, &times, options, nullptr);
  ASSERT_EQ(priors.size(), local_priors.size());
  double centre = 0.0;
  double covariance = 0.0;
  for (size_t i = 0; i < priors.size(); ++i) {
    EXPECT_FALSE(priors[i].cam_from_world_rotation);
    centre = std::max(centre,
                      (priors[i].position - local_priors[i].position).norm());
    covariance = std::max(covariance, (priors[i].position_covariance -
                                       local_priors[i].position_covariance)
                                          .norm());
  }
  std::cout << "[ figures ] nav.nmea: " << priors.size()
            << " priors, largest differences from the local log's: centre "
            << centre << " m, position covariance " << covariance << " m^2\n";
  EXPECT_LT(centre, 1e-3);
  EXPECT_LT(covariance, 1e-9);
}

}  // namespace
}  // namespace uw
