#include "calib/mrcal_calibration.h"

#include <cmath>
#include <cstdio>
#include <memory>
#include <sstream>

#include <Eigen/Geometry>
#include <opencv2/calib3d.hpp>

extern "C" {
// mrcal's headers have no extern "C" of their own.
#include <mrcal/mrcal.h>
}

#include "colmap_plugins/util/error.h"
#include "colmap_plugins/util/file.h"

namespace uw {
namespace {

mrcal_lensmodel_t LensModel(const std::string& name) {
  mrcal_lensmodel_t model;
  if (!mrcal_lensmodel_from_name(&model, name.c_str()) ||
      !mrcal_lensmodel_type_is_valid(model.type)) {
    throw ErrorAt("lens model '", name,
                  "' is not one of mrcal's (e.g. LENSMODEL_OPENCV4, "
                  "LENSMODEL_OPENCV8, LENSMODEL_SPLINED_STEREOGRAPHIC_order=3_"
                  "Nx=16_Ny=12_fov_x_deg=100)");
  }
  return model;
}

Eigen::Matrix3d RotationFromRodrigues(const mrcal_point3_t& r) {
  const Eigen::Vector3d axis(r.x, r.y, r.z);
  const double angle = axis.norm();
  if (angle < 1e-300) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(angle, axis / angle).toRotationMatrix();
}

std::string Number(double value) {
  char buffer[40];
  std::snprintf(buffer, sizeof(buffer), "%.17g", value);
  return buffer;
}

// One mrcal_optimize() call on the problem's current state.
struct Problem {
  std::vector<double> intrinsics;
  std::vector<mrcal_pose_t> frames_toref;  // = cam_from_board (camera = ref)
  std::vector<mrcal_observation_board_t> observations;
  std::vector<mrcal_point3_t> pool;  // (Nobs, H, W): x, y, weight
  std::vector<bool> found;           // per pool entry: found by the detector
  mrcal_calobject_warp_t warp{};
  int imagersize[2] = {0, 0};

  mrcal_stats_t Solve(const mrcal_lensmodel_t& model, bool core,
                      bool distortions, bool regularization, bool outliers,
                      bool warp_too, const CalibrationBoard& board) {
    mrcal_problem_selections_t selections{};
    selections.do_optimize_intrinsics_core = core;
    selections.do_optimize_intrinsics_distortions = distortions;
    selections.do_optimize_extrinsics = true;
    selections.do_optimize_frames = true;
    selections.do_optimize_calobject_warp = warp_too;
    selections.do_apply_regularization = regularization;
    selections.do_apply_outlier_rejection = outliers;
    const mrcal_problem_constants_t constants{-1.0, -1.0};
    const mrcal_stats_t stats = mrcal_optimize(
        nullptr, 0, nullptr, 0, intrinsics.data(), nullptr, frames_toref.data(),
        nullptr, warp_too ? &warp : nullptr, 1, 0,
        static_cast<int>(frames_toref.size()), 0, 0, observations.data(),
        nullptr, static_cast<int>(observations.size()), 0, pool.data(), &model,
        imagersize, selections, &constants, board.spacing_m, board.grid_width,
        board.grid_height, false, false);
    if (!std::isfinite(stats.rms_reproj_error__pixels) ||
        stats.rms_reproj_error__pixels < 0.0) {
      throw Error("mrcal_optimize failed (no finite solution)");
    }
    return stats;
  }
};

}  // namespace

void MrcalCalibrationOptions::Check() const {
  LensModel(lens_model);
  if (!(focal_px > 0.0) || !std::isfinite(focal_px)) {
    throw Error("calibration: focal_px (the seed focal length) must be > 0");
  }
  if (image_width <= 0 || image_height <= 0) {
    throw Error("calibration: image_width and image_height must be > 0");
  }
}

MrcalCalibration CalibrateWithMrcal(
    const std::vector<BoardObservation>& observations,
    const CalibrationBoard& board, const MrcalCalibrationOptions& options) {
  options.Check();
  const mrcal_lensmodel_t model = LensModel(options.lens_model);
  const int num_params = mrcal_lensmodel_num_params(&model);
  const std::vector<Eigen::Vector3d> corners = board.CornersInBoard();
  const int num_corners = board.NumCorners();

  MrcalCalibration result;
  result.lens_model = options.lens_model;
  result.image_width = options.image_width;
  result.image_height = options.image_height;

  Problem problem;
  problem.imagersize[0] = options.image_width;
  problem.imagersize[1] = options.image_height;
  // The stereographic seed (mrcal's seed_stereographic): f, centre at the
  // image's middle in mrcal's pixel convention.
  problem.intrinsics = {options.focal_px, options.focal_px,
                        (options.image_width - 1) / 2.0,
                        (options.image_height - 1) / 2.0};
  mrcal_lensmodel_t stereographic;
  stereographic.type = MRCAL_LENSMODEL_STEREOGRAPHIC;

  std::vector<cv::Point3d> object_points;
  for (const Eigen::Vector3d& corner : corners) {
    object_points.emplace_back(corner.x(), corner.y(), corner.z());
  }
  for (const BoardObservation& observation : observations) {
    if (!observation.Found()) continue;
    if (static_cast<int>(observation.pixels.size()) != num_corners) {
      throw ErrorAt(observation.image, ": ", observation.pixels.size(),
                    " corners, but the board ", board.ToString(), " has ",
                    num_corners);
    }
    // Board pose by PnP of the seed's unprojections (normalised, z = 1).
    std::vector<cv::Point3d> seen_in_board;
    std::vector<cv::Point2d> normalised;
    for (int k = 0; k < num_corners; ++k) {
      if (observation.weights[k] <= 0.0) continue;
      const mrcal_point2_t q{
          {observation.pixels[k].x(), observation.pixels[k].y()}};
      mrcal_point3_t v;
      if (!mrcal_unproject(&v, &q, 1, &stereographic,
                           problem.intrinsics.data()) ||
          !(v.z > 0.0)) {
        continue;
      }
      seen_in_board.push_back(object_points[k]);
      normalised.emplace_back(v.x / v.z, v.y / v.z);
    }
    if (seen_in_board.size() < 4) continue;  // mrcal drops such images too
    cv::Mat rvec;
    cv::Mat tvec;
    if (!cv::solvePnP(seen_in_board, normalised, cv::Mat::eye(3, 3, CV_64F),
                      cv::Mat(), rvec, tvec)) {
      continue;
    }
    mrcal_pose_t pose;
    for (int i = 0; i < 3; ++i) {
      pose.r.xyz[i] = rvec.at<double>(i);
      pose.t.xyz[i] = tvec.at<double>(i);
    }
    const int frame = static_cast<int>(problem.frames_toref.size());
    problem.frames_toref.push_back(pose);
    problem.observations.push_back({{0, -1}, frame});
    for (int k = 0; k < num_corners; ++k) {
      mrcal_point3_t point;
      point.x = observation.pixels[k].x();
      point.y = observation.pixels[k].y();
      point.z = observation.weights[k] > 0.0 ? observation.weights[k] : -1.0;
      problem.pool.push_back(point);
      problem.found.push_back(observation.weights[k] > 0.0);
      result.num_corners_observed += observation.weights[k] > 0.0;
    }
    result.images.push_back(observation.image);
  }

  // Enough data: 3 views at least (one view cannot tell focal length from
  // distance), and more measurements than unknowns.
  const int num_views = static_cast<int>(problem.frames_toref.size());
  const int unknowns = 6 * num_views + num_params;
  if (num_views < 3 || 2 * result.num_corners_observed < 2 * unknowns) {
    throw ErrorAt("calibration: ", num_views, " board views with ",
                  result.num_corners_observed, " corners are too few for ",
                  options.lens_model, " (", num_params,
                  " intrinsics): need at least 3 views and twice as many "
                  "corner coordinates as unknowns (",
                  2 * unknowns, ")");
  }

  // mrcal-calibrate-cameras' stages.
  problem.Solve(stereographic, false, false, false, false, false, board);
  problem.Solve(stereographic, true, false, false, false, false, board);
  problem.intrinsics.resize(num_params, 0.0);
  const int num_missing =
      static_cast<int>(problem.pool.size()) - result.num_corners_observed;
  mrcal_stats_t stats = problem.Solve(model, true, true, true,
                                      options.outlier_rejection, false, board);
  if (options.calobject_warp) {
    stats = problem.Solve(model, true, true, options.regularization,
                          options.outlier_rejection, true, board);
  } else if (!options.regularization) {
    stats = problem.Solve(model, true, true, false, options.outlier_rejection,
                          false, board);
  }
  result.rms_px = stats.rms_reproj_error__pixels;
  result.num_outliers = stats.Noutliers - num_missing;
  result.intrinsics = problem.intrinsics;
  result.calobject_warp = {problem.warp.x2, problem.warp.y2};

  const std::vector<bool>& found = problem.found;
  // Residuals through mrcal's projection, the board warped as mrcal warps it.
  for (int view = 0; view < num_views; ++view) {
    const mrcal_pose_t& pose = problem.frames_toref[view];
    const Eigen::Matrix3d rotation = RotationFromRodrigues(pose.r);
    const Eigen::Vector3d translation(pose.t.x, pose.t.y, pose.t.z);
    Rigid3d cam_from_board;
    cam_from_board.rotation = Eigen::Quaterniond(rotation);
    cam_from_board.translation = translation;
    result.cam_from_board.push_back(cam_from_board);
    std::vector<Eigen::Vector2d> residuals;
    std::vector<bool> outliers;
    for (int k = 0; k < num_corners; ++k) {
      const int i = k % board.grid_width;
      const int j = k / board.grid_width;
      const double xr = static_cast<double>(i) / (board.grid_width - 1);
      const double yr = static_cast<double>(j) / (board.grid_height - 1);
      Eigen::Vector3d point = corners[k];
      point.z() += problem.warp.x2 * 4.0 * xr * (1.0 - xr) +
                   problem.warp.y2 * 4.0 * yr * (1.0 - yr);
      const Eigen::Vector3d in_cam = rotation * point + translation;
      const mrcal_point3_t p{{in_cam.x(), in_cam.y(), in_cam.z()}};
      mrcal_point2_t q;
      mrcal_project(&q, nullptr, nullptr, &p, 1, &model,
                    problem.intrinsics.data());
      const mrcal_point3_t& seen = problem.pool[view * num_corners + k];
      residuals.emplace_back(q.x - seen.x, q.y - seen.y);
      // Missing on input or thrown out by the solve: both have weight < 0;
      // only the second is an outlier.
      outliers.push_back(seen.z <= 0.0 && found[view * num_corners + k]);
    }
    result.residuals_px.push_back(std::move(residuals));
    result.outliers.push_back(std::move(outliers));
  }
  return result;
}

std::string FormatCameraModel(const std::string& lens_model,
                              const std::vector<double>& intrinsics,
                              int image_width, int image_height,
                              const std::vector<std::string>& comments) {
  std::ostringstream text;
  for (const std::string& comment : comments) text << "# " << comment << "\n";
  text << "{\n    'lensmodel':  '" << lens_model << "',\n"
       << "    # intrinsics are fx,fy,cx,cy,distortion0,distortion1,....\n"
       << "    'intrinsics': [";
  for (const double value : intrinsics) text << " " << Number(value) << ",";
  text << " ],\n"
       << "    # extrinsics are rt_fromref\n"
       << "    'extrinsics': [ 0, 0, 0, 0, 0, 0, ],\n"
       << "    'imagersize': [ " << image_width << ", " << image_height
       << ", ],\n}\n";
  return text.str();
}

MrcalCameraModel ReadCameraModel(const std::string& path) {
  const std::string text = ReadFileToString(path);
  mrcal_cameramodel_t* parsed = mrcal_read_cameramodel_string(
      text.c_str(), static_cast<int>(text.size()));
  if (parsed == nullptr) {
    throw ErrorAt(path,
                  ": not a .cameramodel mrcal can read (mrcal's parser "
                  "refused it; see its messages above)");
  }
  std::unique_ptr<mrcal_cameramodel_t, void (*)(mrcal_cameramodel_t*)> owner(
      parsed,
      [](mrcal_cameramodel_t* model) { mrcal_free_cameramodel(&model); });
  MrcalCameraModel model;
  char name[256];
  if (!mrcal_lensmodel_name(name, sizeof(name), &parsed->lensmodel)) {
    throw ErrorAt(path, ": its lens model has no name mrcal knows");
  }
  model.lens_model = name;
  const int num_params = mrcal_lensmodel_num_params(&parsed->lensmodel);
  model.intrinsics.assign(parsed->intrinsics, parsed->intrinsics + num_params);
  model.image_width = static_cast<int>(parsed->imagersize[0]);
  model.image_height = static_cast<int>(parsed->imagersize[1]);
  for (int i = 0; i < 6; ++i) model.rt_cam_ref(i) = parsed->rt_cam_ref[i];
  return model;
}

}  // namespace uw
