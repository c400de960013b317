// A small survey's report inputs with known figures, for the report's unit
// tests: a model of 4 images along a line over a tilted plane, nav.csv,
// the mesh, ba_report.json, a laser report folder, table.csv, compare.json
// and timings.csv.
#pragma once

#include <filesystem>
#include <fstream>
#include <string>

#include <opencv2/imgcodecs.hpp>

#include "colmap_plugins/scene/model_io.h"
#include "common/mesh/mesh.h"
#include "common/mesh/test_meshes.h"
#include "report/report_inputs.h"

namespace uw {

inline void WriteTestText(const std::filesystem::path& path,
                          const std::string& text) {
  std::filesystem::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << text;
}

// A plot-like PNG: a gradient, so that it decodes to something non-uniform.
inline void WriteTestPng(const std::filesystem::path& path, int width,
                         int height) {
  std::filesystem::create_directories(path.parent_path());
  cv::Mat image(height, width, CV_8UC3);
  for (int r = 0; r < height; ++r) {
    for (int c = 0; c < width; ++c) {
      image.at<cv::Vec3b>(r, c) = cv::Vec3b(c % 256, r % 256, 128);
    }
  }
  cv::imwrite(path.string(), image);
}

// Writes every input under `dir` and returns their paths (no truth).
inline SurveyReportInputs WriteTestReportInputs(
    const std::filesystem::path& dir) {
  namespace fs = std::filesystem;
  fs::remove_all(dir);
  SurveyReportInputs inputs;

  Reconstruction model;
  Camera camera;
  camera.camera_id = 1;
  camera.model_id = CameraModelId::kPinhole;
  camera.width = 640;
  camera.height = 480;
  camera.params = {500, 500, 320, 240};
  model.AddCamera(camera);
  std::string nav =
      "image_name,time,dive,x,y,z,roll,pitch,yaw,std_x,std_y,std_z,std_roll,"
      "std_pitch,std_yaw\n";
  for (int i = 0; i < 4; ++i) {
    Image image;
    image.image_id = static_cast<image_t>(i + 1);
    image.camera_id = 1;
    image.name = std::to_string(i) + ".png";
    const Eigen::Vector3d centre(1.0 + 2.0 * i, 2.0, 2.5);
    image.cam_from_world.rotation =
        Eigen::Quaterniond(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()));
    image.cam_from_world.translation =
        -(image.cam_from_world.rotation * centre);
    model.AddImage(image);
    nav += image.name + "," + std::to_string(i) + "," +
           std::to_string(i < 2 ? 1 : 2) + "," + std::to_string(centre.x()) +
           ",2.5," + std::to_string(centre.z()) +
           ",0,0,0,0.5,0.5,0.05,0.01,0.01,0.05\n";
  }
  // One more navigation row than registered images.
  nav += "4.png,4,2,9,2.5,2.5,0,0,0,0.5,0.5,0.05,0.01,0.01,0.05\n";
  inputs.model_path = dir / "model";
  fs::create_directories(inputs.model_path);
  WriteModel(model, inputs.model_path, ModelFormat::kText);
  inputs.nav_path = dir / "nav.csv";
  WriteTestText(inputs.nav_path, nav);

  TriangleMesh mesh;
  AddGrid(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(8, 0, 0.8),
          Eigen::Vector3d(0, 4, 0), 16, 8, &mesh);
  inputs.mesh_path = dir / "mesh.ply";
  WritePly(mesh, inputs.mesh_path, "test mesh in the test model's frame");

  inputs.ba_report_path = dir / "ba_report.json";
  WriteTestText(inputs.ba_report_path,
                R"({"format": "uwmetric-ba-report", "version": 1,
 "run": {"strategy": "prior"}, "weight_px_per_m": 0.4077,
 "weighting": "likelihood", "nav_sigma_m": 0.5, "prior_residual_rms_m": 0.5,
 "dive_offsets": [{"dive": 1, "num_images": 2, "offset_m": [0, 0, 0]},
                  {"dive": 2, "num_images": 2, "offset_m": [0.25, -0.5, 0.0],
                   "sigma_m": [0.02, 0.02, 0.01]}],
 "prior_residuals": [
  {"name": "0.png", "dive": 1, "error_m": [0, -0.5, 0], "error_norm_m": 0.5, "mahalanobis": 1.0},
  {"name": "1.png", "dive": 1, "error_m": [0, -0.5, 0], "error_norm_m": 0.5, "mahalanobis": 1.0},
  {"name": "2.png", "dive": 2, "error_m": [0, -0.5, 0], "error_norm_m": 0.5, "mahalanobis": 1.0},
  {"name": "3.png", "dive": 2, "error_m": [0, 0.5, 0], "error_norm_m": 0.5, "mahalanobis": 3.5}],
 "warnings": ["navigation positions on one pass: the 4 camera centres lie nearly on one line"]}
)");

  inputs.laser_report_dir = dir / "laser";
  WriteTestText(inputs.laser_report_dir / "scale.json",
                R"({"format": "uwmetric-laser-scale", "version": 1,
 "method": "fum", "num_iterations": 500, "scale": 1.0125, "sigma": 0.0025,
 "ci95": [1.0075, 1.0175], "birge_ratio": 0.8, "num_images": 3,
 "num_accepted": 2,
 "model_draws": {"count": 200, "gauge": "priors", "meaning": "..."},
 "variance_by_source": {"calibration": {"sigma": 0.002, "share": 0.64},
                        "model": {"sigma": 0.0015, "share": 0.36}},
 "navigation": {"log_scale_sigma": 0.05, "z": 4.25, "consistent": false}})");
  WriteTestText(inputs.laser_report_dir / "items.csv",
                "image,item,nominal,problem,mc_mean,mc_std,p2_5,p97_5,"
                "num_invalid\n"
                "L0.png,L0,1.01,,1.01,0.002,1.006,1.014,0\n"
                "L0.png,\"L0-L1\",1.02,,1.02,0.002,1.016,1.024,0\n"
                "L1.png,L0,1.03,,1.03,0.002,1.026,1.034,0\n"
                "L2.png,L0,,no hit,,,,,5\n");
  WriteTestText(inputs.laser_report_dir / "segments.csv",
                "segment,x,y,z,num_images,scale,sigma,ci95_low,ci95_high,"
                "birge_ratio\n1,2,2,0,2,1.0125,0.0025,1.0075,1.0175,0.8\n");
  for (const char* name : {"scales.png", "histogram.png", "convergence.png"}) {
    WriteTestPng(inputs.laser_report_dir / name, 300, 200);
  }
  WriteTestPng(inputs.laser_report_dir / "overlays" / "L0.png", 640, 480);
  WriteTestPng(inputs.laser_report_dir / "overlays" / "L1.png", 640, 480);

  inputs.compare_table_path = dir / "table.csv";
  WriteTestText(inputs.compare_table_path,
                "method,abs_rmse_m,sim_rmse_m,sim_percent_of_extent,"
                "scale_error_percent,surface_rms_m,sagitta_m,time_s\n"
                "\"colmap BA + model_aligner (camera centres)\",0.83,0.001,"
                "0.016,5.01,0.0045,-0.0009,2.79\n"
                "\"ours --Nav.strategy prior\",0.82,0.001,0.015,1.10,0.0044,"
                "-0.0006,8.29\n");
  inputs.dense_comparison_path = dir / "compare.json";
  WriteTestText(inputs.dense_comparison_path,
                R"({"format": "uwmetric-model-comparison", "version": 1,
 "alignment": {"reference_from_model": {"scale": 1.01}},
 "dense_surface": {"camera_scene_distance": 2.25, "num_samples": 1000,
  "median_distance": 0.0025, "p90_distance": 0.006, "rms_distance": 0.004,
  "mean_signed_distance": -0.0005, "observed_area": 30.0,
  "covered_area": 28.5, "coverage": 0.95, "coverage_tolerance": 0.0225}})");
  inputs.covariance_dir = dir / "covariance";
  WriteTestText(inputs.covariance_dir / "covariance.json",
                R"({"format": "uwmetric-covariance", "version": 1,
 "gauge": "priors", "gauge_description": "the navigation priors",
 "pixel_sigma_px": 0.35, "pixel_sigma_source": "estimated",
 "nav_sigma_scale": 1.42,
 "nav_sigma_source": "as the adjustment weighted them: lambda 0.4 px/m",
 "num_images": 4, "num_points": 100,
 "images": {"sigma_position_m": {"median": 0.012, "p95": 0.02, "max": 0.031},
            "sigma_rotation_deg": {"median": 0.08, "p95": 0.1, "max": 0.14}},
 "points": {"num_weak": 3, "weak_rule": "...",
            "sigma_largest_axis_m": {"median": 0.009, "p95": 0.015,
                                     "max": 0.056}},
 "samples": {"count": 200, "log_scale_sigma": 0.0705,
             "log_scale_meaning": "the navigation's own scale uncertainty"},
 "warnings": ["image 3.png sees 4 points only",
              "navigation positions on one pass: the 4 camera centres lie nearly on one line"]})");
  WriteTestText(inputs.covariance_dir / "cameras.csv",
                "image_id,name,held,num_points,sigma_x_m,sigma_y_m,sigma_z_m,"
                "sigma_position_m,sigma_rotation_deg\n"
                "1,0.png,0,40,0.01,0.01,0.005,0.015,0.08\n"
                "2,1.png,0,30,0.01,0.01,0.005,0.012,0.07\n"
                "3,2.png,0,35,0.02,0.02,0.01,0.031,0.14\n"
                "4,3.png,0,4,0.01,0.01,0.005,0.011,0.09\n");
  WriteTestPng(inputs.covariance_dir / "uncertainty_map.png", 300, 200);
  inputs.timings_path = dir / "timings.csv";
  WriteTestText(inputs.timings_path,
                "stage,seconds\n\"copy the survey\",2\n\"dense_mesher\",40\n"
                "\"total\",60\n");
  return inputs;
}

}  // namespace uw
