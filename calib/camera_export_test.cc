#include "calib/camera_export.h"

#include <cstdio>
#include <random>

#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

extern "C" {
#include <mrcal/mrcal.h>
}

#include "common/util/error.h"

namespace uw {
namespace {

MrcalCameraModel Model(const std::string& lens_model,
                       const std::vector<double>& intrinsics) {
  MrcalCameraModel model;
  model.lens_model = lens_model;
  model.intrinsics = intrinsics;
  model.image_width = 1024;
  model.image_height = 768;
  return model;
}

std::vector<MrcalCameraModel> ExportableModels() {
  return {
      Model("LENSMODEL_PINHOLE", {850.2, 848.7, 511.3, 383.9}),
      Model("LENSMODEL_OPENCV4",
            {850.2, 848.7, 511.3, 383.9, -0.11, 0.06, 8e-4, -4e-4}),
      Model("LENSMODEL_OPENCV5",
            {850.2, 848.7, 511.3, 383.9, -0.11, 0.06, 8e-4, -4e-4, -0.02}),
      Model("LENSMODEL_OPENCV8", {850.2, 848.7, 511.3, 383.9, -0.11, 0.06, 8e-4,
                                  -4e-4, -0.02, 0.01, 0.002, -0.001}),
      Model("LENSMODEL_OPENCV12",
            {850.2, 848.7, 511.3, 383.9, -0.11, 0.06, 8e-4, -4e-4, -0.02, 0.01,
             0.002, -0.001, 0.0, 0.0, 0.0, 0.0}),
  };
}

mrcal_lensmodel_t LensModel(const std::string& name) {
  mrcal_lensmodel_t model;
  EXPECT_TRUE(mrcal_lensmodel_from_name(&model, name.c_str()));
  return model;
}

// Every pixel of a 16-px grid over the whole image (borders included) is
// unprojected by mrcal and projected back by COLMAP's camera model.
TEST(ColmapCameraFromMrcal, ProjectsLikeTheCameraModelOverTheWholeImage) {
  for (const MrcalCameraModel& model : ExportableModels()) {
    const Camera camera = ColmapCameraFromMrcal(model, "test");
    const mrcal_lensmodel_t lens = LensModel(model.lens_model);
    double worst = 0.0;
    int count = 0;
    for (double y = 0.0; y <= model.image_height - 1; y += 16.0) {
      for (double x = 0.0; x <= model.image_width - 1; x += 16.0) {
        const mrcal_point2_t q{{x, y}};
        mrcal_point3_t v;
        ASSERT_TRUE(mrcal_unproject(&v, &q, 1, &lens, model.intrinsics.data()));
        const Eigen::Vector2d colmap =
            camera.ImgFromCam(Eigen::Vector3d(v.x, v.y, v.z));
        worst = std::max(worst,
                         (colmap - Eigen::Vector2d(x + 0.5, y + 0.5)).norm());
        // And forward: mrcal's projection of the ray.
        mrcal_point2_t back;
        mrcal_project(&back, nullptr, nullptr, &v, 1, &lens,
                      model.intrinsics.data());
        worst = std::max(
            worst,
            (colmap - Eigen::Vector2d(back.x + 0.5, back.y + 0.5)).norm());
        ++count;
      }
    }
    std::printf("[ figures ] %s -> %s: %d pixels, worst %.3g px\n",
                model.lens_model.c_str(), camera.ModelName().c_str(), count,
                worst);
    EXPECT_LT(worst, 0.01) << model.lens_model;
    EXPECT_EQ(camera.width, 1024u);
  }
}

TEST(OpenCvYamlFromMrcal, ProjectPointsAgreesWithMrcal) {
  for (const MrcalCameraModel& model : ExportableModels()) {
    const std::string yaml = OpenCvYamlFromMrcal(model, "test");
    cv::FileStorage storage(yaml,
                            cv::FileStorage::READ | cv::FileStorage::MEMORY);
    cv::Mat camera_matrix;
    cv::Mat distortion;
    storage["camera_matrix"] >> camera_matrix;
    storage["distortion_coefficients"] >> distortion;
    EXPECT_EQ(static_cast<int>(storage["image_width"]), 1024);
    const mrcal_lensmodel_t lens = LensModel(model.lens_model);
    std::mt19937 random(3);
    std::uniform_real_distribution<double> uniform(-0.5, 0.5);
    std::vector<cv::Point3d> points;
    for (int i = 0; i < 200; ++i) {
      points.emplace_back(uniform(random), 0.75 * uniform(random), 1.0);
    }
    std::vector<cv::Point2d> projected;
    cv::projectPoints(points, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0),
                      camera_matrix, distortion, projected);
    double worst = 0.0;
    for (size_t i = 0; i < points.size(); ++i) {
      const mrcal_point3_t p{{points[i].x, points[i].y, points[i].z}};
      mrcal_point2_t q;
      mrcal_project(&q, nullptr, nullptr, &p, 1, &lens,
                    model.intrinsics.data());
      worst = std::max(worst,
                       std::hypot(q.x - projected[i].x, q.y - projected[i].y));
    }
    EXPECT_LT(worst, 1e-6) << model.lens_model;
  }
}

TEST(ColmapCameraFromMrcal, RefusesModelsWithoutAColmapEquivalent) {
  MrcalCameraModel prism = ExportableModels().back();
  prism.intrinsics[13] = 1e-4;
  try {
    ColmapCameraFromMrcal(prism, "cam.cameramodel");
    ADD_FAILURE() << "exported thin-prism terms";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("thin-prism"), std::string::npos);
  }
  EXPECT_NO_THROW(OpenCvYamlFromMrcal(prism, "cam.cameramodel"));
  for (const char* name :
       {"LENSMODEL_STEREOGRAPHIC", "LENSMODEL_CAHVOR",
        "LENSMODEL_SPLINED_STEREOGRAPHIC_order=3_Nx=16_Ny=12_fov_x_deg=100"}) {
    const MrcalCameraModel model = Model(name, {850, 850, 511, 383});
    try {
      ColmapCameraFromMrcal(model, "cam.cameramodel");
      ADD_FAILURE() << "exported " << name;
    } catch (const Error& error) {
      EXPECT_NE(std::string(error.what()).find("cam.cameramodel: "),
                std::string::npos);
      EXPECT_NE(std::string(error.what()).find("no OpenCV or COLMAP"),
                std::string::npos);
    }
    EXPECT_THROW(OpenCvYamlFromMrcal(model, "x"), Error);
  }
}

}  // namespace
}  // namespace uw
