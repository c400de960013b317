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
//
// Each kind has its options and its maker in sim/worlds/ (seafloor.h,
// vent.h, scarp.h, breakwater.h, canyon.h), built from noise, relief,
// rocks and height grids there.
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
#include "sim/worlds/breakwater.h"
#include "sim/worlds/canyon.h"
#include "sim/worlds/scarp.h"
#include "sim/worlds/seafloor.h"
#include "sim/worlds/vent.h"

namespace uw::sim {

enum class WorldKind { kSeafloor, kVent, kScarp, kBreakwater, kCanyon };
// "seafloor", "vent", "scarp", "breakwater", "canyon"
std::string WorldKindName(WorldKind kind);
// Throws uw::Error listing the valid names.
WorldKind WorldKindFromName(const std::string& name);

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
  // "world options: vent.flange_count = -1: must be in [0, 20]".
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
