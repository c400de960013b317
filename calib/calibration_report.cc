#include "calib/calibration_report.h"

#include <cmath>
#include <sstream>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "colmap_plugins/util/error.h"
#include "colmap_plugins/util/file.h"
#include "colmap_plugins/util/plot.h"

namespace uw {
namespace {

// The inlier RMS (2D error norm) of one image's corners.
double InlierRms(const MrcalCalibration& camera, size_t view, int* inliers) {
  double sum_squares = 0.0;
  *inliers = 0;
  for (size_t k = 0; k < camera.residuals_px[view].size(); ++k) {
    if (camera.outliers[view][k]) continue;
    sum_squares += camera.residuals_px[view][k].squaredNorm();
    ++*inliers;
  }
  return std::sqrt(sum_squares / std::max(*inliers, 1));
}

PendingFile PngFile(const std::filesystem::path& path, const Plot& plot) {
  std::vector<uchar> bytes;
  if (!cv::imencode(".png", plot.Render(), bytes)) {
    throw ErrorAt(path.string(), ": cannot encode the plot");
  }
  return {path, [bytes](std::ostream& out) {
            out.write(reinterpret_cast<const char*>(bytes.data()),
                      static_cast<std::streamsize>(bytes.size()));
          }};
}

}  // namespace

void WriteCalibrationReport(const MrcalRigCalibration& result,
                            const std::vector<std::string>& globs,
                            const std::string& command,
                            const std::filesystem::path& dir) {
  std::vector<PendingFile> files;
  nlohmann::json json_cameras = nlohmann::json::array();
  Plot residuals("Reprojection residuals (projected - observed)", "dx [px]",
                 "dy [px]", 700, 700);
  Plot per_image("Inlier RMS per image", "image (in corners.vnl order)",
                 "RMS [px]");
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
      images.push_back(
          {{"image", camera.images[v]},
           {"rms_px", rms.back()},
           {"outliers",
            static_cast<int>(camera.residuals_px[v].size()) - inliers}});
      for (size_t k = 0; k < camera.residuals_px[v].size(); ++k) {
        const Eigen::Vector2d& r = camera.residuals_px[v][k];
        (camera.outliers[v][k] ? outlier_x : dx).push_back(r.x());
        (camera.outliers[v][k] ? outlier_y : dy).push_back(r.y());
      }
    }
    const std::string label = "camera " + std::to_string(c);
    residuals.Points(dx, dy, Plot::Colour(static_cast<int>(c)), label);
    per_image.Points(index, rms, Plot::Colour(static_cast<int>(c)), label);
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
         {"images", images}});
    files.push_back(
        {dir / ("camera-" + std::to_string(c) + ".cameramodel"),
         [&, c](std::ostream& stream) {
           const MrcalCalibration& camera = result.cameras[c];
           stream << FormatCameraModel(
               camera.lens_model, camera.intrinsics, camera.image_width,
               camera.image_height, result.cam_from_rig[c],
               {"generated with " + command,
                "RMS reprojection error: " + std::to_string(result.rms_px) +
                    " pixels",
                "Noutliers: " + std::to_string(camera.num_outliers) +
                    " out of " + std::to_string(camera.num_corners_observed)});
         }});
  }
  if (!outlier_x.empty()) {
    residuals.Points(outlier_x, outlier_y, cv::Scalar(40, 40, 230), "outliers");
  }
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
  files.push_back(PngFile(dir / "residuals.png", residuals));
  files.push_back(PngFile(dir / "residuals_per_image.png", per_image));
  WriteFilesAtomically(files, true);
}

}  // namespace uw
