#include "sim/worlds/rocks.h"

#include <algorithm>
#include <cmath>

#include "common/util/error.h"
#include "sim/worlds/noise.h"
#include "sim/worlds/option_checks.h"
#include "sim/worlds/relief.h"

namespace uw::sim {

void RockOptions::Check(const std::string& where) const {
  CheckRange(count, 0, 100000, where, "count");
  CheckPositive(min_diameter_m, where, "min_diameter_m");
  CheckPositive(max_diameter_m, where, "max_diameter_m");
  if (min_diameter_m > max_diameter_m) {
    throw ErrorAt(OptionName(where, "min_diameter_m"), " = ", min_diameter_m,
                  ": exceeds max_diameter_m = ", max_diameter_m);
  }
}

RockPlace OutsideDisc(double keep_out_radius) {
  return [keep_out_radius](const Eigen::Vector2d& centre, double radius) {
    return centre.norm() > keep_out_radius + radius;
  };
}

void AddRocks(const RockOptions& options,
              const std::function<double(double, double)>& ground,
              const RockPlace& allowed, SplitMix64Stream& random,
              HeightGrid* grid) {
  const GradientNoise outline_noise(random.Next());
  const GradientNoise bump_noise(random.Next());
  const double x1 = grid->x(grid->nx - 1), y1 = grid->y(grid->ny - 1);
  for (int rock = 0; rock < options.count; ++rock) {
    // Diameters with density proportional to d^-2 (inverse CDF).
    const double d0 = options.min_diameter_m, d1 = options.max_diameter_m;
    const double diameter =
        1.0 / (1.0 / d0 - random.Uniform() * (1.0 / d0 - 1.0 / d1));
    const double radius = 0.5 * diameter;
    const double aspect = random.Uniform(0.6, 1.0);
    const double angle = random.Uniform(0.0, 2.0 * M_PI);
    const double height = radius * random.Uniform(0.5, 1.0);
    Eigen::Vector2d centre;
    // Redraw a centre where the rock may not lie (the vent's chimney, off a
    // canyon's floor): with a fraction f of the grid excluded, all 64
    // tries fail with probability f^64, 1e-7 for the default canyon's
    // ~78 %.
    bool placed = false;
    for (int attempt = 0; attempt < 64 && !placed; ++attempt) {
      centre = Eigen::Vector2d(random.Uniform(grid->x0 + radius, x1 - radius),
                               random.Uniform(grid->y0 + radius, y1 - radius));
      placed = allowed(centre, radius);
    }
    if (!placed) continue;
    const double base = ground(centre.x(), centre.y()) - 0.25 * height;
    const double cos_a = std::cos(angle), sin_a = std::sin(angle);
    const double bump_wavelength =
        std::max(radius, kVerticesPerFinestWavelength * grid->dx);
    // The outline wobbles by up to 20 %; the box covers it.
    const double reach = 1.3 * radius;
    const int i0 = std::max(
        0, static_cast<int>(
               std::floor((centre.x() - reach - grid->x0) / grid->dx)));
    const int i1 = std::min(grid->nx - 1,
                            static_cast<int>(std::ceil(
                                (centre.x() + reach - grid->x0) / grid->dx)));
    const int j0 = std::max(
        0, static_cast<int>(
               std::floor((centre.y() - reach - grid->y0) / grid->dy)));
    const int j1 = std::min(grid->ny - 1,
                            static_cast<int>(std::ceil(
                                (centre.y() + reach - grid->y0) / grid->dy)));
    for (int j = j0; j <= j1; ++j) {
      for (int i = i0; i <= i1; ++i) {
        const double px = grid->x(i) - centre.x(), py = grid->y(j) - centre.y();
        const double u = (cos_a * px + sin_a * py) / radius;
        const double v = (-sin_a * px + cos_a * py) / (aspect * radius);
        const double phi = std::atan2(v, u);
        const double wobble =
            0.12 * outline_noise(Eigen::Vector3d(
                       1.3 * std::cos(phi), 1.3 * std::sin(phi), 7.1 * rock));
        const double q =
            std::hypot(u, v) / (1.0 + std::clamp(wobble, -0.2, 0.2));
        if (q >= 1.0) continue;
        constexpr double kRoundness = 2.5;  // 2: ellipsoid; larger: blockier
        const double cap =
            std::pow(1.0 - std::pow(q, kRoundness), 1.0 / kRoundness);
        // Bumps no finer than the mesh resolves.
        const double bumps =
            0.08 * radius *
            bump_noise(Eigen::Vector3d(grid->x(i), grid->y(j), 3.3 * rock) /
                       bump_wavelength);
        grid->at(i, j) = std::max(grid->at(i, j), base + height * cap + bumps);
      }
    }
  }
}

}  // namespace uw::sim
