#include "sim/worlds/canyon.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "common/util/error.h"
#include "sim/world.h"
#include "sim/worlds/height_grid.h"
#include "sim/worlds/noise.h"
#include "sim/worlds/option_checks.h"

namespace uw::sim {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

// Canyon: vertical extent of the rounding at the walls' foot and rim (m),
// wavelength of the walls' height variation along the canyon (m), and
// spacing of the polyline that approximates the axis (m; its chord error
// is about 1 mm at the sharpest default bend).
constexpr double kCanyonFootRounding = 1.0;
constexpr double kCanyonRimRounding = 1.5;
constexpr double kCanyonWallHeightWavelength = 20.0;
constexpr double kCanyonAxisStep = 0.25;

// Polynomial smooth minimum (Quilez): min(a, b) with the corner rounded
// over a band k wide; C1.
double SmoothMin(double a, double b, double k) {
  const double h = std::max(k - std::abs(a - b), 0.0) / k;
  return std::min(a, b) - 0.25 * k * h * h;
}

// The canyon's axis y = c(x): two sines of random phase, the second 2.1
// times shorter, whose amplitudes sum to meander_amplitude_m; and the
// signed horizontal distance from it, via a polyline.
class CanyonAxis {
 public:
  CanyonAxis(const CanyonOptions& options, SplitMix64Stream& random)
      : amplitude_(options.meander_amplitude_m),
        wavenumber_(2.0 * M_PI / options.meander_wavelength_m),
        phase_long_(random.Uniform(0.0, 2.0 * M_PI)),
        phase_short_(random.Uniform(0.0, 2.0 * M_PI)) {
    // Far enough beyond the ends that every grid vertex finds its nearest
    // axis point on the polyline.
    x_first_ = -0.5 * (options.length_m + options.width_m);
    const int count = static_cast<int>(
        std::ceil((options.length_m + options.width_m) / kCanyonAxisStep));
    for (int k = 0; k <= count; ++k) {
      const double x = x_first_ + k * kCanyonAxisStep;
      points_.emplace_back(x, y(x));
    }
  }

  double y(double x) const {
    return amplitude_ * (0.75 * std::sin(wavenumber_ * x + phase_long_) +
                         0.25 * std::sin(2.1 * wavenumber_ * x + phase_short_));
  }

  // Positive on the +y side.
  double SignedDistance(double x, double y) const {
    const Eigen::Vector2d p(x, y);
    const int last = static_cast<int>(points_.size()) - 2;
    const int start = std::clamp(
        static_cast<int>(std::floor((x - x_first_) / kCanyonAxisStep)), 0,
        last);
    double best = std::numeric_limits<double>::infinity();
    double sign = 1.0;
    const auto visit = [&](int k) {
      const Eigen::Vector2d a = points_[k], d = points_[k + 1] - a;
      const double t = std::clamp((p - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
      const Eigen::Vector2d offset = p - (a + t * d);
      const double distance = offset.norm();
      if (distance < best) {
        best = distance;
        sign = d.x() * offset.y() - d.y() * offset.x() >= 0.0 ? 1.0 : -1.0;
      }
    };
    // Segments further away in x than the best distance cannot be nearer.
    for (int k = start; k >= 0 && x - points_[k + 1].x() < best; --k) visit(k);
    for (int k = start + 1; k <= last && points_[k].x() - x < best; ++k) {
      visit(k);
    }
    return sign * best;
  }

 private:
  double amplitude_, wavenumber_, phase_long_, phase_short_;
  double x_first_;
  std::vector<Eigen::Vector2d> points_;
};

}  // namespace

void CanyonOptions::Check() const {
  const std::string section = "canyon";
  CheckPositive(length_m, section, "length_m");
  CheckPositive(width_m, section, "width_m");
  CheckPositive(floor_width_m, section, "floor_width_m");
  CheckPositive(wall_height_m, section, "wall_height_m");
  CheckRange(wall_height_variation_m, 0.0, 0.5 * wall_height_m, section,
             "wall_height_variation_m");
  CheckRange(wall_slope_deg, 30.0, 80.0, section, "wall_slope_deg");
  CheckNonNegative(meander_amplitude_m, section, "meander_amplitude_m");
  CheckPositive(meander_wavelength_m, section, "meander_wavelength_m");
  CheckNonNegative(wall_relief_m, section, "wall_relief_m");
  CheckPositive(wall_relief_wavelength_m, section, "wall_relief_wavelength_m");
  CheckPositive(vertex_spacing_m, section, "vertex_spacing_m");
  relief.Check(section + ".relief");
  rocks.Check(section + ".rocks");
  // The survey strip runs straight along x on the floor.
  const double strip =
      floor_width_m - 2.0 * meander_amplitude_m - 2.0 * wall_relief_m;
  if (!(strip >= 1.0)) {
    throw ErrorAt(OptionName(section, "floor_width_m"), " = ", floor_width_m,
                  ": leaves a straight strip of ", strip,
                  " m along the floor; must be at least ",
                  floor_width_m - strip + 1.0,
                  " m (2 x (meander_amplitude_m + wall_relief_m) + 1 m)");
  }
  if (rocks.count > 0 && rocks.max_diameter_m >= floor_width_m) {
    throw ErrorAt(OptionName(section, "rocks.max_diameter_m"), " = ",
                  rocks.max_diameter_m, ": rocks must fit on the floor");
  }
  const double needed =
      floor_width_m +
      2.0 * (meander_amplitude_m + wall_relief_m +
             (wall_height_m + wall_height_variation_m + kCanyonRimRounding) /
                 std::tan(wall_slope_deg * kDegToRad) +
             1.0);
  if (!(width_m >= needed)) {
    throw ErrorAt(OptionName(section, "width_m"), " = ", width_m,
                  ": too narrow for the canyon and 1 m of rim on each side "
                  "(needs ",
                  needed, " m)");
  }
  CheckTriangles(2.0 * (length_m / vertex_spacing_m + 1.0) *
                     (width_m / vertex_spacing_m + 1.0),
                 section, "vertex_spacing_m");
}

World MakeCanyon(const CanyonOptions& options, SplitMix64Stream& random) {
  const CanyonAxis axis(options, random);
  const Relief relief(options.relief, options.vertex_spacing_m, random);
  const Fbm wall_noise(random, options.wall_relief_wavelength_m,
                       kVerticesPerFinestWavelength * options.vertex_spacing_m);
  const Fbm height_noise_plus_y(random, kCanyonWallHeightWavelength,
                                kCanyonWallHeightWavelength);
  const Fbm height_noise_minus_y(random, kCanyonWallHeightWavelength,
                                 kCanyonWallHeightWavelength);
  const double half_floor = 0.5 * options.floor_width_m;
  const double tan_slope = std::tan(options.wall_slope_deg * kDegToRad);
  // Height of the profile at distance e from the axis under a wall of
  // height wall: floor, wall, rim, with a rounded foot and rim.
  const auto profile = [&](double e, double wall) {
    const double rising = (e - half_floor) * tan_slope;
    return -SmoothMin(0.0, -SmoothMin(wall, rising, kCanyonRimRounding),
                      kCanyonFootRounding);
  };
  const auto terrain = [&](double x, double y) {
    const double e = axis.SignedDistance(x, y);
    const Fbm& height_noise =
        e >= 0.0 ? height_noise_plus_y : height_noise_minus_y;
    const double wall =
        options.wall_height_m +
        options.wall_height_variation_m *
            std::tanh(height_noise(Eigen::Vector3d(x, 0.0, 0.0)));
    const double nominal = profile(std::abs(e), wall);
    const Eigen::Vector3d p(x, y, nominal);
    // The wall moves horizontally by up to wall_relief_m; the floor and
    // the rim plateau are flat, so the wander changes nothing there and
    // its noise is not evaluated.
    const double rounded_floor = half_floor - kCanyonFootRounding / tan_slope;
    const double rounded_rim =
        half_floor + (wall + kCanyonRimRounding) / tan_slope;
    double wandered = std::abs(e);
    if (std::abs(e) + options.wall_relief_m > rounded_floor &&
        std::abs(e) - options.wall_relief_m < rounded_rim) {
      wandered -= options.wall_relief_m * std::tanh(wall_noise(p));
    }
    return profile(wandered, wall) + relief(p);
  };
  HeightGrid grid(-0.5 * options.length_m, -0.5 * options.width_m,
                  options.length_m, options.width_m, options.vertex_spacing_m);
  for (int j = 0; j < grid.ny; ++j) {
    for (int i = 0; i < grid.nx; ++i) {
      grid.at(i, j) = terrain(grid.x(i), grid.y(j));
    }
  }
  AddRocks(
      options.rocks, terrain,
      [&](const Eigen::Vector2d& centre, double radius) {
        return std::abs(axis.SignedDistance(centre.x(), centre.y())) +
                   0.5 * radius <=
               half_floor;
      },
      random, &grid);

  // The survey strip: the axis' range in y over the grid, narrowed by it
  // and by the walls' wander.
  double axis_min = std::numeric_limits<double>::infinity();
  double axis_max = -axis_min;
  for (int i = 0; i < grid.nx; ++i) {
    axis_min = std::min(axis_min, axis.y(grid.x(i)));
    axis_max = std::max(axis_max, axis.y(grid.x(i)));
  }
  const double strip_y = 0.5 * (axis_min + axis_max);
  const double strip_width = options.floor_width_m -
                             2.0 * options.wall_relief_m -
                             (axis_max - axis_min);
  double sum_z = 0.0;
  int count = 0;
  for (int j = 0; j < grid.ny; ++j) {
    if (std::abs(grid.y(j) - strip_y) > 0.5 * strip_width) continue;
    for (int i = 0; i < grid.nx; ++i) {
      sum_z += grid.at(i, j);
      ++count;
    }
  }

  World world;
  world.name = "canyon";
  AppendHeightGrid(grid, &world.mesh);
  world.survey_origin =
      Eigen::Vector3d(0.0, strip_y, count > 0 ? sum_z / count : 0.0);
  world.survey_normal = Eigen::Vector3d::UnitZ();
  world.survey_along = Eigen::Vector3d::UnitX();
  world.survey_length = options.length_m;
  world.survey_width = strip_width;
  return world;
}

}  // namespace uw::sim
