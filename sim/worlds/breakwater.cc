#include "sim/worlds/breakwater.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

#include <Eigen/Geometry>

#include "common/util/error.h"
#include "sim/world.h"
#include "sim/worlds/height_grid.h"
#include "sim/worlds/noise.h"
#include "sim/worlds/option_checks.h"

namespace uw::sim {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

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
                                   SplitMix64Stream& random) {
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

}  // namespace

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
    throw ErrorAt(OptionName(section, "rocks.max_diameter_m"), " = ",
                  rocks.max_diameter_m, ": rocks must fit on the apron (",
                  apron_width_m, " m)");
  }
  CheckPositive(block_size_m, section, "block_size_m");
  // Smaller blocks would not be resolved by the mesh (and would number
  // millions).
  if (block_size_m < kVerticesPerFinestWavelength * vertex_spacing_m) {
    throw ErrorAt(OptionName(section, "block_size_m"), " = ", block_size_m,
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
    throw ErrorAt(OptionName(section, "height_m"), " = ", height_m,
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

World MakeBreakwater(const BreakwaterOptions& options,
                     SplitMix64Stream& random) {
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

}  // namespace uw::sim
