#include "calib/calibration_report.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "calib/projection_uncertainty_plot.h"
#include "common/util/error.h"
#include "common/util/figure.h"
#include "common/util/file.h"
#include "common/util/png_file.h"

namespace uw {
namespace {

// The inlier RMS (2D error norm) of one image's corners.
double InlierRms(const MrcalCalibration& camera, size_t view, int* inliers) {
  double sum_squares = 0.0;
  *inliers = 0;
  for (size_t k = 0; k < camera.residuals_px[view].size(); ++k) {
    if (!camera.found[view][k] || camera.outliers[view][k]) continue;
    sum_squares += camera.residuals_px[view][k].squaredNorm();
    ++*inliers;
  }
  return std::sqrt(sum_squares / std::max(*inliers, 1));
}

PendingFile BytesFile(const std::filesystem::path& path, std::string bytes) {
  return {path,
          [bytes = std::move(bytes)](std::ostream& out) { out << bytes; }};
}

// Four significant digits: the JSON's grid is for reading, not for
// recomputing.
double Rounded(double value) {
  if (!std::isfinite(value)) return value;
  return std::strtod(fmt::format("{:.4g}", value).c_str(), nullptr);
}

nlohmann::json RoundedList(const std::vector<double>& values) {
  nlohmann::json list = nlohmann::json::array();
  for (const double value : values) list.push_back(Rounded(value));
  return list;
}

// The camera's projection uncertainty for calibration.json: the plot's
// figures, and a grid 16 samples across, small enough to read.
nlohmann::json UncertaintyJson(const MrcalCalibration& camera,
                               const ProjectionUncertaintyMap& plotted,
                               ProjectionUncertaintyOptions options) {
  options.grid_width = 16;
  options.grid_height =
      std::max(2, static_cast<int>(std::lround(16.0 * camera.image_height /
                                               camera.image_width)));
  const ProjectionUncertaintyMap grid =
      MapProjectionUncertainty(camera, options);
  nlohmann::json values = nlohmann::json::array();
  for (int i = 0; i < grid.stdev_px.rows(); ++i) {
    std::vector<double> row(grid.stdev_px.cols());
    for (int j = 0; j < grid.stdev_px.cols(); ++j) row[j] = grid.stdev_px(i, j);
    values.push_back(RoundedList(row));
  }
  return {
      {"what",
       "1-sigma of the projection in its worst direction, pixels, as "
       "mrcal-show-projection-uncertainty plots it (null: the pixel "
       "does not unproject)"},
      {"distance_m", options.distance > 0.0 ? nlohmann::json(options.distance)
                                            : nlohmann::json(nullptr)},
      {"observed_pixel_sigma_px", Rounded(plotted.observed_pixel_sigma)},
      {"at_centre_px", Rounded(plotted.at_centre_px)},
      {"max_px", Rounded(plotted.MaxPx())},
      {"max_px_over", "the plot's " + std::to_string(plotted.x_px.size()) +
                          "x" + std::to_string(plotted.y_px.size()) +
                          " samples"},
      {"grid_x_px", RoundedList(grid.x_px)},
      {"grid_y_px", RoundedList(grid.y_px)},
      {"values_px", values}};
}

}  // namespace

void WriteCalibrationReport(const MrcalRigCalibration& result,
                            const std::vector<std::string>& globs,
                            const std::string& command,
                            const ProjectionUncertaintyOptions& uncertainty,
                            const std::filesystem::path& dir) {
  uncertainty.Check();
  std::vector<PendingFile> files;
  nlohmann::json json_cameras = nlohmann::json::array();
  Figure residuals("Reprojection residuals (projected \u2212 observed)",
                   "dx (px)", "dy (px)", 7.0, 7.0);
  residuals.EqualAspect();
  Figure per_image("Inlier RMS per image", "image (in corners.vnl order)",
                   "RMS (px)", 10.0, 5.0);
  std::vector<double> outlier_x;
  std::vector<double> outlier_y;
  for (size_t c = 0; c < result.cameras.size(); ++c) {
    const MrcalCalibration& camera = result.cameras[c];
    nlohmann::json images = nlohmann::json::array();
    std::vector<double> dx;
    std::vector<double> dy;
    std::vector<double> index;
    std::vector<double> rms;
    for (size_t v = 0; v < camera.images.size(); ++v) {
      int inliers = 0;
      rms.push_back(InlierRms(camera, v, &inliers));
      index.push_back(static_cast<double>(v));
      int outliers = 0;
      for (size_t k = 0; k < camera.outliers[v].size(); ++k) {
        outliers += camera.found[v][k] && camera.outliers[v][k];
      }
      images.push_back({{"image", camera.images[v]},
                        {"rms_px", rms.back()},
                        {"outliers", outliers}});
      for (size_t k = 0; k < camera.residuals_px[v].size(); ++k) {
        if (!camera.found[v][k]) continue;  // no residual
        const Eigen::Vector2d& r = camera.residuals_px[v][k];
        (camera.outliers[v][k] ? outlier_x : dx).push_back(r.x());
        (camera.outliers[v][k] ? outlier_y : dy).push_back(r.y());
      }
    }
    const std::string label = "camera " + std::to_string(c);
    residuals.Points(dx, dy, Figure::Colour(static_cast<int>(c)), label);
    per_image.Points(index, rms, Figure::Colour(static_cast<int>(c)), label);
    const ProjectionUncertaintyMap map =
        MapProjectionUncertainty(camera, uncertainty);
    const bool rig = result.cameras.size() > 1;
    std::string title = "Projection uncertainty (1-sigma, worst direction, px)";
    if (rig) title += " of camera " + std::to_string(c);
    title += uncertainty.distance > 0.0
                 ? fmt::format(", looking out to {:g} m", uncertainty.distance)
                 : ", looking out to infinity";
    const std::filesystem::path map_path =
        dir /
        (rig ? "projection_uncertainty-camera-" + std::to_string(c) + ".png"
             : std::string("projection_uncertainty.png"));
    files.push_back(BytesFile(
        map_path,
        EncodePng(RenderProjectionUncertainty(map, camera.image_width,
                                              camera.image_height, title),
                  map_path)));
    const Rigid3d& cam_from_rig = result.cam_from_rig[c];
    const Eigen::Quaterniond& q = cam_from_rig.rotation;
    json_cameras.push_back(
        {{"camera", c},
         {"glob", c < globs.size() ? globs[c] : "*"},
         {"intrinsics", camera.intrinsics},
         {"cam_from_rig",
          {{"rotation_wxyz", {q.w(), q.x(), q.y(), q.z()}},
           {"translation",
            {cam_from_rig.translation.x(), cam_from_rig.translation.y(),
             cam_from_rig.translation.z()}}}},
         {"corners_observed", camera.num_corners_observed},
         {"outliers", camera.num_outliers},
         {"images", images},
         {"projection_uncertainty",
          UncertaintyJson(camera, map, uncertainty)}});
    files.push_back(
        {dir / ("camera-" + std::to_string(c) + ".cameramodel"),
         [&, c](std::ostream& stream) {
           const MrcalCalibration& camera = result.cameras[c];
           stream << FormatCameraModel(
               camera.lens_model, camera.intrinsics, camera.image_width,
               camera.image_height, result.cam_from_rig[c],
               {"generated with " + command,
                fmt::format("RMS reprojection error: {:.6f} pixels",
                            result.rms_px),
                "Noutliers: " + std::to_string(camera.num_outliers) +
                    " out of " + std::to_string(camera.num_corners_observed)});
         }});
  }
  if (!outlier_x.empty()) {
    residuals.Points(outlier_x, outlier_y, "black", "outliers");
  }
  // A rig's cameras see the board in different views, so only a single
  // camera's images name the axis.
  if (result.cameras.size() == 1) per_image.ItemAxis(result.cameras[0].images);
  const MrcalCalibration& first = result.cameras.at(0);
  const nlohmann::json report = {
      {"lens_model", first.lens_model},
      {"imagersize", {first.image_width, first.image_height}},
      {"pixel_convention",
       "mrcal/OpenCV: (0, 0) is the centre of the top-left pixel"},
      {"rms_px", result.rms_px},
      {"rms_px_meaning",
       "inlier corners' residuals, per coordinate (as mrcal reports it)"},
      {"outliers", result.num_outliers},
      {"calobject_warp_m",
       {first.calobject_warp.x(), first.calobject_warp.y()}},
      {"units", "the board's (its square or tag side): metres"},
      {"cameras", json_cameras}};
  files.push_back({dir / "calibration.json", [&](std::ostream& stream) {
                     stream << report.dump(1) << "\n";
                   }});
  const std::vector<FigureFiles> drawn = DrawFigures({residuals, per_image});
  const char* const names[] = {"residuals", "residuals_per_image"};
  for (size_t i = 0; i < drawn.size(); ++i) {
    files.push_back(
        BytesFile(dir / (std::string(names[i]) + ".png"), drawn[i].png));
    files.push_back(
        BytesFile(dir / (std::string(names[i]) + ".svg"), drawn[i].svg));
  }
  WriteFilesAtomically(files, true);
}

std::vector<std::string> DescribeRigCalibration(
    const MrcalRigCalibration& result,
    const ProjectionUncertaintyOptions& uncertainty) {
  std::vector<std::string> lines;
  for (size_t c = 0; c < result.cameras.size(); ++c) {
    const MrcalCalibration& camera = result.cameras[c];
    lines.push_back(fmt::format(
        "camera {}: {} views, {} outliers of {} corners{}", c,
        camera.images.size(), camera.num_outliers, camera.num_corners_observed,
        c == 0 ? std::string()
               : fmt::format(", baseline {:.6f} m",
                             result.cam_from_rig[c].translation.norm())));
  }
  const double distance = uncertainty.distance;
  for (size_t c = 0; c < result.cameras.size(); ++c) {
    const MrcalCalibration& camera = result.cameras[c];
    const double centre = ProjectionUncertaintyAtPixel(
        camera,
        {(camera.image_width - 1) / 2.0, (camera.image_height - 1) / 2.0},
        distance);
    lines.push_back(fmt::format(
        "camera {}: projection uncertainty at the centre {:.3f} px (1-sigma, "
        "worst direction), {}",
        c, centre,
        distance > 0.0 ? fmt::format("{:g} m out", distance) : "at infinity"));
  }
  return lines;
}

}  // namespace uw
