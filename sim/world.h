// Synthetic worlds for uwsim: triangle meshes in metres (world frame x east,
// y north, z up) with a procedural albedo, each deterministic from a seed.
//
//  seafloor  rough fBm relief with boulders, z up
//  vent      a ~10 m hydrothermal chimney with overhanging flanges on a
//            rough mound, like the thesis's Lucky Strike model
//  scarp     a ~300 m long, ~10 m high fault wall dipping ~82 deg, facing
//            -y, with a strip of seafloor at its foot, like AUTT28
//  breakwater  a ~40 m long, ~5 m high rubble-mound breakwater along x,
//            armoured with tilted rounded-cube blocks, seaward side -y,
//            like the thesis's Sant Feliu harbour and UWSim scenes
//  canyon    a ~60 m long winding canyon along x: a 6-10 m wide rocky
//            floor between two steep rough walls 8-15 m high, open at both
//            ends, like the thesis's Sant Feliu canyon
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <nlohmann/json_fwd.hpp>

#include "common/mesh/mesh.h"
#include "sim/procedural_texture.h"
#include "sim/texture.h"

namespace uw::sim {

enum class WorldKind { kSeafloor, kVent, kScarp, kBreakwater, kCanyon };
// "seafloor", "vent", "scarp", "breakwater", "canyon"
std::string WorldKindName(WorldKind kind);
// Throws uw::Error listing the valid names.
WorldKind WorldKindFromName(const std::string& name);

// Relief as two bands of fractal (fBm) gradient noise: metre-scale
// undulation and dm-scale roughness. Each band's octaves halve in
// wavelength and amplitude down to four vertex spacings (finer relief would
// not be resolved by the mesh; the texture carries it). Amplitudes are the
// bands' standard deviations.
struct ReliefOptions {
  double undulation_amplitude_m = 0.3;
  double undulation_wavelength_m = 8.0;
  double roughness_amplitude_m = 0.04;
  double roughness_wavelength_m = 0.6;

  void Check(const std::string& where) const;
};

// Boulders: rounded, irregular, partly buried bumps merged into a
// heightfield. Diameters follow a power law (many small, few large).
struct RockOptions {
  int count = 40;
  double min_diameter_m = 0.2;
  double max_diameter_m = 1.0;

  void Check(const std::string& where) const;
};

struct SeafloorOptions {
  double length_m = 24.0;  // along x
  double width_m = 16.0;   // along y
  // 2.5 cm: relief stays smooth at 1-3 m altitude with ~1.2 M triangles.
  double vertex_spacing_m = 0.025;
  ReliefOptions relief;
  RockOptions rocks;

  void Check() const;
};

struct VentOptions {
  double ground_size_m = 30.0;  // square, centred on the chimney
  double ground_vertex_spacing_m = 0.05;
  ReliefOptions ground_relief = {0.25, 8.0, 0.05, 0.6};
  RockOptions ground_rocks = {30, 0.2, 1.2};
  // A sulfide debris mound under the chimney (Gaussian profile).
  double mound_height_m = 1.5;
  double mound_radius_m = 7.0;
  double chimney_height_m = 10.0;  // above the ground at its centre
  double chimney_base_radius_m = 2.8;
  double chimney_top_radius_m = 1.4;
  // Relative standard deviation of the radius with angle and height.
  double chimney_radius_noise = 0.12;
  // Standard deviation of the chimney axis' horizontal wander (m).
  double chimney_lean_m = 0.3;
  // Flanges: ledges whose radius exceeds the body below them (overhangs),
  // between 30 % and 85 % of the height, each covering part of the
  // circumference.
  int flange_count = 3;
  double flange_min_width_m = 0.5;
  double flange_max_width_m = 1.2;
  double chimney_vertex_spacing_m = 0.03;

  void Check() const;
};

struct ScarpOptions {
  double length_m = 300.0;  // along x
  double height_m = 10.0;
  double dip_deg = 82.0;  // angle of the wall from horizontal, (45, 90]
  // Flat seafloor strip in front of the wall's foot and behind its crest.
  double foot_width_m = 6.0;
  double crest_width_m = 3.0;
  // 10 cm: ~1.2 M triangles for the default 300 m; finer detail is texture.
  double vertex_spacing_m = 0.1;
  ReliefOptions relief = {0.35, 6.0, 0.06, 0.8};
  // Horizontal wander of the wall's trace (standard deviation, wavelength).
  double meander_amplitude_m = 1.5;
  double meander_wavelength_m = 60.0;

  void Check() const;
};

// A rubble mound: a trapezoidal core covered with block_layers layers of
// armour blocks, on a rough seafloor. The design profile (the mean outer
// surface of the armour) rises from the seafloor (z = 0) at slope_deg to a
// crest height_m high and crest_width_m wide; its crest runs length_m along
// x, and both ends (roundheads) slope down like the sides. Seaward is -y.
struct BreakwaterOptions {
  double length_m = 40.0;  // of the crest, along x
  double height_m = 5.0;
  double crest_width_m = 4.0;
  double slope_deg = 33.0;  // 1:1.5, typical of armoured slopes
  // Seafloor around the toe of the design profile.
  double apron_width_m = 6.0;
  // 6 cm: ~1.2 M triangles; a block spans ~27 vertices.
  double vertex_spacing_m = 0.06;
  ReliefOptions relief = {0.15, 8.0, 0.04, 0.6};  // seafloor and core
  RockOptions rocks = {60, 0.3, 1.2};  // on the seafloor, off the mound
  // Armour: rounded cubes (superellipsoids of exponent 6) of edge
  // block_size_m, each edge scaled by up to 1 +- block_size_variation and
  // sheared a little, laid on jittered grids, one per layer, and tilted by
  // up to block_tilt_deg from the slope. The surface is a heightfield (no
  // hollows under blocks) whose slopes are capped at 72 deg, so block
  // sides become skirts a few vertices wide rather than one-cell cliffs.
  double block_size_m = 1.6;
  double block_size_variation = 0.2;
  int block_layers = 2;
  double block_tilt_deg = 20.0;
  // Standard deviation of the blocks' surface roughness (armourstone).
  double block_roughness_m = 0.03;

  void Check() const;
};

// A canyon winding along x: its axis y = c(x) meanders within
// +-meander_amplitude_m. Across it: a floor floor_width_m wide (at z = 0),
// walls rising at wall_slope_deg with rounded foot and rim, and a rim
// plateau out to y = +-width_m / 2. Each wall's height varies along the
// canyon within wall_height_m +- wall_height_variation_m; the walls'
// horizontal position wanders by up to wall_relief_m (buttresses, gullies,
// ledges). Rocks lie on the floor only.
struct CanyonOptions {
  double length_m = 60.0;  // along x
  double width_m = 36.0;   // along y, rims included
  double floor_width_m = 8.0;
  double wall_height_m = 11.0;
  double wall_height_variation_m = 2.5;
  double wall_slope_deg = 65.0;
  double meander_amplitude_m = 2.5;
  double meander_wavelength_m = 36.0;
  double wall_relief_m = 0.8;
  double wall_relief_wavelength_m = 4.0;
  // 6 cm: ~1.2 M triangles; walls are heightfield cells stretched ~2.4x.
  double vertex_spacing_m = 0.06;
  ReliefOptions relief = {0.2, 6.0, 0.05, 0.6};
  RockOptions rocks = {40, 0.3, 1.6};

  void Check() const;
};

// Every parameter of every kind of world; MakeWorld uses the section of
// the requested kind and the texture.
struct WorldOptions {
  SeafloorOptions seafloor;
  VentOptions vent;
  ScarpOptions scarp;
  BreakwaterOptions breakwater;
  CanyonOptions canyon;
  ProceduralTextureOptions texture;

  // Throws uw::Error naming the offending field, e.g.
  // "world options: vent.flange_count = -1: must be >= 0".
  void Check() const;
};

// JSON with one object per section and the field names above. Reading keeps
// the current value of every field absent from the JSON; unknown keys and
// values of the wrong type are uw::Errors naming the key.
void to_json(nlohmann::json& json, const WorldOptions& options);
void from_json(const nlohmann::json& json, WorldOptions& options);

struct World {
  std::string name;
  TriangleMesh mesh;
  std::shared_ptr<const Texture> texture;
  Eigen::AlignedBox3d bounds;
  // Where surveys fly: the plane through survey_origin with unit normal
  // survey_normal pointing into the water, unit survey_along its long
  // in-plane axis, and the surveyable extent along and across it (m).
  //  seafloor: the mean height of the floor, +z, +x, its full size;
  //  vent: the top of the chimney (so that a survey at a stand-off above
  //        the plane clears it), +z, +x, the chimney's footprint plus 3 m
  //        on each side;
  //  scarp: the wall's mean plane at mid-height, normal -y tilted up by
  //         90 deg - dip, +x, its length and slant height;
  //  breakwater: the seaward (-y) face of the design profile at mid-height,
  //         normal -y tilted up by 90 deg - slope, +x, the crest length
  //         and the slant height from toe to crest;
  //  canyon: the floor: the mean height of the strip below, +z, +x, the
  //         canyon's length, and the widest strip parallel to x that lies
  //         on the floor all along (floor width - 2 wall_relief - the
  //         axis' range in y; at least 1 m), centred in that range.
  Eigen::Vector3d survey_origin;
  Eigen::Vector3d survey_normal;
  Eigen::Vector3d survey_along;
  double survey_length = 0.0;
  double survey_width = 0.0;
};

// Checks the options; the same kind, options and seed give the same mesh
// and texture bit for bit.
World MakeWorld(WorldKind kind, const WorldOptions& options, uint64_t seed);

}  // namespace uw::sim
