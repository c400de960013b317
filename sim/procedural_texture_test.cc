#include "sim/procedural_texture.h"

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "common/util/error.h"

namespace uw::sim {
namespace {

const Eigen::Vector3d kUp = Eigen::Vector3d::UnitZ();

float Luminance(const Eigen::Vector3f& rgb) {
  return 0.2126f * rgb.x() + 0.7152f * rgb.y() + 0.0722f * rgb.z();
}

bool SameBits(const Eigen::Vector3f& a, const Eigen::Vector3f& b) {
  return std::memcmp(a.data(), b.data(), sizeof(float) * 3) == 0;
}

std::vector<Eigen::Vector3d> RandomPoints(int count, double extent,
                                          uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uniform(-extent, extent);
  std::vector<Eigen::Vector3d> points(count);
  for (Eigen::Vector3d& point : points) {
    point = Eigen::Vector3d(uniform(rng), uniform(rng), uniform(rng));
  }
  return points;
}

// Luminance on a square grid of n x n samples `step` apart, spanned by the
// unit vectors a and b from `origin`.
std::vector<float> Patch(const ProceduralTexture& texture,
                         const Eigen::Vector3d& origin,
                         const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                         const Eigen::Vector3d& normal, int n, double step) {
  std::vector<float> values;
  values.reserve(n * n);
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      values.push_back(
          Luminance(texture.Albedo(origin + step * (i * a + j * b), normal)));
    }
  }
  return values;
}

double Correlation(const std::vector<float>& x, const std::vector<float>& y) {
  double mx = 0, my = 0;
  for (size_t i = 0; i < x.size(); ++i) {
    mx += x[i];
    my += y[i];
  }
  mx /= x.size();
  my /= y.size();
  double sxy = 0, sxx = 0, syy = 0;
  for (size_t i = 0; i < x.size(); ++i) {
    sxy += (x[i] - mx) * (y[i] - my);
    sxx += (x[i] - mx) * (x[i] - mx);
    syy += (y[i] - my) * (y[i] - my);
  }
  return sxy / std::sqrt(sxx * syy);
}

TEST(ProceduralTextureTest, SameSeedSameBitsDifferentSeedDifferent) {
  const ProceduralTextureOptions options;
  const ProceduralTexture a(options, 42), b(options, 42), c(options, 43);
  int differing = 0;
  for (const Eigen::Vector3d& point : RandomPoints(2000, 50.0, 1)) {
    EXPECT_TRUE(SameBits(a.Albedo(point, kUp), b.Albedo(point, kUp)));
    differing += !SameBits(a.Albedo(point, kUp), c.Albedo(point, kUp));
  }
  EXPECT_GT(differing, 1900);
}

TEST(ProceduralTextureTest, ThreadsDoNotChangeTheResult) {
  const ProceduralTexture texture(ProceduralTextureOptions(), 7);
  const std::vector<Eigen::Vector3d> points = RandomPoints(20000, 20.0, 2);
  std::vector<Eigen::Vector3f> sequential(points.size()),
      parallel(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    sequential[i] = texture.Albedo(points[i], kUp);
  }
  constexpr int kThreads = 4;
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t) {
    threads.emplace_back([&, t] {
      for (size_t i = t; i < points.size(); i += kThreads) {
        parallel[i] = texture.Albedo(points[i], kUp);
      }
    });
  }
  for (std::thread& thread : threads) thread.join();
  for (size_t i = 0; i < points.size(); ++i) {
    ASSERT_TRUE(SameBits(sequential[i], parallel[i])) << "point " << i;
  }
}

TEST(ProceduralTextureTest, AlbedoIsFiniteAndInRangeEverywhere) {
  const ProceduralTexture texture(ProceduralTextureOptions(), 3);
  std::mt19937_64 rng(3);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (const Eigen::Vector3d& point : RandomPoints(20000, 2000.0, 3)) {
    const Eigen::Vector3d n =
        Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
    const Eigen::Vector3f albedo = texture.Albedo(point, n);
    ASSERT_TRUE(albedo.allFinite());
    ASSERT_GE(albedo.minCoeff(), 0.0f);
    ASSERT_LE(albedo.maxCoeff(), 1.0f);
  }
}

// What SIFT needs at 1-5 m with a ~1000 px focal length (1-5 mm pixels):
// strong contrast between points a few cm apart, on floors, walls and
// overhang undersides alike, yet smooth below a pixel.
TEST(ProceduralTextureTest, StrongCentimetreContrastOnEveryOrientation) {
  const ProceduralTexture texture(ProceduralTextureOptions(), 11);
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX();
  const Eigen::Vector3d y = Eigen::Vector3d::UnitY();
  const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
  struct Surface {
    Eigen::Vector3d a, b, normal;
  };
  for (const Surface& surface :
       {Surface{x, y, z}, Surface{x, z, -y}, Surface{y, x, -z}}) {
    double mean = 0.0, far_sq = 0.0, near_sq = 0.0;
    int count = 0;
    for (const Eigen::Vector3d& point : RandomPoints(5000, 10.0, 5)) {
      const auto at = [&](double da, double db) {
        return Luminance(texture.Albedo(point + da * surface.a + db * surface.b,
                                        surface.normal));
      };
      const float centre = at(0.0, 0.0);
      mean += centre;
      far_sq += std::pow(at(0.02, 0.0) - centre, 2);
      near_sq += std::pow(at(0.0005, 0.0) - centre, 2);
      ++count;
    }
    mean /= count;
    const double far_rms = std::sqrt(far_sq / count);
    const double near_rms = std::sqrt(near_sq / count);
    EXPECT_GT(far_rms, 0.15 * mean) << "normal " << surface.normal.transpose();
    EXPECT_LT(near_rms, 0.3 * far_rms)
        << "normal " << surface.normal.transpose();
  }
}

// Neighbouring images must differ beyond the grain: mean brightness over
// 0.5 m squares varies from place to place.
TEST(ProceduralTextureTest, LargerStructureMakesPlacesDistinguishable) {
  const ProceduralTexture texture(ProceduralTextureOptions(), 13);
  std::vector<double> means;
  for (int place = 0; place < 40; ++place) {
    const Eigen::Vector3d origin(1.37 * place, -0.91 * place, 0.0);
    const std::vector<float> patch =
        Patch(texture, origin, Eigen::Vector3d::UnitX(),
              Eigen::Vector3d::UnitY(), kUp, 20, 0.025);
    double sum = 0.0;
    for (const float value : patch) sum += value;
    means.push_back(sum / patch.size());
  }
  double mean = 0.0, var = 0.0;
  for (const double m : means) mean += m / means.size();
  for (const double m : means) var += (m - mean) * (m - mean) / means.size();
  EXPECT_GT(std::sqrt(var), 0.1 * mean);
}

// A pattern that repeats would give SIFT false matches between places. The
// fine structure (differences between neighbouring samples, which is what
// SIFT's gradient histograms see) of a 12 cm patch is compared with that of
// patches shifted along the axes and a diagonal by multiples of 10 cm up
// to 40 m.
TEST(ProceduralTextureTest, NoRepetitionAlongAxesAndDiagonals) {
  const ProceduralTexture texture(ProceduralTextureOptions(), 17);
  const Eigen::Vector3d a = Eigen::Vector3d::UnitX();
  const Eigen::Vector3d b = Eigen::Vector3d::UnitY();
  const Eigen::Vector3d origin(0.3, -0.2, 0.05);
  constexpr int kSize = 24;
  const auto fine_structure = [&](const Eigen::Vector3d& corner) {
    const std::vector<float> patch =
        Patch(texture, corner, a, b, kUp, kSize, 0.005);
    std::vector<float> differences;
    for (int j = 0; j < kSize; ++j) {
      for (int i = 0; i + 1 < kSize; ++i) {
        differences.push_back(patch[j * kSize + i + 1] - patch[j * kSize + i]);
      }
    }
    return differences;
  };
  const std::vector<float> reference = fine_structure(origin);
  double worst = 0.0;
  for (const Eigen::Vector3d& direction :
       {Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 1, 0),
        Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(1, 1, 1).normalized()}) {
    for (int k = 1; k <= 400; ++k) {
      worst = std::max(
          worst,
          Correlation(reference, fine_structure(origin + 0.1 * k * direction)));
    }
  }
  EXPECT_LT(worst, 0.6);  // a repeat would give ~1; chance gives ~0.4
}

// With the brightness modulations and stains off, the albedo is a blend of
// rock and sediment: the share of a level floor closer to the sediment
// colour follows sediment_cover, and overhang undersides stay rock.
TEST(ProceduralTextureTest, SedimentCoverFollowsOptionAndOrientation) {
  ProceduralTextureOptions options;
  options.grain_contrast = 0.0;
  options.patch_contrast = 0.0;
  options.stain_strength = 0.0;
  const Eigen::Vector3d rock(options.rock_albedo.data());
  const Eigen::Vector3d sediment(options.sediment_albedo.data());
  const auto sediment_share = [&](const ProceduralTexture& texture,
                                  const Eigen::Vector3d& normal) {
    int count = 0;
    const std::vector<Eigen::Vector3d> points = RandomPoints(20000, 200.0, 19);
    for (const Eigen::Vector3d& point : points) {
      const Eigen::Vector3d albedo =
          texture.Albedo(point, normal).cast<double>();
      count += (albedo - sediment).norm() < (albedo - rock).norm();
    }
    return static_cast<double>(count) / points.size();
  };
  for (const double cover : {0.2, 0.45, 0.8}) {
    options.sediment_cover = cover;
    const ProceduralTexture texture(options, 23);
    EXPECT_NEAR(sediment_share(texture, kUp), cover, 0.08) << cover;
    EXPECT_LT(sediment_share(texture, -kUp), 0.1 * cover + 0.02) << cover;
  }
}

TEST(ProceduralTextureTest, CheckRejectsNonsense) {
  EXPECT_NO_THROW(ProceduralTextureOptions().Check());
  const auto rejects = [](auto modify) {
    ProceduralTextureOptions options;
    modify(options);
    EXPECT_THROW(options.Check(), Error);
    EXPECT_THROW(ProceduralTexture(options, 1), Error);
  };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  rejects([](auto& o) { o.grain_wavelength_m = -0.01; });
  rejects([](auto& o) { o.patch_wavelength_m = 0.0; });
  rejects([&](auto& o) { o.region_wavelength_m = nan; });
  rejects([](auto& o) {
    o.region_wavelength_m = std::numeric_limits<double>::infinity();
  });
  rejects([](auto& o) { o.grain_octaves = 0; });
  rejects([](auto& o) { o.grain_octaves = 5; });
  rejects([&](auto& o) { o.grain_contrast = nan; });
  rejects([](auto& o) { o.patch_contrast = 1.5; });
  rejects([](auto& o) { o.sediment_cover = -0.1; });
  rejects([](auto& o) { o.rock_albedo[1] = 1.2; });
  rejects([&](auto& o) { o.stain_albedo[2] = nan; });
  rejects([](auto& o) { o.stain_strength = 2.0; });
}

}  // namespace
}  // namespace uw::sim
