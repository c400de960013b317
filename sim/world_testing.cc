#include "sim/world_testing.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include <gtest/gtest.h>

#include "common/util/error.h"

namespace uw::sim {

WorldOptions SmallOptions() {
  WorldOptions options;
  options.seafloor.length_m = 4.0;
  options.seafloor.width_m = 3.0;
  options.seafloor.vertex_spacing_m = 0.05;
  options.seafloor.rocks.count = 4;
  options.vent.ground_size_m = 16.0;
  options.vent.ground_vertex_spacing_m = 0.2;
  options.vent.chimney_vertex_spacing_m = 0.1;
  options.vent.ground_rocks.count = 5;
  options.scarp.length_m = 20.0;
  options.scarp.vertex_spacing_m = 0.25;
  options.breakwater.length_m = 6.0;
  options.breakwater.height_m = 3.0;
  options.breakwater.crest_width_m = 2.0;
  options.breakwater.apron_width_m = 2.0;
  options.breakwater.vertex_spacing_m = 0.1;
  options.breakwater.block_size_m = 0.8;
  options.breakwater.rocks = {5, 0.3, 1.0};
  options.canyon.length_m = 12.0;
  options.canyon.width_m = 18.0;
  options.canyon.floor_width_m = 5.0;
  options.canyon.wall_height_m = 4.0;
  options.canyon.wall_height_variation_m = 1.0;
  options.canyon.wall_slope_deg = 60.0;
  options.canyon.meander_amplitude_m = 1.0;
  options.canyon.meander_wavelength_m = 12.0;
  options.canyon.wall_relief_m = 0.3;
  options.canyon.wall_relief_wavelength_m = 2.0;
  options.canyon.vertex_spacing_m = 0.15;
  options.canyon.rocks = {4, 0.3, 1.0};
  return options;
}

double TriangleArea(const TriangleMesh& mesh, size_t t) {
  const Eigen::Vector3i& f = mesh.triangles[t];
  return 0.5 * (mesh.vertices[f[1]] - mesh.vertices[f[0]])
                   .cross(mesh.vertices[f[2]] - mesh.vertices[f[0]])
                   .norm();
}

Eigen::Vector3d Centroid(const TriangleMesh& mesh, size_t t) {
  const Eigen::Vector3i& f = mesh.triangles[t];
  return (mesh.vertices[f[0]] + mesh.vertices[f[1]] + mesh.vertices[f[2]]) /
         3.0;
}

std::optional<std::pair<size_t, double>> FirstHit(
    const TriangleMesh& mesh, const Eigen::Vector3d& origin,
    const Eigen::Vector3d& direction) {
  std::optional<std::pair<size_t, double>> best;
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Eigen::Vector3i& f = mesh.triangles[t];
    const Eigen::Vector3d& a = mesh.vertices[f[0]];
    const Eigen::Vector3d e1 = mesh.vertices[f[1]] - a;
    const Eigen::Vector3d e2 = mesh.vertices[f[2]] - a;
    const Eigen::Vector3d p = direction.cross(e2);
    const double det = e1.dot(p);
    if (std::abs(det) < 1e-15) continue;
    const Eigen::Vector3d s = origin - a;
    const double u = s.dot(p) / det;
    if (u < 0.0 || u > 1.0) continue;
    const Eigen::Vector3d q = s.cross(e1);
    const double v = direction.dot(q) / det;
    if (v < 0.0 || u + v > 1.0) continue;
    const double distance = e2.dot(q) / det;
    if (distance > 1e-9 && (!best || distance < best->second)) {
      best = std::make_pair(t, distance);
    }
  }
  return best;
}

void ExpectRaysMeetFrontFaces(const World& world,
                              const std::vector<Eigen::Vector3d>& origins,
                              const std::vector<Eigen::Vector3d>& directions) {
  for (size_t r = 0; r < origins.size(); ++r) {
    const auto hit = FirstHit(world.mesh, origins[r], directions[r]);
    ASSERT_TRUE(hit) << world.name << " ray " << r;
    EXPECT_LT(world.mesh.TriangleNormal(hit->first).dot(directions[r]), 0.0)
        << world.name << " ray " << r << " from " << origins[r].transpose();
  }
}

void ExpectConsistentOrientation(const TriangleMesh& mesh) {
  std::vector<std::pair<int64_t, int>> edges;
  edges.reserve(3 * mesh.triangles.size());
  for (const Eigen::Vector3i& f : mesh.triangles) {
    for (int k = 0; k < 3; ++k) {
      edges.emplace_back(static_cast<int64_t>(f[k]) << 32 | f[(k + 1) % 3], 0);
    }
  }
  std::sort(edges.begin(), edges.end());
  const auto repeated = std::adjacent_find(
      edges.begin(), edges.end(),
      [](const auto& a, const auto& b) { return a.first == b.first; });
  EXPECT_TRUE(repeated == edges.end())
      << "directed edge " << (repeated->first >> 32) << " -> "
      << (repeated->first & 0xffffffff) << " used twice";
}

std::vector<double> HeightsIn(const World& world, double x0, double x1,
                              double y0, double y1) {
  std::vector<double> heights;
  for (const Eigen::Vector3d& vertex : world.mesh.vertices) {
    if (vertex.x() >= x0 && vertex.x() <= x1 && vertex.y() >= y0 &&
        vertex.y() <= y1) {
      heights.push_back(vertex.z());
    }
  }
  return heights;
}

double MaxHeightIn(const World& world, double x0, double x1, double y0,
                   double y1) {
  const std::vector<double> heights = HeightsIn(world, x0, x1, y0, y1);
  EXPECT_FALSE(heights.empty()) << "no vertex in [" << x0 << ", " << x1
                                << "] x [" << y0 << ", " << y1 << "]";
  return heights.empty() ? std::numeric_limits<double>::quiet_NaN()
                         : *std::max_element(heights.begin(), heights.end());
}

std::vector<std::pair<double, double>> CrossSection(const World& world,
                                                    double x0,
                                                    double tolerance) {
  std::vector<std::pair<double, double>> section;
  for (const Eigen::Vector3d& vertex : world.mesh.vertices) {
    if (std::abs(vertex.x() - x0) <= tolerance) {
      section.emplace_back(vertex.y(), vertex.z());
    }
  }
  std::sort(section.begin(), section.end());
  return section;
}

void ExpectNormalsUp(const World& world) {
  for (size_t t = 0; t < world.mesh.triangles.size(); ++t) {
    ASSERT_GT(world.mesh.TriangleNormal(t).z(), 0.0) << "triangle " << t;
  }
}

void ExpectUnitSurveyFrame(const World& world) {
  EXPECT_NEAR(world.survey_normal.norm(), 1.0, 1e-12);
  EXPECT_NEAR(world.survey_along.norm(), 1.0, 1e-12);
  EXPECT_NEAR(world.survey_normal.dot(world.survey_along), 0.0, 1e-12);
  EXPECT_GT(world.survey_length, 0.0);
  EXPECT_GT(world.survey_width, 0.0);
  EXPECT_TRUE(world.bounds.contains(world.survey_origin))
      << world.survey_origin.transpose();
}

}  // namespace uw::sim
