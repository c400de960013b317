// For the worlds' tests (sim/world_test.cc, sim/worlds/*_test.cc): small
// options, and checks of meshes by brute force.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "common/util/error_testing.h"  // ErrorOf
#include "sim/world.h"

namespace uw::sim {

inline constexpr WorldKind kKinds[] = {
    WorldKind::kSeafloor, WorldKind::kVent, WorldKind::kScarp,
    WorldKind::kBreakwater, WorldKind::kCanyon};

// Worlds small enough to build in a few milliseconds; the default worlds
// are built once each, in the tests named after them.
WorldOptions SmallOptions();

double TriangleArea(const TriangleMesh& mesh, size_t t);
Eigen::Vector3d Centroid(const TriangleMesh& mesh, size_t t);

// Brute-force first hit (Moller-Trumbore) of the ray origin + t * direction,
// t > 0: the triangle index and distance.
std::optional<std::pair<size_t, double>> FirstHit(
    const TriangleMesh& mesh, const Eigen::Vector3d& origin,
    const Eigen::Vector3d& direction);

// Rays from the water towards the surface must first meet a triangle
// whose normal faces them: the normals point into the water.
void ExpectRaysMeetFrontFaces(const World& world,
                              const std::vector<Eigen::Vector3d>& origins,
                              const std::vector<Eigen::Vector3d>& directions);

// A consistently oriented surface uses each directed edge at most once
// (a flipped neighbour would repeat it).
void ExpectConsistentOrientation(const TriangleMesh& mesh);

// Heights of the vertices in a box of the plane: the worlds built as
// heightfields have one vertex per grid point.
std::vector<double> HeightsIn(const World& world, double x0, double x1,
                              double y0, double y1);
double MaxHeightIn(const World& world, double x0, double x1, double y0,
                   double y1);

// The (y, z) of a heightfield's vertices within `tolerance` of x = x0,
// sorted by y.
std::vector<std::pair<double, double>> CrossSection(const World& world,
                                                    double x0,
                                                    double tolerance);

void ExpectNormalsUp(const World& world);
// Unit, orthogonal survey axes, a positive extent and an origin within the
// world's bounds.
void ExpectUnitSurveyFrame(const World& world);

}  // namespace uw::sim
