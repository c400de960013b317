#include "sim/worlds/scarp.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "common/util/error.h"
#include "sim/world.h"
#include "sim/worlds/height_grid.h"
#include "sim/worlds/noise.h"
#include "sim/worlds/option_checks.h"

namespace uw::sim {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

// Shape of the scarp's profile: a concave talus apron at the foot and a
// rounded crest, as radii of the arcs joining the wall to the flat strips.
constexpr double kScarpFootRadius = 1.5;
constexpr double kScarpCrestRadius = 0.8;

// The scarp's cross-section in the (y, z) plane, by arc length from the
// far edge of the foot strip: floor, concave apron, wall, rounded crest,
// crest strip. Each piece is a line or a circular arc.
class ScarpProfile {
 public:
  explicit ScarpProfile(const ScarpOptions& options) {
    const double dip = options.dip_deg * kDegToRad;
    const Eigen::Vector2d level(1.0, 0.0);
    const Eigen::Vector2d up_wall(std::cos(dip), std::sin(dip));
    const Eigen::Vector2d foot(0.0, 0.0);
    const Eigen::Vector2d crest = options.height_m / std::sin(dip) * up_wall;
    // Tangent lengths of the arcs that turn by the dip angle.
    const double foot_cut = kScarpFootRadius * std::tan(0.5 * dip);
    const double crest_cut = kScarpCrestRadius * std::tan(0.5 * dip);
    const Eigen::Vector2d start(-options.foot_width_m, 0.0);
    Add(start, level, options.foot_width_m - foot_cut, 0.0);
    Add(foot - foot_cut * level, level, kScarpFootRadius * dip,
        1.0 / kScarpFootRadius);
    Add(foot + foot_cut * up_wall, up_wall,
        options.height_m / std::sin(dip) - foot_cut - crest_cut, 0.0);
    Add(crest - crest_cut * up_wall, up_wall, kScarpCrestRadius * dip,
        -1.0 / kScarpCrestRadius);
    Add(crest + crest_cut * level, level, options.crest_width_m - crest_cut,
        0.0);
  }

  double length() const { return length_; }

  // Point and unit normal on the water side at arc length s.
  void At(double s, Eigen::Vector2d* point, Eigen::Vector2d* normal) const {
    const Piece* piece = &pieces_.front();
    for (const Piece& candidate : pieces_) {
      if (s >= candidate.start_s) piece = &candidate;
    }
    const double u = std::min(s - piece->start_s, piece->length);
    const Eigen::Vector2d left(-piece->direction.y(), piece->direction.x());
    if (piece->curvature == 0.0) {
      *point = piece->start + u * piece->direction;
      *normal = left;
      return;
    }
    const double phi = piece->curvature * u;
    *point = piece->start +
             (std::sin(phi) * piece->direction + (1.0 - std::cos(phi)) * left) /
                 piece->curvature;
    *normal = std::cos(phi) * left - std::sin(phi) * piece->direction;
  }

 private:
  // Curvature > 0 turns left (counter-clockwise), towards the water.
  struct Piece {
    Eigen::Vector2d start;
    Eigen::Vector2d direction;
    double length;
    double curvature;
    double start_s;
  };

  void Add(const Eigen::Vector2d& start, const Eigen::Vector2d& direction,
           double length, double curvature) {
    pieces_.push_back({start, direction, length, curvature, length_});
    length_ += length;
  }

  std::vector<Piece> pieces_;
  double length_ = 0.0;
};

}  // namespace

void ScarpOptions::Check() const {
  const std::string section = "scarp";
  CheckPositive(length_m, section, "length_m");
  CheckPositive(height_m, section, "height_m");
  if (!(dip_deg > 45.0 && dip_deg <= 90.0)) {
    throw ErrorAt(OptionName(section, "dip_deg"), " = ", dip_deg,
                  ": must be in (45, 90] (a wall, not a slope)");
  }
  const double dip = dip_deg * kDegToRad;
  const double rounding =
      (kScarpFootRadius + kScarpCrestRadius) * std::tan(0.5 * dip);
  if (height_m / std::sin(dip) <= rounding) {
    throw ErrorAt(OptionName(section, "height_m"), " = ", height_m,
                  ": too low for the rounded foot and crest (needs more than ",
                  rounding * std::sin(dip), " m at this dip)");
  }
  const double foot_cut = kScarpFootRadius * std::tan(0.5 * dip);
  const double crest_cut = kScarpCrestRadius * std::tan(0.5 * dip);
  if (!(foot_width_m >= foot_cut && std::isfinite(foot_width_m))) {
    throw ErrorAt(OptionName(section, "foot_width_m"), " = ", foot_width_m,
                  ": must be at least ", foot_cut,
                  " m (the apron at the foot)");
  }
  if (!(crest_width_m >= crest_cut && std::isfinite(crest_width_m))) {
    throw ErrorAt(OptionName(section, "crest_width_m"), " = ", crest_width_m,
                  ": must be at least ", crest_cut,
                  " m (the rounding of the crest)");
  }
  CheckPositive(vertex_spacing_m, section, "vertex_spacing_m");
  relief.Check(section + ".relief");
  CheckNonNegative(meander_amplitude_m, section, "meander_amplitude_m");
  CheckPositive(meander_wavelength_m, section, "meander_wavelength_m");
  const double profile =
      foot_width_m + height_m / std::sin(dip) + crest_width_m;
  CheckTriangles(2.0 * (length_m / vertex_spacing_m + 1.0) *
                     (profile / vertex_spacing_m + 1.0),
                 section, "vertex_spacing_m");
}

World MakeScarp(const ScarpOptions& options, SplitMix64Stream& random) {
  const ScarpProfile profile(options);
  const Relief relief(options.relief, options.vertex_spacing_m, random);
  const Fbm meander(random, options.meander_wavelength_m,
                    options.meander_wavelength_m);
  const int columns =
      static_cast<int>(std::ceil(options.length_m / options.vertex_spacing_m)) +
      1;
  const int rows =
      static_cast<int>(std::ceil(profile.length() / options.vertex_spacing_m)) +
      1;
  World world;
  world.name = "scarp";
  TriangleMesh& mesh = world.mesh;
  mesh.vertices.reserve(static_cast<size_t>(rows) * columns);
  std::vector<double> trace(columns);
  for (int i = 0; i < columns; ++i) {
    const double x =
        options.length_m * (static_cast<double>(i) / (columns - 1) - 0.5);
    trace[i] =
        options.meander_amplitude_m * meander(Eigen::Vector3d(x, 0.0, 0.0));
  }
  for (int j = 0; j < rows; ++j) {
    Eigen::Vector2d point, normal;
    profile.At(profile.length() * j / (rows - 1), &point, &normal);
    for (int i = 0; i < columns; ++i) {
      const double x =
          options.length_m * (static_cast<double>(i) / (columns - 1) - 0.5);
      const Eigen::Vector3d base(x, point.x() + trace[i], point.y());
      mesh.vertices.push_back(
          base + relief(base) * Eigen::Vector3d(0.0, normal.x(), normal.y()));
    }
  }
  // Columns run along +x and rows from the foot strip up the wall, so
  // d/dx x d/ds points to the water (-y on the wall, +z on the strips).
  AppendGridTriangles(0, columns, rows, /*wrap_u=*/false, &mesh);

  const double dip = options.dip_deg * kDegToRad;
  const double slant_height = options.height_m / std::sin(dip);
  world.survey_origin = Eigen::Vector3d(
      0.0, 0.5 * options.height_m / std::tan(dip), 0.5 * options.height_m);
  world.survey_normal = Eigen::Vector3d(0.0, -std::sin(dip), std::cos(dip));
  world.survey_along = Eigen::Vector3d::UnitX();
  world.survey_length = options.length_m;
  world.survey_width = slant_height;
  return world;
}

}  // namespace uw::sim
