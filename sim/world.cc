#include "sim/world.h"

#include <nlohmann/json.hpp>

#include "common/util/error.h"
#include "common/util/json_fields.h"
#include "common/util/random.h"

namespace uw::sim {
namespace {

Eigen::AlignedBox3d Bounds(const TriangleMesh& mesh) {
  Eigen::AlignedBox3d bounds;
  for (const Eigen::Vector3d& vertex : mesh.vertices) bounds.extend(vertex);
  return bounds;
}

// JSON: one object per section, with the field names of the options
// structs; sections nest as the structs do.

nlohmann::json ReliefJson(const ReliefOptions& o) {
  return {{"undulation_amplitude_m", o.undulation_amplitude_m},
          {"undulation_wavelength_m", o.undulation_wavelength_m},
          {"roughness_amplitude_m", o.roughness_amplitude_m},
          {"roughness_wavelength_m", o.roughness_wavelength_m}};
}

void ReadRelief(JsonFields& fields, ReliefOptions* o) {
  fields.Read("undulation_amplitude_m", &o->undulation_amplitude_m);
  fields.Read("undulation_wavelength_m", &o->undulation_wavelength_m);
  fields.Read("roughness_amplitude_m", &o->roughness_amplitude_m);
  fields.Read("roughness_wavelength_m", &o->roughness_wavelength_m);
}

nlohmann::json RocksJson(const RockOptions& o) {
  return {{"count", o.count},
          {"min_diameter_m", o.min_diameter_m},
          {"max_diameter_m", o.max_diameter_m}};
}

void ReadRocks(JsonFields& fields, RockOptions* o) {
  fields.Read("count", &o->count);
  fields.Read("min_diameter_m", &o->min_diameter_m);
  fields.Read("max_diameter_m", &o->max_diameter_m);
}

// A nested section read by `read`(fields, options).
template <typename Options>
void ReadSection(JsonFields& fields, const char* key, Options* options,
                 void (*read)(JsonFields&, Options*)) {
  fields.Section(key, [&](JsonFields& section) { read(section, options); });
}

nlohmann::json SeafloorJson(const SeafloorOptions& o) {
  return {{"length_m", o.length_m},
          {"width_m", o.width_m},
          {"vertex_spacing_m", o.vertex_spacing_m},
          {"relief", ReliefJson(o.relief)},
          {"rocks", RocksJson(o.rocks)}};
}

void ReadSeafloor(JsonFields& fields, SeafloorOptions* o) {
  fields.Read("length_m", &o->length_m);
  fields.Read("width_m", &o->width_m);
  fields.Read("vertex_spacing_m", &o->vertex_spacing_m);
  ReadSection(fields, "relief", &o->relief, ReadRelief);
  ReadSection(fields, "rocks", &o->rocks, ReadRocks);
}

nlohmann::json VentJson(const VentOptions& o) {
  return {{"ground_size_m", o.ground_size_m},
          {"ground_vertex_spacing_m", o.ground_vertex_spacing_m},
          {"ground_relief", ReliefJson(o.ground_relief)},
          {"ground_rocks", RocksJson(o.ground_rocks)},
          {"mound_height_m", o.mound_height_m},
          {"mound_radius_m", o.mound_radius_m},
          {"chimney_height_m", o.chimney_height_m},
          {"chimney_base_radius_m", o.chimney_base_radius_m},
          {"chimney_top_radius_m", o.chimney_top_radius_m},
          {"chimney_radius_noise", o.chimney_radius_noise},
          {"chimney_lean_m", o.chimney_lean_m},
          {"flange_count", o.flange_count},
          {"flange_min_width_m", o.flange_min_width_m},
          {"flange_max_width_m", o.flange_max_width_m},
          {"chimney_vertex_spacing_m", o.chimney_vertex_spacing_m}};
}

void ReadVent(JsonFields& fields, VentOptions* o) {
  fields.Read("ground_size_m", &o->ground_size_m);
  fields.Read("ground_vertex_spacing_m", &o->ground_vertex_spacing_m);
  ReadSection(fields, "ground_relief", &o->ground_relief, ReadRelief);
  ReadSection(fields, "ground_rocks", &o->ground_rocks, ReadRocks);
  fields.Read("mound_height_m", &o->mound_height_m);
  fields.Read("mound_radius_m", &o->mound_radius_m);
  fields.Read("chimney_height_m", &o->chimney_height_m);
  fields.Read("chimney_base_radius_m", &o->chimney_base_radius_m);
  fields.Read("chimney_top_radius_m", &o->chimney_top_radius_m);
  fields.Read("chimney_radius_noise", &o->chimney_radius_noise);
  fields.Read("chimney_lean_m", &o->chimney_lean_m);
  fields.Read("flange_count", &o->flange_count);
  fields.Read("flange_min_width_m", &o->flange_min_width_m);
  fields.Read("flange_max_width_m", &o->flange_max_width_m);
  fields.Read("chimney_vertex_spacing_m", &o->chimney_vertex_spacing_m);
}

nlohmann::json ScarpJson(const ScarpOptions& o) {
  return {{"length_m", o.length_m},
          {"height_m", o.height_m},
          {"dip_deg", o.dip_deg},
          {"foot_width_m", o.foot_width_m},
          {"crest_width_m", o.crest_width_m},
          {"vertex_spacing_m", o.vertex_spacing_m},
          {"relief", ReliefJson(o.relief)},
          {"meander_amplitude_m", o.meander_amplitude_m},
          {"meander_wavelength_m", o.meander_wavelength_m}};
}

void ReadScarp(JsonFields& fields, ScarpOptions* o) {
  fields.Read("length_m", &o->length_m);
  fields.Read("height_m", &o->height_m);
  fields.Read("dip_deg", &o->dip_deg);
  fields.Read("foot_width_m", &o->foot_width_m);
  fields.Read("crest_width_m", &o->crest_width_m);
  fields.Read("vertex_spacing_m", &o->vertex_spacing_m);
  ReadSection(fields, "relief", &o->relief, ReadRelief);
  fields.Read("meander_amplitude_m", &o->meander_amplitude_m);
  fields.Read("meander_wavelength_m", &o->meander_wavelength_m);
}

nlohmann::json BreakwaterJson(const BreakwaterOptions& o) {
  return {{"length_m", o.length_m},
          {"height_m", o.height_m},
          {"crest_width_m", o.crest_width_m},
          {"slope_deg", o.slope_deg},
          {"apron_width_m", o.apron_width_m},
          {"vertex_spacing_m", o.vertex_spacing_m},
          {"relief", ReliefJson(o.relief)},
          {"rocks", RocksJson(o.rocks)},
          {"block_size_m", o.block_size_m},
          {"block_size_variation", o.block_size_variation},
          {"block_layers", o.block_layers},
          {"block_tilt_deg", o.block_tilt_deg},
          {"block_roughness_m", o.block_roughness_m}};
}

void ReadBreakwater(JsonFields& fields, BreakwaterOptions* o) {
  fields.Read("length_m", &o->length_m);
  fields.Read("height_m", &o->height_m);
  fields.Read("crest_width_m", &o->crest_width_m);
  fields.Read("slope_deg", &o->slope_deg);
  fields.Read("apron_width_m", &o->apron_width_m);
  fields.Read("vertex_spacing_m", &o->vertex_spacing_m);
  ReadSection(fields, "relief", &o->relief, ReadRelief);
  ReadSection(fields, "rocks", &o->rocks, ReadRocks);
  fields.Read("block_size_m", &o->block_size_m);
  fields.Read("block_size_variation", &o->block_size_variation);
  fields.Read("block_layers", &o->block_layers);
  fields.Read("block_tilt_deg", &o->block_tilt_deg);
  fields.Read("block_roughness_m", &o->block_roughness_m);
}

nlohmann::json CanyonJson(const CanyonOptions& o) {
  return {{"length_m", o.length_m},
          {"width_m", o.width_m},
          {"floor_width_m", o.floor_width_m},
          {"wall_height_m", o.wall_height_m},
          {"wall_height_variation_m", o.wall_height_variation_m},
          {"wall_slope_deg", o.wall_slope_deg},
          {"meander_amplitude_m", o.meander_amplitude_m},
          {"meander_wavelength_m", o.meander_wavelength_m},
          {"wall_relief_m", o.wall_relief_m},
          {"wall_relief_wavelength_m", o.wall_relief_wavelength_m},
          {"vertex_spacing_m", o.vertex_spacing_m},
          {"relief", ReliefJson(o.relief)},
          {"rocks", RocksJson(o.rocks)}};
}

void ReadCanyon(JsonFields& fields, CanyonOptions* o) {
  fields.Read("length_m", &o->length_m);
  fields.Read("width_m", &o->width_m);
  fields.Read("floor_width_m", &o->floor_width_m);
  fields.Read("wall_height_m", &o->wall_height_m);
  fields.Read("wall_height_variation_m", &o->wall_height_variation_m);
  fields.Read("wall_slope_deg", &o->wall_slope_deg);
  fields.Read("meander_amplitude_m", &o->meander_amplitude_m);
  fields.Read("meander_wavelength_m", &o->meander_wavelength_m);
  fields.Read("wall_relief_m", &o->wall_relief_m);
  fields.Read("wall_relief_wavelength_m", &o->wall_relief_wavelength_m);
  fields.Read("vertex_spacing_m", &o->vertex_spacing_m);
  ReadSection(fields, "relief", &o->relief, ReadRelief);
  ReadSection(fields, "rocks", &o->rocks, ReadRocks);
}

nlohmann::json TextureJson(const ProceduralTextureOptions& o) {
  return {{"grain_wavelength_m", o.grain_wavelength_m},
          {"grain_octaves", o.grain_octaves},
          {"grain_contrast", o.grain_contrast},
          {"patch_wavelength_m", o.patch_wavelength_m},
          {"region_wavelength_m", o.region_wavelength_m},
          {"patch_contrast", o.patch_contrast},
          {"sediment_cover", o.sediment_cover},
          {"rock_albedo", o.rock_albedo},
          {"sediment_albedo", o.sediment_albedo},
          {"stain_albedo", o.stain_albedo},
          {"stain_strength", o.stain_strength}};
}

void ReadTexture(JsonFields& fields, ProceduralTextureOptions* o) {
  fields.Read("grain_wavelength_m", &o->grain_wavelength_m);
  fields.Read("grain_octaves", &o->grain_octaves);
  fields.Read("grain_contrast", &o->grain_contrast);
  fields.Read("patch_wavelength_m", &o->patch_wavelength_m);
  fields.Read("region_wavelength_m", &o->region_wavelength_m);
  fields.Read("patch_contrast", &o->patch_contrast);
  fields.Read("sediment_cover", &o->sediment_cover);
  fields.Read("rock_albedo", &o->rock_albedo);
  fields.Read("sediment_albedo", &o->sediment_albedo);
  fields.Read("stain_albedo", &o->stain_albedo);
  fields.Read("stain_strength", &o->stain_strength);
}

// The top-level sections are named "world options: <section>", as the
// checks name their fields (sim/worlds/option_checks.h).
template <typename Options>
void ReadWorldSection(JsonFields& fields, const char* key, Options* options,
                      void (*read)(JsonFields&, Options*)) {
  fields.Section(key, std::string("world options: ") + key,
                 [&](JsonFields& section) { read(section, options); });
}

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

void WorldOptions::Check() const {
  seafloor.Check();
  vent.Check();
  scarp.Check();
  breakwater.Check();
  canyon.Check();
  texture.Check();
}

void to_json(nlohmann::json& json, const WorldOptions& options) {
  json = {{"seafloor", SeafloorJson(options.seafloor)},
          {"vent", VentJson(options.vent)},
          {"scarp", ScarpJson(options.scarp)},
          {"breakwater", BreakwaterJson(options.breakwater)},
          {"canyon", CanyonJson(options.canyon)},
          {"texture", TextureJson(options.texture)}};
}

void from_json(const nlohmann::json& json, WorldOptions& options) {
  JsonFields fields(json, "world options");
  ReadWorldSection(fields, "seafloor", &options.seafloor, ReadSeafloor);
  ReadWorldSection(fields, "vent", &options.vent, ReadVent);
  ReadWorldSection(fields, "scarp", &options.scarp, ReadScarp);
  ReadWorldSection(fields, "breakwater", &options.breakwater, ReadBreakwater);
  ReadWorldSection(fields, "canyon", &options.canyon, ReadCanyon);
  ReadWorldSection(fields, "texture", &options.texture, ReadTexture);
  fields.RejectUnknown();
}

World MakeWorld(const WorldKind kind, const WorldOptions& options,
                const uint64_t seed) {
  options.Check();
  // Independent streams for geometry and texture: changing a geometry
  // parameter leaves the texture as it was.
  SplitMix64Stream seeds(seed);
  SplitMix64Stream geometry(seeds.Next());
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
