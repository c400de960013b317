#include "sim/procedural_texture.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <utility>

#include <Eigen/Geometry>

#include "common/util/error.h"
#include "common/util/random.h"

namespace uw::sim {
namespace {

using internal::NoiseLanes;

// GCC/Clang vector extensions: plain IEEE operations lane by lane, so every
// instruction set computes the same bits as scalar code would.
using Floats =
    float __attribute__((vector_size(4 * NoiseLanes::kLanes), may_alias));
using Ints =
    int32_t __attribute__((vector_size(4 * NoiseLanes::kLanes), may_alias));
using Uints =
    uint32_t __attribute__((vector_size(4 * NoiseLanes::kLanes), may_alias));

constexpr int kGrainLane = 0;
constexpr int kMaxGrainOctaves = 4;
constexpr int kPatchLane = 4;
constexpr int kRegionLane = 6;
constexpr int kBandOctaves = 2;

// Turns the user's seed into per-octave seeds and rotations.
using SeedStream = SplitMix64Stream;

// The lanes are 32-byte aligned arrays; may_alias above makes reading them
// as vectors well defined.
template <typename Vector, typename Scalar>
inline const Vector& AsVector(const Scalar (&lanes)[NoiseLanes::kLanes]) {
  return *reinterpret_cast<const Vector*>(lanes);
}

// The helpers below pass SIMD vectors by reference: by value, their ABI
// would differ between the AVX2 and the default clone of WeightedNoise.

// A full-avalanche 32-bit mix (Wellons' "lowbias32"). Each lattice axis
// hashes its integer coordinate with it under its own seed, so the
// combined hash has no period shorter than 2^32 cells in any direction (a
// linear combination such as ix*P1 + iy*P2 + iz*P3 would repeat along short
// lattice vectors).
inline void Avalanche(Uints& h) {
  h ^= h >> 16;
  h *= 0x7feb352du;
  h ^= h >> 15;
  h *= 0x846ca68bu;
  h ^= h >> 16;
}

// Values in [-1, 1) of the eight lattice corners [x][y][z] whose per-axis
// hashes are given; the multiply breaks the XOR's linearity between
// neighbouring corners.
inline void CornerValues(const Uints (&hx)[2], const Uints (&hy)[2],
                         const Uints (&hz)[2], Floats (&value)[2][2][2]) {
  for (int i = 0; i < 2; ++i) {
    for (int j = 0; j < 2; ++j) {
      for (int k = 0; k < 2; ++k) {
        Uints h = (hx[i] ^ hy[j] ^ hz[k]) * 0x9e3779b1u;
        h ^= h >> 15;
        value[i][j][k] = __builtin_convertvector((Ints)h, Floats) * 0x1.0p-31f;
      }
    }
  }
}

// C2 interpolation weight: no creases along lattice planes in the image
// gradients SIFT computes.
inline void Fade(Floats& t) {
  t = t * t * t * (t * (t * 6.0f - 15.0f) + 10.0f);
}

inline void LerpInto(Floats& a, const Floats& b, const Floats& t) {
  a += t * (b - a);
}

// Trilinear value noise of all eight octaves at one point, times their
// weights. Cloned for AVX2 where available; both clones do the same IEEE
// operations (no FMA), so results do not depend on the machine's SIMD.
__attribute__((target_clones("avx2", "default"))) void WeightedNoise(
    const NoiseLanes& lanes, float x, float y, float z,
    float (&out)[NoiseLanes::kLanes]) {
  const auto& m = lanes.lattice_from_world;
  Uints hash[3][2];
  Floats fade[3];
  for (int axis = 0; axis < 3; ++axis) {
    const Floats lattice = AsVector<Floats>(m[3 * axis]) * x +
                           AsVector<Floats>(m[3 * axis + 1]) * y +
                           AsVector<Floats>(m[3 * axis + 2]) * z +
                           AsVector<Floats>(lanes.offset[axis]);
    // Floor by truncation and a correction for negative values: std::floor
    // is a library call without SSE4.1.
    Ints cell = __builtin_convertvector(lattice, Ints);
    cell += lattice < __builtin_convertvector(cell, Floats);  // true is -1
    fade[axis] = lattice - __builtin_convertvector(cell, Floats);
    Fade(fade[axis]);
    hash[axis][0] = AsVector<Uints>(lanes.axis_seed[axis]) + (Uints)cell;
    hash[axis][1] = hash[axis][0] + 1u;
    Avalanche(hash[axis][0]);
    Avalanche(hash[axis][1]);
  }
  Floats value[2][2][2];
  CornerValues(hash[0], hash[1], hash[2], value);
  for (int j = 0; j < 2; ++j) {
    for (int k = 0; k < 2; ++k)
      LerpInto(value[0][j][k], value[1][j][k], fade[0]);
  }
  for (int k = 0; k < 2; ++k) LerpInto(value[0][0][k], value[0][1][k], fade[1]);
  LerpInto(value[0][0][0], value[0][0][1], fade[2]);
  const Floats weighted = value[0][0][0] * AsVector<Floats>(lanes.weight);
  std::memcpy(out, &weighted, sizeof(out));
}

// Standard deviation of one value-noise octave: corners uniform in [-1, 1]
// (variance 1/3) blended trilinearly with the quintic fade w give variance
// (1/3) (2 E[w^2])^3 with E[w^2] = 0.39177 over a cell. Dividing by it
// gives every band unit variance whatever its octave count.
constexpr float kOctaveStdDev = 0.40f;

// The sediment field is region + kPatchInSediment * patch - kSteepPenalty *
// steepness: ragged dm-scale edges on m-scale areas, and little sediment on
// steep surfaces. Steepness ramps from 0 on slopes gentler than ~40 deg
// (normal.z > kGentleUp) to 1 beyond ~70 deg (normal.z < kSteepUp), so that
// it is constant on ordinary floors and walls: a renderer passes flat
// per-triangle normals, and any dependence on small normal changes would
// print the triangles onto the texture.
constexpr float kPatchInSediment = 0.35f;
constexpr float kSteepPenalty = 2.5f;
constexpr float kGentleUp = 0.75f;
constexpr float kSteepUp = 0.35f;

// Threshold on the sediment field above which a level floor is sediment
// with probability `cover`: both bands are close to unit normal, so the
// field is normal with standard deviation sqrt(1 + kPatchInSediment^2).
float SedimentThreshold(double cover) {
  const double sigma = std::sqrt(1.0 + kPatchInSediment * kPatchInSediment);
  // Bisection on the normal upper tail probability 0.5 * erfc(z / sqrt 2).
  double low = -8.0, high = 8.0;
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (low + high);
    if (0.5 * std::erfc(mid / M_SQRT2) > cover) {
      low = mid;
    } else {
      high = mid;
    }
  }
  return static_cast<float>(sigma * 0.5 * (low + high));
}

// Four floats clamped lane by lane without branches: std::clamp and
// std::min/max on scalars compile to branches here, which random texture
// values mispredict.
using Float4 = float __attribute__((vector_size(16)));

inline Float4 Clamp(Float4 x, Float4 low, Float4 high) {
  x = x < low ? low : x;
  return x > high ? high : x;
}

inline float SmoothStep01(float t) { return t * t * (3.0f - 2.0f * t); }

inline Float4 Rgb(const Eigen::Vector3f& rgb) {
  return Float4{rgb.x(), rgb.y(), rgb.z(), 0.0f};
}

Eigen::Vector3f Colour(const std::array<double, 3>& rgb) {
  return Eigen::Vector3d(rgb[0], rgb[1], rgb[2]).cast<float>();
}

void CheckFraction(double value, const char* name) {
  if (!(value >= 0.0 && value <= 1.0)) {
    throw ErrorAt("ProceduralTextureOptions.", name, " = ", value,
                  ": must be in [0, 1]");
  }
}

void CheckWavelength(double value, const char* name) {
  if (!(value > 0.0 && std::isfinite(value))) {
    throw ErrorAt("ProceduralTextureOptions.", name, " = ", value,
                  ": must be a positive wavelength in metres");
  }
}

}  // namespace

void ProceduralTextureOptions::Check() const {
  CheckWavelength(grain_wavelength_m, "grain_wavelength_m");
  CheckWavelength(patch_wavelength_m, "patch_wavelength_m");
  CheckWavelength(region_wavelength_m, "region_wavelength_m");
  if (grain_octaves < 1 || grain_octaves > kMaxGrainOctaves) {
    throw ErrorAt("ProceduralTextureOptions.grain_octaves = ", grain_octaves,
                  ": must be in [1, ", kMaxGrainOctaves, "]");
  }
  CheckFraction(grain_contrast, "grain_contrast");
  CheckFraction(patch_contrast, "patch_contrast");
  CheckFraction(sediment_cover, "sediment_cover");
  CheckFraction(stain_strength, "stain_strength");
  const std::pair<const char*, const std::array<double, 3>*> colours[] = {
      {"rock_albedo", &rock_albedo},
      {"sediment_albedo", &sediment_albedo},
      {"stain_albedo", &stain_albedo}};
  for (const auto& [name, rgb] : colours) {
    for (const double channel : *rgb) {
      if (!(channel >= 0.0 && channel <= 1.0)) {
        throw ErrorAt("ProceduralTextureOptions.", name,
                      ": every channel must be in [0, 1], got ", channel);
      }
    }
  }
}

ProceduralTexture::ProceduralTexture(const ProceduralTextureOptions& options,
                                     const uint64_t seed)
    : options_(options), lanes_() {
  options_.Check();
  rock_ = Colour(options_.rock_albedo);
  sediment_ = Colour(options_.sediment_albedo);
  stain_ = Colour(options_.stain_albedo);
  sediment_threshold_ = SedimentThreshold(options_.sediment_cover);
  grain_contrast_ = static_cast<float>(options_.grain_contrast);
  patch_contrast_ = static_cast<float>(options_.patch_contrast);
  stain_strength_ = static_cast<float>(options_.stain_strength);

  SeedStream stream(seed);
  const auto set_lane = [&](int lane, double wavelength, float weight) {
    // A uniformly random rotation (Shoemake's method), so that the lattice
    // axes of different octaves never line up.
    const double u1 = stream.Uniform(), u2 = stream.Uniform(),
                 u3 = stream.Uniform();
    const Eigen::Quaterniond rotation(
        std::sqrt(u1) * std::cos(2.0 * M_PI * u3),
        std::sqrt(1.0 - u1) * std::sin(2.0 * M_PI * u2),
        std::sqrt(1.0 - u1) * std::cos(2.0 * M_PI * u2),
        std::sqrt(u1) * std::sin(2.0 * M_PI * u3));
    const Eigen::Matrix3d lattice_from_world =
        rotation.toRotationMatrix() / wavelength;
    for (int row = 0; row < 3; ++row) {
      for (int col = 0; col < 3; ++col) {
        lanes_.lattice_from_world[3 * row + col][lane] =
            static_cast<float>(lattice_from_world(row, col));
      }
      lanes_.offset[row][lane] = static_cast<float>(stream.Uniform());
      lanes_.axis_seed[row][lane] = static_cast<uint32_t>(stream.Next() >> 32);
    }
    lanes_.weight[lane] = weight;
  };
  const auto normalise_band = [this](int first_lane, int count) {
    float sum_squares = 0.0f;
    for (int i = first_lane; i < first_lane + count; ++i) {
      sum_squares += lanes_.weight[i] * lanes_.weight[i];
    }
    const float scale = 1.0f / (kOctaveStdDev * std::sqrt(sum_squares));
    for (int i = first_lane; i < first_lane + count; ++i) {
      lanes_.weight[i] *= scale;
    }
  };
  // Grain octaves keep most of their amplitude towards the finest one: the
  // cm-scale contrast is what SIFT needs. Unused grain lanes weigh nothing.
  for (int i = 0; i < kMaxGrainOctaves; ++i) {
    set_lane(kGrainLane + i, options_.grain_wavelength_m * (1 << i),
             i < options_.grain_octaves ? std::pow(1.25f, i) : 0.0f);
  }
  normalise_band(kGrainLane, options_.grain_octaves);
  for (int i = 0; i < kBandOctaves; ++i) {
    set_lane(kPatchLane + i, options_.patch_wavelength_m / (1 << i),
             std::pow(0.5f, i));
    set_lane(kRegionLane + i, options_.region_wavelength_m / (1 << i),
             std::pow(0.5f, i));
  }
  normalise_band(kPatchLane, kBandOctaves);
  normalise_band(kRegionLane, kBandOctaves);
}

Eigen::Vector3f ProceduralTexture::Albedo(
    const Eigen::Vector3d& point_in_world,
    const Eigen::Vector3d& normal_in_world) const {
  float noise[NoiseLanes::kLanes];
  WeightedNoise(lanes_, static_cast<float>(point_in_world.x()),
                static_cast<float>(point_in_world.y()),
                static_cast<float>(point_in_world.z()), noise);
  const float grain = (noise[0] + noise[1]) + (noise[2] + noise[3]);
  const float patch = noise[kPatchLane] + noise[kPatchLane + 1];
  const float region = noise[kRegionLane] + noise[kRegionLane + 1];

  // Every shaping curve below needs its input clamped; each Clamp does four
  // at once.
  const float up = static_cast<float>(normal_in_world.z());
  const Float4 shaped =
      Clamp(Float4{0.65f * grain, (kGentleUp - up) / (kGentleUp - kSteepUp),
                   patch - 0.4f, 0.5f * patch},
            Float4{-1.0f, 0.0f, 0.0f, -1.0f}, Float4{1.0f, 1.0f, 1.0f, 1.0f});
  const float steepness = SmoothStep01(shaped[1]);
  const float sediment_field =
      region + kPatchInSediment * patch - kSteepPenalty * steepness;
  const float sediment = SmoothStep01(
      Clamp(Float4{2.0f * (sediment_field - sediment_threshold_) + 0.5f},
            Float4{}, Float4{} + 1.0f)[0]);
  // An S-curve flattens the grain into blobs with sharp rims: pebbles and
  // pits rather than fog, which is what makes SIFT keypoints stable.
  const float pebbles = shaped[0] * (1.5f - 0.5f * shaped[0] * shaped[0]);
  const float stain = stain_strength_ * SmoothStep01(shaped[2]);

  Float4 colour = Rgb(rock_) + sediment * (Rgb(sediment_) - Rgb(rock_));
  colour += stain * (Rgb(stain_) - colour);
  // Sediment is smoother than rock but keeps enough grain to be matched.
  const float brightness =
      (1.0f + grain_contrast_ * pebbles * (1.0f - 0.35f * sediment)) *
      (1.0f + patch_contrast_ * shaped[3]);
  const Float4 albedo = Clamp(brightness * colour, Float4{}, Float4{} + 1.0f);
  return Eigen::Vector3f(albedo[0], albedo[1], albedo[2]);
}

}  // namespace uw::sim
