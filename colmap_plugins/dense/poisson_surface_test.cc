#include "colmap_plugins/dense/poisson_surface.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "common/util/error.h"
#include "common/util/error_testing.h"
#include "common/util/file.h"

namespace uw {
namespace {

class PoissonSurfaceTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ =
        std::filesystem::path(::testing::TempDir()) /
        ("poisson_surface_test_" +
         std::string(
             ::testing::UnitTest::GetInstance()->current_test_info()->name()));
    std::filesystem::remove_all(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  std::filesystem::path dir_;
};

// `count` points spread evenly over a sphere (Fibonacci lattice), normals
// outwards.
OrientedPoints Sphere(const Eigen::Vector3d& centre, double radius, int count) {
  OrientedPoints sphere;
  const double golden_angle = M_PI * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < count; ++i) {
    const double z = 1.0 - 2.0 * (i + 0.5) / count;
    const double r = std::sqrt(1.0 - z * z);
    const Eigen::Vector3d normal(r * std::cos(golden_angle * i),
                                 r * std::sin(golden_angle * i), z);
    sphere.points.push_back(centre + radius * normal);
    sphere.normals.push_back(normal);
    sphere.num_images.push_back(2);
  }
  return sphere;
}

PoissonOptions Options() {
  PoissonOptions options;
  // Cells of about 4.4 m / 2^8 = 1.7 cm for the 2 m sphere below; one
  // thread, as the machine is shared.
  options.depth = 8;
  options.num_threads = 1;
  return options;
}

struct RadialErrors {
  double median = 0.0;
  double max = 0.0;
};

// |distance to the centre - radius| over the mesh's vertices.
RadialErrors RadialErrorsOf(const TriangleMesh& mesh,
                            const Eigen::Vector3d& centre, double radius) {
  std::vector<double> errors;
  for (const Eigen::Vector3d& vertex : mesh.vertices) {
    errors.push_back(std::abs((vertex - centre).norm() - radius));
  }
  RadialErrors result;
  if (errors.empty()) {
    return result;
  }
  result.max = *std::max_element(errors.begin(), errors.end());
  std::nth_element(errors.begin(), errors.begin() + errors.size() / 2,
                   errors.end());
  result.median = errors[errors.size() / 2];
  return result;
}

TEST_F(PoissonSurfaceTest, SphereIsReconstructedOnItsPoints) {
  const Eigen::Vector3d centre(0.3, -0.2, 1.0);
  const OrientedPoints points = Sphere(centre, 2.0, 3000);
  const TriangleMesh mesh = PoissonSurface(points, Options(), dir_);
  // One closed surface of sphere topology (Euler characteristic 2: F = 2 V
  // - 4), as finely meshed as the 3000 points allow.
  EXPECT_GT(mesh.vertices.size(), 3000u);
  EXPECT_EQ(mesh.triangles.size(), 2 * mesh.vertices.size() - 4);
  // Measured: median 0.9 mm, max 6 mm (a third of a cell).
  const RadialErrors errors = RadialErrorsOf(mesh, centre, 2.0);
  EXPECT_LT(errors.median, 0.002) << errors.median;
  EXPECT_LT(errors.max, 0.012) << errors.max;
  // The mesh faces outwards, along the points' normals: positive signed
  // volume.
  double volume = 0.0;
  for (const Eigen::Vector3i& t : mesh.triangles) {
    volume += (mesh.vertices[t[0]] - centre)
                  .dot((mesh.vertices[t[1]] - centre)
                           .cross(mesh.vertices[t[2]] - centre)) /
              6.0;
  }
  EXPECT_NEAR(volume, 4.0 / 3.0 * M_PI * 8.0, 0.005 * 4.0 / 3.0 * M_PI * 8.0);
  EXPECT_TRUE(std::filesystem::exists(dir_ / "fused.ply"));
  EXPECT_TRUE(std::filesystem::exists(dir_ / "poisson_mesher.log"));
}

TEST_F(PoissonSurfaceTest, MeshIsInThePointsFrameFarFromTheOrigin) {
  // 100 km from the origin, where float coordinates would be 8 mm apart.
  const Eigen::Vector3d centre(1.0e5, -2.0e5, 50.0);
  const OrientedPoints points = Sphere(centre, 2.0, 3000);
  const TriangleMesh mesh = PoissonSurface(points, Options(), dir_);
  ASSERT_GT(mesh.vertices.size(), 3000u);
  const RadialErrors errors = RadialErrorsOf(mesh, centre, 2.0);
  EXPECT_LT(errors.median, 0.002) << errors.median;
  EXPECT_LT(errors.max, 0.012) << errors.max;
  // The same surface as near the origin, shifted: the mean vertex lies at
  // the same place relative to the centre.
  const Eigen::Vector3d near_centre(0.3, -0.2, 1.0);
  const TriangleMesh near =
      PoissonSurface(Sphere(near_centre, 2.0, 3000), Options(), dir_ / "near");
  Eigen::Vector3d far_mean = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& vertex : mesh.vertices) {
    far_mean += (vertex - centre) / static_cast<double>(mesh.vertices.size());
  }
  Eigen::Vector3d near_mean = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& vertex : near.vertices) {
    near_mean +=
        (vertex - near_centre) / static_cast<double>(near.vertices.size());
  }
  EXPECT_LT((far_mean - near_mean).norm(), 1e-6)
      << far_mean.transpose() << " vs " << near_mean.transpose();
}

TEST_F(PoissonSurfaceTest, TooFewPointsThrow) {
  OrientedPoints points = Sphere(Eigen::Vector3d::Zero(), 1.0, 99);
  try {
    PoissonSurface(points, Options(), dir_);
    ADD_FAILURE() << "99 points accepted";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("only 99 fused points"),
              std::string::npos)
        << error.what();
  }
}

TEST_F(PoissonSurfaceTest, MissingColmapIsNamed) {
  PoissonOptions options = Options();
  options.colmap_path = "/nonexistent/uw/colmap";
  try {
    PoissonSurface(Sphere(Eigen::Vector3d::Zero(), 1.0, 500), options, dir_);
    ADD_FAILURE() << "no error";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("/nonexistent/uw/colmap"),
              std::string::npos)
        << error.what();
  }
}

TEST_F(PoissonSurfaceTest, ColmapFailureQuotesItsLog) {
  // A program that runs but fails: colmap's log goes into the error.
  PoissonOptions options = Options();
  options.colmap_path = "false";
  try {
    PoissonSurface(Sphere(Eigen::Vector3d::Zero(), 1.0, 500), options, dir_);
    ADD_FAILURE() << "no error";
  } catch (const Error& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("poisson_mesher failed (exit 1"), std::string::npos)
        << message;
    EXPECT_NE(message.find("poisson_mesher.log"), std::string::npos) << message;
  }
}

TEST_F(PoissonSurfaceTest, WriteOrientedPlyWritesColmapsLayout) {
  OrientedPoints points;
  points.points = {{100.5, 200.25, -3.0}, {101.0, 199.0, -2.5}};
  points.normals = {{0.0, 0.6, 0.8}, {1.0, 0.0, 0.0}};
  points.num_images = {2, 3};
  const Eigen::Vector3d origin(100.0, 200.0, -3.0);
  const std::filesystem::path path = dir_ / "points.ply";
  WriteOrientedPly(points, origin, path);
  // Nothing but the file: the temporary was renamed.
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir_),
                          std::filesystem::directory_iterator()),
            1);

  const std::string content = ReadFileToString(path);
  const std::string header =
      "ply\nformat binary_little_endian 1.0\nelement vertex 2\n"
      "property float x\nproperty float y\nproperty float z\n"
      "property float nx\nproperty float ny\nproperty float nz\n"
      "property uchar red\nproperty uchar green\nproperty uchar blue\n"
      "end_header\n";
  ASSERT_EQ(content.substr(0, header.size()), header);
  ASSERT_EQ(content.size(), header.size() + 2 * (6 * 4 + 3));
  for (size_t i = 0; i < 2; ++i) {
    const char* record = content.data() + header.size() + i * 27;
    float values[6];
    std::memcpy(values, record, sizeof(values));
    const Eigen::Vector3d shifted = points.points[i] - origin;
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(values[k], static_cast<float>(shifted[k])) << i << " " << k;
      EXPECT_EQ(values[3 + k], static_cast<float>(points.normals[i][k]))
          << i << " " << k;
    }
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(static_cast<unsigned char>(record[24 + k]), 128);
    }
  }
}

TEST(PoissonOptions, CheckRejectsBadFields) {
  EXPECT_NO_THROW(PoissonOptions().Check());
  const std::vector<
      std::pair<std::function<void(PoissonOptions*)>, std::string>>
      cases = {
          {[](PoissonOptions* o) { o->depth = 3; }, "depth"},
          {[](PoissonOptions* o) { o->depth = 17; }, "depth"},
          {[](PoissonOptions* o) { o->point_weight = -1.0; }, "point_weight"},
          {[](PoissonOptions* o) { o->num_threads = 0; }, "num_threads"},
          {[](PoissonOptions* o) { o->num_threads = -2; }, "num_threads"},
          {[](PoissonOptions* o) { o->colmap_path.clear(); }, "colmap_path"},
      };
  for (const auto& [spoil, field] : cases) {
    PoissonOptions options;
    spoil(&options);
    ExpectErrorContaining([&] { options.Check(); }, field);
  }
}

}  // namespace
}  // namespace uw
