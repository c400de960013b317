#include "sim/distractors.h"

#include <cmath>
#include <memory>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include "colmap_plugins/scene/model_testing.h"
#include "common/mesh/ray_caster.h"
#include "common/mesh/test_meshes.h"
#include "common/util/error.h"
#include "sim/renderer.h"

namespace uw::sim {
namespace {

class GreyTexture : public Texture {
 public:
  Eigen::Vector3f Albedo(const Eigen::Vector3d&,
                         const Eigen::Vector3d&) const override {
    return Eigen::Vector3f::Constant(0.2f);
  }
};

// The plane z = 2 facing a camera at the origin, 4 m wide.
TriangleMesh FacingPlane() {
  TriangleMesh mesh;
  AddGrid({-2, -2, 2}, {0, 4, 0}, {4, 0, 0}, 2, 2, &mesh);
  return mesh;
}

RenderOptions NoiselessOptions() {
  RenderOptions options;
  options.sensor.noise_sigma = 0.0;
  options.sensor.supersampling = 1;
  return options;
}

TEST(DistractorTexture, AShellIsWhiteWithinItsRadiusOnly) {
  const auto base = std::make_shared<GreyTexture>();
  const DistractorTexture texture(
      base, {Shell({0.5, 0.0, 2.0}, 0.03),
             Debris({-0.5, 0, 2}, 0.02, {0.1f, 0.6f, 0.2f})});
  const Eigen::Vector3d normal(0, 0, -1);
  EXPECT_EQ(texture.Albedo({0.5, 0.02, 2.0}, normal),
            Eigen::Vector3f::Constant(0.9f));
  EXPECT_EQ(texture.Albedo({0.5, 0.04, 2.0}, normal),
            Eigen::Vector3f::Constant(0.2f));
  EXPECT_EQ(texture.Albedo({-0.5, 0.0, 2.0}, normal),
            Eigen::Vector3f(0.1f, 0.6f, 0.2f));
  EXPECT_FALSE(texture.HasShine());
  const DistractorTexture shiny(base, {ShinyObject({0, 0, 2}, 0.05)});
  EXPECT_TRUE(shiny.HasShine());
  EXPECT_GT(shiny.ShineAt({0.01, 0, 2}).weight, 0.0f);
  EXPECT_EQ(shiny.ShineAt({0.1, 0, 2}).weight, 0.0f);
}

// In the image: the shell brightens its own pixels and no others, and a
// shiny object glints where it mirrors the lamp into the camera, far
// brighter than its albedo alone would make it.
TEST(DistractorTexture, RendersShellsAndGlints) {
  const TriangleMesh mesh = FacingPlane();
  const RayCaster caster(mesh);
  // 160 px square, f = 150 px, centre (80, 80).
  const Camera camera = TestPinholeCamera(1, 160, 150.0);
  const auto base = std::make_shared<GreyTexture>();
  const auto render = [&](const Texture& texture) {
    return RenderImage(caster, texture, camera, Rigid3d(), NoiselessOptions(),
                       1, 0)
        .image;
  };
  const cv::Mat plain = render(*base);
  // 0.03 m at 2 m and 150 px: a 4.5 px radius around pixel (80 + 37.5, 80).
  const cv::Mat shell =
      render(DistractorTexture(base, {Shell({0.5, 0, 2}, 0.03)}));
  const cv::Vec3b on = shell.at<cv::Vec3b>(80, 117);
  const cv::Vec3b off = shell.at<cv::Vec3b>(80, 127);
  EXPECT_GT(on[1], plain.at<cv::Vec3b>(80, 117)[1] + 40) << on;
  EXPECT_EQ(off, plain.at<cv::Vec3b>(80, 127));
  // The lamp is 0.3 m above the lens: the mirror point of a plane 2 m away
  // lies 0.15 m above the axis, at row 80 - 11.25.
  const Eigen::Vector3d mirror(0.0, -0.15, 2.0);
  const cv::Mat matte = render(DistractorTexture(
      base, {Debris(mirror, 0.05, Eigen::Vector3f::Constant(0.3f))}));
  const cv::Mat glint =
      render(DistractorTexture(base, {ShinyObject(mirror, 0.05)}));
  const cv::Vec3b at_glint = glint.at<cv::Vec3b>(68, 80);
  const cv::Vec3b at_matte = matte.at<cv::Vec3b>(68, 80);
  EXPECT_GT(at_glint[1], at_matte[1] + 40) << at_glint << " vs " << at_matte;
  // Beyond the object (8 cm from the mirror point) nothing changes.
  EXPECT_EQ(glint.at<cv::Vec3b>(68, 80 + 6), plain.at<cv::Vec3b>(68, 80 + 6));
}

TEST(ScatterDistractors, DensityTimesAreaOnTheMeshDeterministically) {
  const TriangleMesh mesh = FacingPlane();  // 16 m^2
  DistractorOptions options;
  options.shells_per_m2 = 2.0;
  options.debris_per_m2 = 1.0;
  options.shiny_per_m2 = 0.5;
  const std::vector<Distractor> distractors =
      ScatterDistractors(mesh, options, 7);
  ASSERT_EQ(distractors.size(), 32u + 16u + 8u);
  int shiny = 0;
  for (const Distractor& d : distractors) {
    EXPECT_NEAR(d.centre_in_world.z(), 2.0, 1e-12);
    EXPECT_LE(d.centre_in_world.head<2>().cwiseAbs().maxCoeff(), 2.0);
    EXPECT_GE(d.radius_m, options.min_radius_m);
    EXPECT_LE(d.radius_m, options.max_radius_m);
    shiny += d.shine.weight > 0.0f;
  }
  EXPECT_EQ(shiny, 8);
  const std::vector<Distractor> again = ScatterDistractors(mesh, options, 7);
  EXPECT_EQ(again[20].centre_in_world, distractors[20].centre_in_world);
  EXPECT_NE(ScatterDistractors(mesh, options, 8)[20].centre_in_world,
            distractors[20].centre_in_world);
}

TEST(DistractorOptions, JsonAndChecks) {
  DistractorOptions options;
  options.shells_per_m2 = 0.5;
  nlohmann::json json = options;
  DistractorOptions read;
  from_json(json, read);
  EXPECT_EQ(read.shells_per_m2, 0.5);
  EXPECT_TRUE(read.Any());
  EXPECT_FALSE(DistractorOptions().Any());
  json["shells"] = 1;
  EXPECT_THROW(from_json(json, read), Error);
  DistractorOptions bad;
  bad.max_radius_m = 0.001;
  try {
    bad.Check();
    ADD_FAILURE();
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("max_radius_m"),
              std::string::npos);
  }
}

}  // namespace
}  // namespace uw::sim
