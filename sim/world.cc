#include "sim/world.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>
#include <sstream>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/util/error.h"
#include "common/util/random.h"

namespace uw::sim {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

// Beyond this a world needs gigabytes once the ray caster holds a copy;
// a configuration asking for it is almost certainly a unit mistake.
constexpr double kMaxTriangles = 2e7;

// Relief octaves stop at this many vertex spacings per wavelength: finer
// relief would alias on the mesh.
constexpr double kVerticesPerFinestWavelength = 4.0;

// Shape of the scarp's profile: a concave talus apron at the foot and a
// rounded crest, as radii of the arcs joining the wall to the flat strips.
constexpr double kScarpFootRadius = 1.5;
constexpr double kScarpCrestRadius = 0.8;

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

// Armour blocks: each layer is this many block sizes thick (blocks nest
// into the voids of the layer below); block centres wander by this
// fraction of a grid cell; off-diagonal shear of the block shape; the
// roughness' longest wavelength in block sizes.
constexpr double kBlockLayerThickness = 0.8;
constexpr double kBlockJitter = 0.8;
constexpr double kBlockShear = 0.12;
constexpr double kBlockRoughnessWavelength = 0.25;
// Blocks' sides (and the crevices between them) are no steeper than this.
constexpr double kBlockMaxSideSlopeDeg = 72.0;

// Canyon: vertical extent of the rounding at the walls' foot and rim (m),
// wavelength of the walls' height variation along the canyon (m), and
// spacing of the polyline that approximates the axis (m; its chord error
// is about 1 mm at the sharpest default bend).
constexpr double kCanyonFootRounding = 1.0;
constexpr double kCanyonRimRounding = 1.5;
constexpr double kCanyonWallHeightWavelength = 20.0;
constexpr double kCanyonAxisStep = 0.25;

// All randomness of a world derives from its seed.
using Random = SplitMix64Stream;

// Wellons' "lowbias32" mix; nested per axis it hashes lattice cells with no
// period shorter than 2^32 cells.
uint32_t Avalanche(uint32_t h) {
  h ^= h >> 16;
  h *= 0x7feb352du;
  h ^= h >> 15;
  h *= 0x846ca68bu;
  h ^= h >> 16;
  return h;
}

double Fade(double t) { return t * t * t * (t * (t * 6.0 - 15.0) + 10.0); }

double SmoothStep01(double t) {
  t = std::clamp(t, 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}

// Perlin's improved gradient noise (2002) on a hashed lattice: C2 smooth,
// zero mean, unit variance after kGradientNoiseStdDev.
class GradientNoise {
 public:
  explicit GradientNoise(uint64_t seed)
      : seed_(static_cast<uint32_t>(seed ^ (seed >> 32))) {}

  double operator()(const Eigen::Vector3d& p) const {
    const Eigen::Vector3d cell = p.array().floor();
    const Eigen::Vector3d f = p - cell;
    const uint32_t ix = static_cast<uint32_t>(static_cast<int64_t>(cell.x()));
    const uint32_t iy = static_cast<uint32_t>(static_cast<int64_t>(cell.y()));
    const uint32_t iz = static_cast<uint32_t>(static_cast<int64_t>(cell.z()));
    double corner[2][2][2];
    for (uint32_t i = 0; i < 2; ++i) {
      const uint32_t hx = Avalanche(seed_ + ix + i);
      for (uint32_t j = 0; j < 2; ++j) {
        const uint32_t hxy = Avalanche(hx + iy + j);
        for (uint32_t k = 0; k < 2; ++k) {
          corner[i][j][k] = Gradient(Avalanche(hxy + iz + k), f.x() - i,
                                     f.y() - j, f.z() - k);
        }
      }
    }
    const double u = Fade(f.x()), v = Fade(f.y()), w = Fade(f.z());
    const auto lerp = [](double a, double b, double t) {
      return a + t * (b - a);
    };
    const double y0 = lerp(lerp(corner[0][0][0], corner[1][0][0], u),
                           lerp(corner[0][1][0], corner[1][1][0], u), v);
    const double y1 = lerp(lerp(corner[0][0][1], corner[1][0][1], u),
                           lerp(corner[0][1][1], corner[1][1][1], u), v);
    return lerp(y0, y1, w) / kStdDev;
  }

 private:
  // Standard deviation of the raw noise over random points in 3D, measured
  // over 2 * 10^6 of them (0.27; 0.25 on a lattice plane).
  static constexpr double kStdDev = 0.27;

  // Dot product with one of Perlin's 12 cube-edge gradients (four repeated
  // to make 16).
  static double Gradient(uint32_t hash, double x, double y, double z) {
    switch (hash >> 28) {
      case 0:
      case 12:
        return x + y;
      case 1:
      case 13:
        return -x + y;
      case 2:
        return x - y;
      case 3:
        return -x - y;
      case 4:
        return x + z;
      case 5:
        return -x + z;
      case 6:
        return x - z;
      case 7:
        return -x - z;
      case 8:
        return y + z;
      case 9:
      case 14:
        return -y + z;
      case 10:
        return y - z;
      default:
        return -y - z;
    }
  }

  uint32_t seed_;
};

// Fractal Brownian motion of unit variance: octaves from `wavelength` down
// to `min_wavelength` (at least one), each half the wavelength and
// amplitude of the previous one and randomly shifted.
class Fbm {
 public:
  Fbm(Random& random, double wavelength, double min_wavelength)
      : noise_(random.Next()) {
    double sum_squares = 0.0;
    for (double lambda = wavelength, amplitude = 1.0;
         octaves_.empty() || lambda >= min_wavelength;
         lambda *= 0.5, amplitude *= 0.5) {
      const Eigen::Vector3d shift(random.Uniform(0.0, 1024.0),
                                  random.Uniform(0.0, 1024.0),
                                  random.Uniform(0.0, 1024.0));
      octaves_.push_back({1.0 / lambda, amplitude, shift});
      sum_squares += amplitude * amplitude;
    }
    for (Octave& octave : octaves_) octave.amplitude /= std::sqrt(sum_squares);
  }

  double operator()(const Eigen::Vector3d& p) const {
    double sum = 0.0;
    for (const Octave& octave : octaves_) {
      sum += octave.amplitude * noise_(octave.frequency * p + octave.shift);
    }
    return sum;
  }

 private:
  struct Octave {
    double frequency;
    double amplitude;
    Eigen::Vector3d shift;
  };
  GradientNoise noise_;
  std::vector<Octave> octaves_;
};

// Height (or displacement) of a surface: undulation plus roughness.
class Relief {
 public:
  Relief(const ReliefOptions& options, double vertex_spacing, Random& random)
      : options_(options),
        undulation_(random, options.undulation_wavelength_m,
                    kVerticesPerFinestWavelength * vertex_spacing),
        roughness_(random, options.roughness_wavelength_m,
                   kVerticesPerFinestWavelength * vertex_spacing) {}

  double operator()(const Eigen::Vector3d& p) const {
    return options_.undulation_amplitude_m * undulation_(p) +
           options_.roughness_amplitude_m * roughness_(p);
  }

 private:
  ReliefOptions options_;
  Fbm undulation_;
  Fbm roughness_;
};

// Heights on a regular grid over [x0, x0 + length] x [y0, y0 + width].
struct HeightGrid {
  HeightGrid(double x0, double y0, double length, double width, double spacing)
      : x0(x0),
        y0(y0),
        nx(std::max(2, static_cast<int>(std::ceil(length / spacing)) + 1)),
        ny(std::max(2, static_cast<int>(std::ceil(width / spacing)) + 1)),
        dx(length / (nx - 1)),
        dy(width / (ny - 1)),
        z(static_cast<size_t>(nx) * ny, 0.0) {}

  double x(int i) const { return x0 + dx * i; }
  double y(int j) const { return y0 + dy * j; }
  double& at(int i, int j) { return z[static_cast<size_t>(j) * nx + i]; }

  double x0, y0;
  int nx, ny;
  double dx, dy;
  std::vector<double> z;
};

// Triangles of an nu x nv grid of vertices stored v-major from `first`,
// wound counter-clockwise in (u, v) so that normals point along
// dP/du x dP/dv. The cell diagonal alternates like a checkerboard, which
// avoids a directional grain in the shading. With wrap_u the last column
// joins the first (a closed tube).
void AppendGridTriangles(int first, int nu, int nv, bool wrap_u,
                         TriangleMesh* mesh) {
  const int cells_u = wrap_u ? nu : nu - 1;
  const auto index = [&](int i, int j) { return first + j * nu + i % nu; };
  mesh->triangles.reserve(mesh->triangles.size() +
                          2 * static_cast<size_t>(cells_u) * (nv - 1));
  for (int j = 0; j + 1 < nv; ++j) {
    for (int i = 0; i < cells_u; ++i) {
      const int a = index(i, j), b = index(i + 1, j);
      const int c = index(i + 1, j + 1), d = index(i, j + 1);
      if ((i + j) % 2 == 0) {
        mesh->triangles.emplace_back(a, b, c);
        mesh->triangles.emplace_back(a, c, d);
      } else {
        mesh->triangles.emplace_back(a, b, d);
        mesh->triangles.emplace_back(b, c, d);
      }
    }
  }
}

void AppendHeightGrid(const HeightGrid& grid, TriangleMesh* mesh) {
  const int first = static_cast<int>(mesh->vertices.size());
  mesh->vertices.reserve(mesh->vertices.size() + grid.z.size());
  for (int j = 0; j < grid.ny; ++j) {
    for (int i = 0; i < grid.nx; ++i) {
      mesh->vertices.emplace_back(grid.x(i), grid.y(j),
                                  grid.z[static_cast<size_t>(j) * grid.nx + i]);
    }
  }
  AppendGridTriangles(first, grid.nx, grid.ny, /*wrap_u=*/false, mesh);
}

// Where a rock of some radius may lie, by its centre.
using RockPlace = std::function<bool(const Eigen::Vector2d& centre, double)>;

RockPlace OutsideDisc(double keep_out_radius) {
  return [keep_out_radius](const Eigen::Vector2d& centre, double radius) {
    return centre.norm() > keep_out_radius + radius;
  };
}

// Boulders merged into a heightfield: each is a superellipsoid cap with
// an irregular outline and a bumpy top, partly buried in the local ground,
// and the surface is the higher of ground and rock.
void AddRocks(const RockOptions& options,
              const std::function<double(double, double)>& ground,
              const RockPlace& allowed, Random& random, HeightGrid* grid) {
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

// Raises every vertex of the grid to at least the cone of slope max_slope
// (rise over run) hanging from each other vertex, so that no slope is
// steeper: two raster passes propagate the cones over 8-neighbours
// (chamfer distances, within 8 % of Euclidean). Cliffs, which a
// heightfield renders as stair-stepped one-cell walls, become skirts a
// few cells wide.
void LimitSlope(double max_slope, HeightGrid* grid) {
  const double drop_x = max_slope * grid->dx, drop_y = max_slope * grid->dy;
  const double drop_xy = max_slope * std::hypot(grid->dx, grid->dy);
  const auto raise = [grid](int i, int j, int ni, int nj, double drop) {
    if (ni < 0 || ni >= grid->nx || nj < 0 || nj >= grid->ny) return;
    grid->at(i, j) = std::max(grid->at(i, j), grid->at(ni, nj) - drop);
  };
  for (int j = 0; j < grid->ny; ++j) {
    for (int i = 0; i < grid->nx; ++i) {
      raise(i, j, i - 1, j, drop_x);
      raise(i, j, i - 1, j - 1, drop_xy);
      raise(i, j, i, j - 1, drop_y);
      raise(i, j, i + 1, j - 1, drop_xy);
    }
  }
  for (int j = grid->ny - 1; j >= 0; --j) {
    for (int i = grid->nx - 1; i >= 0; --i) {
      raise(i, j, i + 1, j, drop_x);
      raise(i, j, i + 1, j + 1, drop_xy);
      raise(i, j, i, j + 1, drop_y);
      raise(i, j, i - 1, j + 1, drop_xy);
    }
  }
}

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

Eigen::AlignedBox3d Bounds(const TriangleMesh& mesh) {
  Eigen::AlignedBox3d bounds;
  for (const Eigen::Vector3d& vertex : mesh.vertices) bounds.extend(vertex);
  return bounds;
}

World MakeSeafloor(const SeafloorOptions& options, Random& random) {
  const Relief relief(options.relief, options.vertex_spacing_m, random);
  const auto ground = [&relief](double x, double y) {
    return relief(Eigen::Vector3d(x, y, 0.0));
  };
  HeightGrid grid(-0.5 * options.length_m, -0.5 * options.width_m,
                  options.length_m, options.width_m, options.vertex_spacing_m);
  for (int j = 0; j < grid.ny; ++j) {
    for (int i = 0; i < grid.nx; ++i)
      grid.at(i, j) = ground(grid.x(i), grid.y(j));
  }
  AddRocks(options.rocks, ground, OutsideDisc(0.0), random, &grid);

  World world;
  world.name = "seafloor";
  AppendHeightGrid(grid, &world.mesh);
  double sum_z = 0.0;
  for (const double z : grid.z) sum_z += z;
  world.survey_origin = Eigen::Vector3d(0.0, 0.0, sum_z / grid.z.size());
  world.survey_normal = Eigen::Vector3d::UnitZ();
  world.survey_along = Eigen::Vector3d::UnitX();
  world.survey_length = options.length_m;
  world.survey_width = options.width_m;
  return world;
}

// The chimney's radius as a function of angle and height: a tapering body
// with noise, plus flanges.
class Chimney {
 public:
  Chimney(const VentOptions& options, double ground_z, double bottom_z,
          Random& random)
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

World MakeVent(const VentOptions& options, Random& random) {
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
  world.survey_origin = Eigen::Vector3d(0.0, 0.0, Bounds(world.mesh).max().z());
  world.survey_normal = Eigen::Vector3d::UnitZ();
  world.survey_along = Eigen::Vector3d::UnitX();
  world.survey_length = 2.0 * (reach + kVentSurveyMargin);
  world.survey_width = world.survey_length;
  return world;
}

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

World MakeScarp(const ScarpOptions& options, Random& random) {
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

// Signed horizontal distance from the breakwater's crest rectangle
// [-half_length, half_length] x [-half_width, half_width]: negative inside.
// Outside, *away is the unit direction away from the rectangle.
double CrestDistance(double x, double y, double half_length, double half_width,
                     Eigen::Vector2d* away = nullptr) {
  const double dx = std::abs(x) - half_length;
  const double dy = std::abs(y) - half_width;
  const Eigen::Vector2d outside(std::copysign(std::max(dx, 0.0), x),
                                std::copysign(std::max(dy, 0.0), y));
  const double distance = outside.norm();
  if (distance == 0.0) return std::max(dx, dy);
  if (away) *away = outside / distance;
  return distance;
}

// An armour block: the superellipsoid |u|^6 + |v|^6 + |w|^6 <= 1 in unit
// coordinates u = unit_from_world * (p - centre).
struct ArmourBlock {
  Eigen::Vector3d centre;
  Eigen::Matrix3d unit_from_world;
  Eigen::Vector3d reach;  // half extents of its bounding box in the world
};

// Height of the block's upper surface on the vertical line through (x, y),
// if the line meets the block. Along the line, u is linear in z and
// f(z) = sum u_i^6 - 1 convex, so Newton's method started above the upper
// root, at the top of the bounding parallelepiped (|u_i| <= 1), descends
// monotonically onto it; a slope f' <= 0 or falling below the
// parallelepiped means the line passes the block.
std::optional<double> BlockTop(const ArmourBlock& block, double x, double y) {
  const Eigen::Vector3d u0 =
      block.unit_from_world *
      (Eigen::Vector3d(x, y, 0.0) - block.centre);         // u at z = 0
  const Eigen::Vector3d w = block.unit_from_world.col(2);  // du/dz
  double z_low = -std::numeric_limits<double>::infinity();
  double z_high = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 3; ++i) {
    if (w[i] == 0.0) {
      if (std::abs(u0[i]) > 1.0) return std::nullopt;
      continue;
    }
    const double a = (-1.0 - u0[i]) / w[i], b = (1.0 - u0[i]) / w[i];
    z_low = std::max(z_low, std::min(a, b));
    z_high = std::min(z_high, std::max(a, b));
  }
  if (!(z_low < z_high)) return std::nullopt;
  double z = z_high;
  for (int iteration = 0; iteration < 60; ++iteration) {
    double f = -1.0, slope = 0.0;
    for (int i = 0; i < 3; ++i) {
      const double u = u0[i] + z * w[i];
      const double u2 = u * u, u5 = u2 * u2 * u;
      f += u5 * u;
      slope += 6.0 * w[i] * u5;
    }
    if (slope <= 0.0) return std::nullopt;
    const double step = f / slope;
    z -= step;
    if (z < z_low) return std::nullopt;
    if (step < 1e-7) break;
  }
  return z;
}

// Armour blocks laid on the design surface, layer by layer from the core
// outwards: one jittered grid in plan per layer, each shifted by half a
// cell, of cells block_size_m * cos(slope) wide (about one block per block
// area on the slopes, a denser packing on the crest).
std::vector<ArmourBlock> LayArmour(const BreakwaterOptions& options,
                                   Random& random) {
  const double slope = options.slope_deg * kDegToRad;
  const double run = options.height_m / std::tan(slope);
  const double half_length = 0.5 * options.length_m;
  const double half_width = 0.5 * options.crest_width_m;
  const double size = options.block_size_m;
  const double thickness = kBlockLayerThickness * size;
  const double cell = size * std::cos(slope);
  const double tilt = options.block_tilt_deg * kDegToRad;
  // Blocks reach a little beyond the toe of the design profile.
  const double reach = run + 0.3 * size;
  const int nx =
      static_cast<int>(std::ceil(2.0 * (half_length + reach) / cell));
  const int ny = static_cast<int>(std::ceil(2.0 * (half_width + reach) / cell));
  std::vector<ArmourBlock> blocks;
  for (int layer = 0; layer < options.block_layers; ++layer) {
    const double shift = (layer % 2 == 0 ? 0.0 : 0.5) * cell;
    // Depth of the layer's middle below the design surface.
    const double depth = (options.block_layers - layer - 0.5) * thickness;
    for (int j = 0; j < ny; ++j) {
      for (int i = 0; i < nx; ++i) {
        const double x =
            -half_length - reach + shift +
            (i + 0.5 + kBlockJitter * random.Uniform(-0.5, 0.5)) * cell;
        const double y =
            -half_width - reach + shift +
            (j + 0.5 + kBlockJitter * random.Uniform(-0.5, 0.5)) * cell;
        const double yaw = random.Uniform(0.0, 2.0 * M_PI);
        const double tilt_azimuth = random.Uniform(0.0, 2.0 * M_PI);
        const double tilt_angle = tilt * random.Uniform(-1.0, 1.0);
        Eigen::Vector3d half_extents;
        for (int k = 0; k < 3; ++k) {
          half_extents[k] =
              0.5 * size *
              (1.0 + options.block_size_variation * random.Uniform(-1.0, 1.0));
        }
        Eigen::Matrix3d shear = Eigen::Matrix3d::Identity();
        for (int r = 0; r < 3; ++r) {
          for (int c = 0; c < 3; ++c) {
            if (r != c) shear(r, c) = kBlockShear * random.Uniform(-1.0, 1.0);
          }
        }
        Eigen::Vector2d away = Eigen::Vector2d::Zero();
        const double distance =
            CrestDistance(x, y, half_length, half_width, &away);
        if (distance > reach) continue;
        const Eigen::Vector3d surface(
            x, y, options.height_m - std::max(distance, 0.0) * std::tan(slope));
        const Eigen::Vector3d normal =
            distance > 0.0 ? Eigen::Vector3d(std::tan(slope) * away.x(),
                                             std::tan(slope) * away.y(), 1.0)
                                 .normalized()
                           : Eigen::Vector3d::UnitZ();
        const Eigen::Matrix3d world_from_block =
            (Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(),
                                                normal) *
             Eigen::AngleAxisd(tilt_angle,
                               Eigen::Vector3d(std::cos(tilt_azimuth),
                                               std::sin(tilt_azimuth), 0.0)) *
             Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()))
                .toRotationMatrix();
        const Eigen::Matrix3d world_from_unit =
            world_from_block * shear * half_extents.asDiagonal();
        ArmourBlock block;
        block.centre = surface - depth * normal;
        block.unit_from_world = world_from_unit.inverse();
        block.reach = world_from_unit.cwiseAbs().rowwise().sum();
        blocks.push_back(block);
      }
    }
  }
  return blocks;
}

World MakeBreakwater(const BreakwaterOptions& options, Random& random) {
  const double slope = options.slope_deg * kDegToRad;
  const double run = options.height_m / std::tan(slope);
  const double half_length = 0.5 * options.length_m;
  const double half_width = 0.5 * options.crest_width_m;
  const Relief relief(options.relief, options.vertex_spacing_m, random);
  const Fbm roughness(random, kBlockRoughnessWavelength * options.block_size_m,
                      kVerticesPerFinestWavelength * options.vertex_spacing_m);
  const auto floor = [&relief](double x, double y) {
    return relief(Eigen::Vector3d(x, y, 0.0));
  };
  const double x_extent = half_length + run + options.apron_width_m;
  const double y_extent = half_width + run + options.apron_width_m;
  // The seafloor and the core: the design profile moved inwards by the
  // armour's thickness (horizontally by thickness / sin(slope) on the
  // slopes), as rough as the seafloor; the core shows in the voids between
  // blocks.
  const double armour =
      options.block_layers * kBlockLayerThickness * options.block_size_m;
  HeightGrid grid(-x_extent, -y_extent, 2.0 * x_extent, 2.0 * y_extent,
                  options.vertex_spacing_m);
  for (int j = 0; j < grid.ny; ++j) {
    for (int i = 0; i < grid.nx; ++i) {
      const double x = grid.x(i), y = grid.y(j);
      const double core =
          std::min(options.height_m - armour,
                   (run - armour / std::sin(slope) -
                    CrestDistance(x, y, half_length, half_width)) *
                       std::tan(slope));
      grid.at(i, j) = floor(x, y) + std::max(core, 0.0);
    }
  }
  // The blocks are drawn before the rocks, so that changing the rocks
  // leaves them as they were. Rocks lie off the mound, so merging them
  // after the core changes nothing.
  const std::vector<ArmourBlock> blocks = LayArmour(options, random);
  AddRocks(
      options.rocks, floor,
      [&](const Eigen::Vector2d& centre, double radius) {
        return CrestDistance(centre.x(), centre.y(), half_length, half_width) >
               run + radius;
      },
      random, &grid);

  for (const ArmourBlock& block : blocks) {
    const int i0 = std::max(
        0, static_cast<int>(std::floor(
               (block.centre.x() - block.reach.x() - grid.x0) / grid.dx)));
    const int i1 = std::min(
        grid.nx - 1,
        static_cast<int>(std::ceil(
            (block.centre.x() + block.reach.x() - grid.x0) / grid.dx)));
    const int j0 = std::max(
        0, static_cast<int>(std::floor(
               (block.centre.y() - block.reach.y() - grid.y0) / grid.dy)));
    const int j1 = std::min(
        grid.ny - 1,
        static_cast<int>(std::ceil(
            (block.centre.y() + block.reach.y() - grid.y0) / grid.dy)));
    for (int j = j0; j <= j1; ++j) {
      for (int i = i0; i <= i1; ++i) {
        const std::optional<double> top = BlockTop(block, grid.x(i), grid.y(j));
        if (!top) continue;
        const double z =
            *top + options.block_roughness_m *
                       roughness(Eigen::Vector3d(grid.x(i), grid.y(j), *top));
        grid.at(i, j) = std::max(grid.at(i, j), z);
      }
    }
  }

  LimitSlope(std::tan(kBlockMaxSideSlopeDeg * kDegToRad), &grid);

  World world;
  world.name = "breakwater";
  AppendHeightGrid(grid, &world.mesh);
  world.survey_origin =
      Eigen::Vector3d(0.0, -half_width - 0.5 * run, 0.5 * options.height_m);
  world.survey_normal = Eigen::Vector3d(0.0, -std::sin(slope), std::cos(slope));
  world.survey_along = Eigen::Vector3d::UnitX();
  world.survey_length = options.length_m;
  world.survey_width = options.height_m / std::sin(slope);
  return world;
}

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
  CanyonAxis(const CanyonOptions& options, Random& random)
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

World MakeCanyon(const CanyonOptions& options, Random& random) {
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

// ---------------------------------------------------------------------------
// Option checks.

std::string Field(const std::string& section, const char* name) {
  return "world options: " + section + "." + name;
}

void CheckPositive(double value, const std::string& section, const char* name) {
  if (!(value > 0.0 && std::isfinite(value))) {
    throw ErrorAt(Field(section, name), " = ", value,
                  ": must be a positive number");
  }
}

void CheckNonNegative(double value, const std::string& section,
                      const char* name) {
  if (!(value >= 0.0 && std::isfinite(value))) {
    throw ErrorAt(Field(section, name), " = ", value,
                  ": must be a non-negative number");
  }
}

void CheckRange(double value, double low, double high,
                const std::string& section, const char* name) {
  if (!(value >= low && value <= high)) {
    throw ErrorAt(Field(section, name), " = ", value, ": must be in [", low,
                  ", ", high, "]");
  }
}

void CheckTriangles(double triangles, const std::string& section,
                    const char* spacing_name) {
  if (triangles > kMaxTriangles) {
    throw ErrorAt("world options: ", section, ": about ", triangles,
                  " triangles exceed the limit of ", kMaxTriangles,
                  "; increase ", section, ".", spacing_name,
                  " or reduce the size");
  }
}

// ---------------------------------------------------------------------------
// JSON: one description of every section's fields serves writing and
// reading. Visit* call visitor.Field(name, value) for numbers and arrays
// and visitor.Section(name, sub_options, visit_sub) for nested sections.

template <typename Options, typename Visitor>
void VisitRelief(Options& o, Visitor& v) {
  v.Field("undulation_amplitude_m", o.undulation_amplitude_m);
  v.Field("undulation_wavelength_m", o.undulation_wavelength_m);
  v.Field("roughness_amplitude_m", o.roughness_amplitude_m);
  v.Field("roughness_wavelength_m", o.roughness_wavelength_m);
}

template <typename Options, typename Visitor>
void VisitRocks(Options& o, Visitor& v) {
  v.Field("count", o.count);
  v.Field("min_diameter_m", o.min_diameter_m);
  v.Field("max_diameter_m", o.max_diameter_m);
}

template <typename Options, typename Visitor>
void VisitSeafloor(Options& o, Visitor& v) {
  v.Field("length_m", o.length_m);
  v.Field("width_m", o.width_m);
  v.Field("vertex_spacing_m", o.vertex_spacing_m);
  v.Section("relief", o.relief, [](auto& s, auto& w) { VisitRelief(s, w); });
  v.Section("rocks", o.rocks, [](auto& s, auto& w) { VisitRocks(s, w); });
}

template <typename Options, typename Visitor>
void VisitVent(Options& o, Visitor& v) {
  v.Field("ground_size_m", o.ground_size_m);
  v.Field("ground_vertex_spacing_m", o.ground_vertex_spacing_m);
  v.Section("ground_relief", o.ground_relief,
            [](auto& s, auto& w) { VisitRelief(s, w); });
  v.Section("ground_rocks", o.ground_rocks,
            [](auto& s, auto& w) { VisitRocks(s, w); });
  v.Field("mound_height_m", o.mound_height_m);
  v.Field("mound_radius_m", o.mound_radius_m);
  v.Field("chimney_height_m", o.chimney_height_m);
  v.Field("chimney_base_radius_m", o.chimney_base_radius_m);
  v.Field("chimney_top_radius_m", o.chimney_top_radius_m);
  v.Field("chimney_radius_noise", o.chimney_radius_noise);
  v.Field("chimney_lean_m", o.chimney_lean_m);
  v.Field("flange_count", o.flange_count);
  v.Field("flange_min_width_m", o.flange_min_width_m);
  v.Field("flange_max_width_m", o.flange_max_width_m);
  v.Field("chimney_vertex_spacing_m", o.chimney_vertex_spacing_m);
}

template <typename Options, typename Visitor>
void VisitScarp(Options& o, Visitor& v) {
  v.Field("length_m", o.length_m);
  v.Field("height_m", o.height_m);
  v.Field("dip_deg", o.dip_deg);
  v.Field("foot_width_m", o.foot_width_m);
  v.Field("crest_width_m", o.crest_width_m);
  v.Field("vertex_spacing_m", o.vertex_spacing_m);
  v.Section("relief", o.relief, [](auto& s, auto& w) { VisitRelief(s, w); });
  v.Field("meander_amplitude_m", o.meander_amplitude_m);
  v.Field("meander_wavelength_m", o.meander_wavelength_m);
}

template <typename Options, typename Visitor>
void VisitBreakwater(Options& o, Visitor& v) {
  v.Field("length_m", o.length_m);
  v.Field("height_m", o.height_m);
  v.Field("crest_width_m", o.crest_width_m);
  v.Field("slope_deg", o.slope_deg);
  v.Field("apron_width_m", o.apron_width_m);
  v.Field("vertex_spacing_m", o.vertex_spacing_m);
  v.Section("relief", o.relief, [](auto& s, auto& w) { VisitRelief(s, w); });
  v.Section("rocks", o.rocks, [](auto& s, auto& w) { VisitRocks(s, w); });
  v.Field("block_size_m", o.block_size_m);
  v.Field("block_size_variation", o.block_size_variation);
  v.Field("block_layers", o.block_layers);
  v.Field("block_tilt_deg", o.block_tilt_deg);
  v.Field("block_roughness_m", o.block_roughness_m);
}

template <typename Options, typename Visitor>
void VisitCanyon(Options& o, Visitor& v) {
  v.Field("length_m", o.length_m);
  v.Field("width_m", o.width_m);
  v.Field("floor_width_m", o.floor_width_m);
  v.Field("wall_height_m", o.wall_height_m);
  v.Field("wall_height_variation_m", o.wall_height_variation_m);
  v.Field("wall_slope_deg", o.wall_slope_deg);
  v.Field("meander_amplitude_m", o.meander_amplitude_m);
  v.Field("meander_wavelength_m", o.meander_wavelength_m);
  v.Field("wall_relief_m", o.wall_relief_m);
  v.Field("wall_relief_wavelength_m", o.wall_relief_wavelength_m);
  v.Field("vertex_spacing_m", o.vertex_spacing_m);
  v.Section("relief", o.relief, [](auto& s, auto& w) { VisitRelief(s, w); });
  v.Section("rocks", o.rocks, [](auto& s, auto& w) { VisitRocks(s, w); });
}

template <typename Options, typename Visitor>
void VisitTexture(Options& o, Visitor& v) {
  v.Field("grain_wavelength_m", o.grain_wavelength_m);
  v.Field("grain_octaves", o.grain_octaves);
  v.Field("grain_contrast", o.grain_contrast);
  v.Field("patch_wavelength_m", o.patch_wavelength_m);
  v.Field("region_wavelength_m", o.region_wavelength_m);
  v.Field("patch_contrast", o.patch_contrast);
  v.Field("sediment_cover", o.sediment_cover);
  v.Field("rock_albedo", o.rock_albedo);
  v.Field("sediment_albedo", o.sediment_albedo);
  v.Field("stain_albedo", o.stain_albedo);
  v.Field("stain_strength", o.stain_strength);
}

template <typename Options, typename Visitor>
void VisitWorld(Options& o, Visitor& v) {
  v.Section("seafloor", o.seafloor,
            [](auto& s, auto& w) { VisitSeafloor(s, w); });
  v.Section("vent", o.vent, [](auto& s, auto& w) { VisitVent(s, w); });
  v.Section("scarp", o.scarp, [](auto& s, auto& w) { VisitScarp(s, w); });
  v.Section("breakwater", o.breakwater,
            [](auto& s, auto& w) { VisitBreakwater(s, w); });
  v.Section("canyon", o.canyon, [](auto& s, auto& w) { VisitCanyon(s, w); });
  v.Section("texture", o.texture, [](auto& s, auto& w) { VisitTexture(s, w); });
}

class JsonWriter {
 public:
  explicit JsonWriter(nlohmann::json* json) : json_(json) {
    *json_ = nlohmann::json::object();
  }
  template <typename T>
  void Field(const char* name, const T& value) {
    (*json_)[name] = value;
  }
  template <typename Sub, typename Visit>
  void Section(const char* name, const Sub& sub, Visit visit) {
    JsonWriter writer(&(*json_)[name]);
    visit(sub, writer);
  }

 private:
  nlohmann::json* json_;
};

class JsonReader {
 public:
  JsonReader(const nlohmann::json& json, std::string path)
      : json_(json), path_(std::move(path)) {
    if (!json_.is_object()) {
      throw ErrorAt(Where(), ": expected a JSON object, got ", json_.dump());
    }
  }

  void Field(const char* name, double& value) {
    if (const nlohmann::json* item = Find(name)) {
      if (!item->is_number()) Fail(name, "a number", *item);
      value = item->get<double>();
    }
  }
  void Field(const char* name, int& value) {
    if (const nlohmann::json* item = Find(name)) {
      if (!item->is_number_integer()) Fail(name, "an integer", *item);
      const int64_t wide = item->get<int64_t>();
      if (wide < std::numeric_limits<int>::min() ||
          wide > std::numeric_limits<int>::max()) {
        Fail(name, "an integer in the range of int", *item);
      }
      value = static_cast<int>(wide);
    }
  }
  void Field(const char* name, std::array<double, 3>& value) {
    if (const nlohmann::json* item = Find(name)) {
      if (!item->is_array() || item->size() != 3 ||
          !std::all_of(item->begin(), item->end(),
                       [](const nlohmann::json& x) { return x.is_number(); })) {
        Fail(name, "an array of 3 numbers", *item);
      }
      for (int k = 0; k < 3; ++k) value[k] = (*item)[k].get<double>();
    }
  }
  template <typename Sub, typename Visit>
  void Section(const char* name, Sub& sub, Visit visit) {
    if (const nlohmann::json* item = Find(name)) {
      JsonReader reader(*item, path_.empty() ? name : path_ + "." + name);
      visit(sub, reader);
      reader.RejectUnknownKeys();
    }
  }

  // Called after visiting: a key no field asked for is a typo or a
  // parameter this version does not have.
  void RejectUnknownKeys() const {
    for (const auto& [key, value] : json_.items()) {
      if (std::find(known_.begin(), known_.end(), key) == known_.end()) {
        std::ostringstream valid;
        for (size_t i = 0; i < known_.size(); ++i) {
          valid << (i ? ", " : "") << known_[i];
        }
        throw ErrorAt(Where(), ": unknown key \"", key,
                      "\" (valid: ", valid.str(), ")");
      }
    }
  }

 private:
  const nlohmann::json* Find(const char* name) {
    known_.emplace_back(name);
    const auto it = json_.find(name);
    return it == json_.end() ? nullptr : &*it;
  }

  [[noreturn]] void Fail(const char* name, const char* expected,
                         const nlohmann::json& item) const {
    throw ErrorAt(Where(), path_.empty() ? "" : ".", name, ": expected ",
                  expected, ", got ", item.dump());
  }

  std::string Where() const {
    return path_.empty() ? "world options" : "world options: " + path_;
  }

  const nlohmann::json& json_;
  std::string path_;
  std::vector<std::string> known_;
};

}  // namespace

std::string WorldKindName(WorldKind kind) {
  switch (kind) {
    case WorldKind::kSeafloor:
      return "seafloor";
    case WorldKind::kVent:
      return "vent";
    case WorldKind::kScarp:
      return "scarp";
    case WorldKind::kBreakwater:
      return "breakwater";
    case WorldKind::kCanyon:
      return "canyon";
  }
  throw ErrorAt("WorldKindName: invalid WorldKind ", static_cast<int>(kind));
}

WorldKind WorldKindFromName(const std::string& name) {
  std::string valid;
  for (const WorldKind kind :
       {WorldKind::kSeafloor, WorldKind::kVent, WorldKind::kScarp,
        WorldKind::kBreakwater, WorldKind::kCanyon}) {
    if (WorldKindName(kind) == name) return kind;
    valid += (valid.empty() ? "" : ", ") + WorldKindName(kind);
  }
  throw ErrorAt("unknown world \"", name, "\" (valid: ", valid, ")");
}

void ReliefOptions::Check(const std::string& where) const {
  CheckNonNegative(undulation_amplitude_m, where, "undulation_amplitude_m");
  CheckPositive(undulation_wavelength_m, where, "undulation_wavelength_m");
  CheckNonNegative(roughness_amplitude_m, where, "roughness_amplitude_m");
  CheckPositive(roughness_wavelength_m, where, "roughness_wavelength_m");
}

void RockOptions::Check(const std::string& where) const {
  CheckRange(count, 0, 100000, where, "count");
  CheckPositive(min_diameter_m, where, "min_diameter_m");
  CheckPositive(max_diameter_m, where, "max_diameter_m");
  if (min_diameter_m > max_diameter_m) {
    throw ErrorAt(Field(where, "min_diameter_m"), " = ", min_diameter_m,
                  ": exceeds max_diameter_m = ", max_diameter_m);
  }
}

void SeafloorOptions::Check() const {
  const std::string section = "seafloor";
  CheckPositive(length_m, section, "length_m");
  CheckPositive(width_m, section, "width_m");
  CheckPositive(vertex_spacing_m, section, "vertex_spacing_m");
  relief.Check(section + ".relief");
  rocks.Check(section + ".rocks");
  if (rocks.count > 0 && rocks.max_diameter_m >= std::min(length_m, width_m)) {
    throw ErrorAt(Field(section, "rocks.max_diameter_m"), " = ",
                  rocks.max_diameter_m, ": rocks must fit on the floor");
  }
  CheckTriangles(2.0 * (length_m / vertex_spacing_m + 1.0) *
                     (width_m / vertex_spacing_m + 1.0),
                 section, "vertex_spacing_m");
}

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
    throw ErrorAt(Field(section, "flange_min_width_m"), " = ",
                  flange_min_width_m,
                  ": exceeds flange_max_width_m = ", flange_max_width_m);
  }
  CheckPositive(chimney_vertex_spacing_m, section, "chimney_vertex_spacing_m");
  const double footprint =
      2.0 * (std::max(chimney_base_radius_m, chimney_top_radius_m) *
                 (1.0 + 4.0 * chimney_radius_noise) +
             flange_max_width_m + 3.0 * chimney_lean_m);
  if (ground_size_m < footprint + 2.0) {
    throw ErrorAt(Field(section, "ground_size_m"), " = ", ground_size_m,
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

void ScarpOptions::Check() const {
  const std::string section = "scarp";
  CheckPositive(length_m, section, "length_m");
  CheckPositive(height_m, section, "height_m");
  if (!(dip_deg > 45.0 && dip_deg <= 90.0)) {
    throw ErrorAt(Field(section, "dip_deg"), " = ", dip_deg,
                  ": must be in (45, 90] (a wall, not a slope)");
  }
  const double dip = dip_deg * kDegToRad;
  const double rounding =
      (kScarpFootRadius + kScarpCrestRadius) * std::tan(0.5 * dip);
  if (height_m / std::sin(dip) <= rounding) {
    throw ErrorAt(Field(section, "height_m"), " = ", height_m,
                  ": too low for the rounded foot and crest (needs more than ",
                  rounding * std::sin(dip), " m at this dip)");
  }
  const double foot_cut = kScarpFootRadius * std::tan(0.5 * dip);
  const double crest_cut = kScarpCrestRadius * std::tan(0.5 * dip);
  if (!(foot_width_m >= foot_cut && std::isfinite(foot_width_m))) {
    throw ErrorAt(Field(section, "foot_width_m"), " = ", foot_width_m,
                  ": must be at least ", foot_cut,
                  " m (the apron at the foot)");
  }
  if (!(crest_width_m >= crest_cut && std::isfinite(crest_width_m))) {
    throw ErrorAt(Field(section, "crest_width_m"), " = ", crest_width_m,
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

void BreakwaterOptions::Check() const {
  const std::string section = "breakwater";
  CheckPositive(length_m, section, "length_m");
  CheckPositive(height_m, section, "height_m");
  CheckNonNegative(crest_width_m, section, "crest_width_m");
  CheckRange(slope_deg, 10.0, 60.0, section, "slope_deg");
  CheckPositive(apron_width_m, section, "apron_width_m");
  CheckPositive(vertex_spacing_m, section, "vertex_spacing_m");
  relief.Check(section + ".relief");
  rocks.Check(section + ".rocks");
  if (rocks.count > 0 && rocks.max_diameter_m >= apron_width_m) {
    throw ErrorAt(Field(section, "rocks.max_diameter_m"), " = ",
                  rocks.max_diameter_m, ": rocks must fit on the apron (",
                  apron_width_m, " m)");
  }
  CheckPositive(block_size_m, section, "block_size_m");
  // Smaller blocks would not be resolved by the mesh (and would number
  // millions).
  if (block_size_m < kVerticesPerFinestWavelength * vertex_spacing_m) {
    throw ErrorAt(Field(section, "block_size_m"), " = ", block_size_m,
                  ": must span at least ", kVerticesPerFinestWavelength,
                  " vertex spacings (",
                  kVerticesPerFinestWavelength * vertex_spacing_m, " m)");
  }
  CheckRange(block_size_variation, 0.0, 0.5, section, "block_size_variation");
  CheckRange(block_layers, 1, 4, section, "block_layers");
  CheckRange(block_tilt_deg, 0.0, 45.0, section, "block_tilt_deg");
  CheckNonNegative(block_roughness_m, section, "block_roughness_m");
  const double armour = block_layers * kBlockLayerThickness * block_size_m;
  if (height_m <= armour) {
    throw ErrorAt(Field(section, "height_m"), " = ", height_m,
                  ": must exceed the armour's thickness (", armour, " m for ",
                  block_layers, " layers of ", block_size_m, " m blocks)");
  }
  const double run = height_m / std::tan(slope_deg * kDegToRad);
  CheckTriangles(
      2.0 *
          ((length_m + 2.0 * (run + apron_width_m)) / vertex_spacing_m + 1.0) *
          ((crest_width_m + 2.0 * (run + apron_width_m)) / vertex_spacing_m +
           1.0),
      section, "vertex_spacing_m");
}

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
    throw ErrorAt(Field(section, "floor_width_m"), " = ", floor_width_m,
                  ": leaves a straight strip of ", strip,
                  " m along the floor; must be at least ",
                  floor_width_m - strip + 1.0,
                  " m (2 x (meander_amplitude_m + wall_relief_m) + 1 m)");
  }
  if (rocks.count > 0 && rocks.max_diameter_m >= floor_width_m) {
    throw ErrorAt(Field(section, "rocks.max_diameter_m"), " = ",
                  rocks.max_diameter_m, ": rocks must fit on the floor");
  }
  const double needed =
      floor_width_m +
      2.0 * (meander_amplitude_m + wall_relief_m +
             (wall_height_m + wall_height_variation_m + kCanyonRimRounding) /
                 std::tan(wall_slope_deg * kDegToRad) +
             1.0);
  if (!(width_m >= needed)) {
    throw ErrorAt(Field(section, "width_m"), " = ", width_m,
                  ": too narrow for the canyon and 1 m of rim on each side "
                  "(needs ",
                  needed, " m)");
  }
  CheckTriangles(2.0 * (length_m / vertex_spacing_m + 1.0) *
                     (width_m / vertex_spacing_m + 1.0),
                 section, "vertex_spacing_m");
}

void WorldOptions::Check() const {
  seafloor.Check();
  vent.Check();
  scarp.Check();
  breakwater.Check();
  canyon.Check();
  texture.Check();
}

void to_json(nlohmann::json& json, const WorldOptions& options) {
  JsonWriter writer(&json);
  VisitWorld(options, writer);
}

void from_json(const nlohmann::json& json, WorldOptions& options) {
  JsonReader reader(json, "");
  VisitWorld(options, reader);
  reader.RejectUnknownKeys();
}

World MakeWorld(const WorldKind kind, const WorldOptions& options,
                const uint64_t seed) {
  options.Check();
  // Independent streams for geometry and texture: changing a geometry
  // parameter leaves the texture as it was.
  Random seeds(seed);
  Random geometry(seeds.Next());
  const uint64_t texture_seed = seeds.Next();
  World world;
  switch (kind) {
    case WorldKind::kSeafloor:
      world = MakeSeafloor(options.seafloor, geometry);
      break;
    case WorldKind::kVent:
      world = MakeVent(options.vent, geometry);
      break;
    case WorldKind::kScarp:
      world = MakeScarp(options.scarp, geometry);
      break;
    case WorldKind::kBreakwater:
      world = MakeBreakwater(options.breakwater, geometry);
      break;
    case WorldKind::kCanyon:
      world = MakeCanyon(options.canyon, geometry);
      break;
  }
  world.texture =
      std::make_shared<const ProceduralTexture>(options.texture, texture_seed);
  world.bounds = Bounds(world.mesh);
  return world;
}

}  // namespace uw::sim
