#include "sim/worlds/vent.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <vector>

#include "common/util/error.h"
#include "sim/world.h"
#include "sim/worlds/height_grid.h"
#include "sim/worlds/noise.h"
#include "sim/worlds/option_checks.h"

namespace uw::sim {
namespace {

// Flange profile: the underside rises from the body to the rim over
// kFlangeUnderside (steep, so it overhangs); the top slopes back to the
// body over kFlangeTop.
constexpr double kFlangeUnderside = 0.25;
constexpr double kFlangeTop = 0.8;

// The chimney's top: a dome kDomeHeight top radii high, ending in a ring of
// kDomeTip times the radius below it that a small fan closes.
constexpr double kDomeHeight = 0.7;
constexpr double kDomeTip = 0.12;

// Horizontal margin around the chimney included in the vent's survey area.
constexpr double kVentSurveyMargin = 3.0;

// Parameters t in [t0, t1] at which the plane curve c(t) is cut into
// pieces of equal arc length close to `spacing` (first t0, last t1).
std::vector<double> EqualArcLengthParameters(
    const std::function<Eigen::Vector2d(double)>& curve, double t0, double t1,
    double spacing) {
  // Fine enough that a flange underside (dr/dz ~ 10) is resolved.
  const int steps =
      std::max(64, static_cast<int>(std::ceil(64.0 * (t1 - t0) / spacing)));
  std::vector<double> length(steps + 1, 0.0);
  Eigen::Vector2d previous = curve(t0);
  for (int k = 1; k <= steps; ++k) {
    const Eigen::Vector2d point = curve(t0 + (t1 - t0) * k / steps);
    length[k] = length[k - 1] + (point - previous).norm();
    previous = point;
  }
  const int pieces =
      std::max(1, static_cast<int>(std::lround(length.back() / spacing)));
  std::vector<double> parameters(pieces + 1);
  int k = 0;
  for (int piece = 0; piece <= pieces; ++piece) {
    const double target = length.back() * piece / pieces;
    while (k + 1 < steps && length[k + 1] < target) ++k;
    const double span = length[k + 1] - length[k];
    const double fraction =
        span > 0.0 ? std::clamp((target - length[k]) / span, 0.0, 1.0) : 0.0;
    parameters[piece] = t0 + (t1 - t0) * (k + fraction) / steps;
  }
  parameters.front() = t0;
  parameters.back() = t1;
  return parameters;
}

// The chimney's radius as a function of angle and height: a tapering body
// with noise, plus flanges.
class Chimney {
 public:
  Chimney(const VentOptions& options, double ground_z, double bottom_z,
          SplitMix64Stream& random)
      : options_(options),
        ground_z_(ground_z),
        bottom_z_(bottom_z),
        top_z_(ground_z + options.chimney_height_m),
        body_noise_(random, 1.5, 0.2),
        lean_x_(random, 6.0, 6.0),
        lean_y_(random, 6.0, 6.0) {
    const int count = options.flange_count;
    for (int k = 0; k < count; ++k) {
      Flange flange{
          ground_z +
              options.chimney_height_m *
                  (0.3 + 0.55 * (k + random.Uniform(0.15, 0.85)) / count),
          random.Uniform(options.flange_min_width_m,
                         options.flange_max_width_m),
          Fbm(random, 3.0, 3.0)};
      flanges_.push_back(std::move(flange));
    }
  }

  double bottom_z() const { return bottom_z_; }
  double top_z() const { return top_z_; }

  // Horizontal position of the axis at height z.
  Eigen::Vector2d Axis(double z) const {
    const Eigen::Vector3d p(0.0, 0.0, z);
    return options_.chimney_lean_m * Eigen::Vector2d(lean_x_(p), lean_y_(p));
  }

  // Tapering from the base to the top radius, rounded off into a dome over
  // the last kDomeHeight top radii so that the top is not a flat cut.
  double BodyRadius(double z) const {
    const double f =
        std::clamp((z - ground_z_) / options_.chimney_height_m, 0.0, 1.0);
    const double radius =
        options_.chimney_base_radius_m +
        (options_.chimney_top_radius_m - options_.chimney_base_radius_m) *
            std::pow(f, 0.8);
    const double dome_height = kDomeHeight * options_.chimney_top_radius_m;
    const double into_dome = (z - (top_z_ - dome_height)) / dome_height;
    if (into_dome <= 0.0) return radius;
    return radius * std::max(kDomeTip, std::sqrt(std::max(
                                           0.0, 1.0 - into_dome * into_dome)));
  }

  // Radius at angle theta and height z, from the axis.
  double Radius(double theta, double z) const {
    const double c = std::cos(theta), s = std::sin(theta);
    const double body = BodyRadius(z);
    const Eigen::Vector3d on_cylinder(options_.chimney_base_radius_m * c,
                                      options_.chimney_base_radius_m * s, z);
    double radius =
        body * (1.0 + options_.chimney_radius_noise * body_noise_(on_cylinder));
    for (const Flange& flange : flanges_) {
      const double shape = FlangeShape(z - flange.z);
      if (shape == 0.0) continue;
      // Each flange covers part of the circumference, fading in and out.
      const double coverage =
          SmoothStep01(0.5 + 0.7 * flange.coverage(Eigen::Vector3d(
                                       c * 3.0, s * 3.0, flange.z)));
      radius += flange.width * coverage * shape;
    }
    return std::max(radius, 0.2 * body);
  }

  // The largest radius any angle can have at height z, without noise: it
  // sets the spacing of the rows.
  double EnvelopeRadius(double z) const {
    double radius = BodyRadius(z);
    for (const Flange& flange : flanges_) {
      radius += flange.width * FlangeShape(z - flange.z);
    }
    return radius;
  }

  double MaxFlangeWidth() const {
    double width = 0.0;
    for (const Flange& flange : flanges_) width = std::max(width, flange.width);
    return width;
  }

 private:
  struct Flange {
    double z;
    double width;
    Fbm coverage;
  };

  // 0 away from the flange, 1 at its rim (u = 0), rising steeply below it.
  static double FlangeShape(double u) {
    if (u <= -kFlangeUnderside || u >= kFlangeTop) return 0.0;
    if (u < 0.0) return SmoothStep01((u + kFlangeUnderside) / kFlangeUnderside);
    return 1.0 - SmoothStep01(u / kFlangeTop);
  }

  VentOptions options_;
  double ground_z_, bottom_z_, top_z_;
  Fbm body_noise_;
  Fbm lean_x_, lean_y_;
  std::vector<Flange> flanges_;
};

// Appends the chimney: rows at equal arc length of its envelope profile
// (so flange undersides get as many rows as the body), columns around,
// and a domed cap. Returns the largest horizontal distance of its vertices
// from the origin.
double AppendChimney(const Chimney& chimney, double spacing,
                     TriangleMesh* mesh) {
  const std::vector<double> rows = EqualArcLengthParameters(
      [&chimney](double z) {
        return Eigen::Vector2d(chimney.EnvelopeRadius(z), z);
      },
      chimney.bottom_z(), chimney.top_z(), spacing);
  const double max_circumference =
      2.0 * M_PI *
      (chimney.EnvelopeRadius(chimney.bottom_z()) + chimney.MaxFlangeWidth());
  const int columns =
      std::max(16, static_cast<int>(std::ceil(max_circumference / spacing)));
  const int first = static_cast<int>(mesh->vertices.size());
  double reach = 0.0;
  for (const double z : rows) {
    const Eigen::Vector2d axis = chimney.Axis(z);
    for (int i = 0; i < columns; ++i) {
      const double theta = 2.0 * M_PI * i / columns;
      const double radius = chimney.Radius(theta, z);
      const Eigen::Vector3d vertex(axis.x() + radius * std::cos(theta),
                                   axis.y() + radius * std::sin(theta), z);
      reach = std::max(reach, vertex.head<2>().norm());
      mesh->vertices.push_back(vertex);
    }
  }
  // Columns run counter-clockwise seen from above and rows upwards, so
  // d/dtheta x d/dz points outwards.
  AppendGridTriangles(first, columns, static_cast<int>(rows.size()),
                      /*wrap_u=*/true, mesh);
  const double top = chimney.top_z();
  const Eigen::Vector2d axis = chimney.Axis(top);
  const int apex = static_cast<int>(mesh->vertices.size());
  mesh->vertices.emplace_back(axis.x(), axis.y(),
                              top + 0.5 * chimney.BodyRadius(top));
  const int last_row = first + columns * (static_cast<int>(rows.size()) - 1);
  for (int i = 0; i < columns; ++i) {
    mesh->triangles.emplace_back(last_row + i, last_row + (i + 1) % columns,
                                 apex);
  }
  return reach;
}

}  // namespace

void VentOptions::Check() const {
  const std::string section = "vent";
  CheckPositive(ground_size_m, section, "ground_size_m");
  CheckPositive(ground_vertex_spacing_m, section, "ground_vertex_spacing_m");
  ground_relief.Check(section + ".ground_relief");
  ground_rocks.Check(section + ".ground_rocks");
  CheckNonNegative(mound_height_m, section, "mound_height_m");
  CheckPositive(mound_radius_m, section, "mound_radius_m");
  CheckPositive(chimney_height_m, section, "chimney_height_m");
  CheckPositive(chimney_base_radius_m, section, "chimney_base_radius_m");
  CheckPositive(chimney_top_radius_m, section, "chimney_top_radius_m");
  // Beyond ~0.2 the radius would often hit its lower clamp.
  CheckRange(chimney_radius_noise, 0.0, 0.2, section, "chimney_radius_noise");
  CheckNonNegative(chimney_lean_m, section, "chimney_lean_m");
  CheckRange(flange_count, 0, 20, section, "flange_count");
  CheckNonNegative(flange_min_width_m, section, "flange_min_width_m");
  CheckNonNegative(flange_max_width_m, section, "flange_max_width_m");
  if (flange_min_width_m > flange_max_width_m) {
    throw ErrorAt(OptionName(section, "flange_min_width_m"), " = ",
                  flange_min_width_m,
                  ": exceeds flange_max_width_m = ", flange_max_width_m);
  }
  CheckPositive(chimney_vertex_spacing_m, section, "chimney_vertex_spacing_m");
  const double footprint =
      2.0 * (std::max(chimney_base_radius_m, chimney_top_radius_m) *
                 (1.0 + 4.0 * chimney_radius_noise) +
             flange_max_width_m + 3.0 * chimney_lean_m);
  if (ground_size_m < footprint + 2.0) {
    throw ErrorAt(OptionName(section, "ground_size_m"), " = ", ground_size_m,
                  ": the ground must extend at least 1 m around the "
                  "chimney's footprint (",
                  footprint, " m across)");
  }
  const double ground_cells = ground_size_m / ground_vertex_spacing_m + 1.0;
  const double rows =
      (chimney_height_m + 2.0 + 2.0 * flange_count * flange_max_width_m) /
      chimney_vertex_spacing_m;
  const double columns = M_PI * footprint / chimney_vertex_spacing_m;
  CheckTriangles(2.0 * ground_cells * ground_cells + 2.0 * rows * columns,
                 section, "ground_vertex_spacing_m/chimney_vertex_spacing_m");
}

World MakeVent(const VentOptions& options, SplitMix64Stream& random) {
  const Relief relief(options.ground_relief, options.ground_vertex_spacing_m,
                      random);
  const double mound_radius_squared =
      options.mound_radius_m * options.mound_radius_m;
  const auto ground = [&](double x, double y) {
    return relief(Eigen::Vector3d(x, y, 0.0)) +
           options.mound_height_m *
               std::exp(-(x * x + y * y) / mound_radius_squared);
  };
  const double half = 0.5 * options.ground_size_m;
  HeightGrid grid(-half, -half, options.ground_size_m, options.ground_size_m,
                  options.ground_vertex_spacing_m);
  for (int j = 0; j < grid.ny; ++j) {
    for (int i = 0; i < grid.nx; ++i)
      grid.at(i, j) = ground(grid.x(i), grid.y(j));
  }

  // The body starts below the lowest ground around its foot, so that no
  // gap opens between chimney and ground.
  const double foot_radius = options.chimney_base_radius_m *
                                 (1.0 + 4.0 * options.chimney_radius_noise) +
                             3.0 * options.chimney_lean_m;
  double lowest = ground(0.0, 0.0);
  for (int k = 0; k < 256; ++k) {
    const double theta = 2.0 * M_PI * k / 256;
    for (const double r : {0.5 * foot_radius, foot_radius}) {
      lowest =
          std::min(lowest, ground(r * std::cos(theta), r * std::sin(theta)));
    }
  }
  const Chimney chimney(options, ground(0.0, 0.0), lowest - 0.3, random);
  AddRocks(options.ground_rocks, ground, OutsideDisc(foot_radius), random,
           &grid);

  World world;
  world.name = "vent";
  AppendHeightGrid(grid, &world.mesh);
  const double reach =
      AppendChimney(chimney, options.chimney_vertex_spacing_m, &world.mesh);
  double top = -std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3d& vertex : world.mesh.vertices) {
    top = std::max(top, vertex.z());
  }
  world.survey_origin = Eigen::Vector3d(0.0, 0.0, top);
  world.survey_normal = Eigen::Vector3d::UnitZ();
  world.survey_along = Eigen::Vector3d::UnitX();
  world.survey_length = 2.0 * (reach + kVentSurveyMargin);
  world.survey_width = world.survey_length;
  return world;
}

}  // namespace uw::sim
