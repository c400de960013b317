#include "common/mesh/assimp_mesh.h"

#include <fstream>

#include <fmt/format.h>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "common/util/error_testing.h"
#include "tests/support/process.h"

namespace uw {
namespace {

namespace fs = std::filesystem;

// A unit square at height 2 as two triangles, counter-clockwise seen from
// above, in ASCII STL (every triangle with its own corners) offset by
// `offset` in x.
std::string SquareStl(double offset) {
  const auto vertex = [&](double x, double y) {
    return fmt::format("      vertex {:.9f} {:.9f} 2\n", offset + x, y);
  };
  return "solid square\n  facet normal 0 0 1\n    outer loop\n" + vertex(0, 0) +
         vertex(1, 0) + vertex(1, 1) +
         "    endloop\n  endfacet\n  facet normal 0 0 1\n    outer loop\n" +
         vertex(0, 0) + vertex(1, 1) + vertex(0, 1) +
         "    endloop\n  endfacet\nendsolid square\n";
}

// STL and OFF (as CAD tools and Metashape export them) read through
// ReadMesh: shared corners joined, the winding kept.
TEST(AssimpMesh, ReadsStlAndOffWithSharedCorners) {
  const fs::path dir = testing::FreshTestDir("uw_assimp_mesh_test");
  std::ofstream(dir / "square.stl") << SquareStl(0.0);
  std::ofstream(dir / "square.off")
      << "OFF\n4 2 0\n0 0 2\n1 0 2\n1 1 2\n0 1 2\n3 0 1 2\n3 0 2 3\n";
  for (const char* name : {"square.stl", "square.off"}) {
    const TriangleMesh mesh = ReadMesh(dir / name);
    EXPECT_EQ(mesh.vertices.size(), 4u) << name;
    ASSERT_EQ(mesh.triangles.size(), 2u) << name;
    double area = 0.0;
    for (size_t t = 0; t < mesh.triangles.size(); ++t) {
      EXPECT_TRUE(mesh.TriangleNormal(t).isApprox(Eigen::Vector3d::UnitZ()))
          << name;
      const Eigen::Vector3i& tri = mesh.triangles[t];
      area += 0.5 * (mesh.vertices[tri[1]] - mesh.vertices[tri[0]])
                        .cross(mesh.vertices[tri[2]] - mesh.vertices[tri[0]])
                        .norm();
    }
    EXPECT_NEAR(area, 1.0, 1e-6) << name;
    for (const Eigen::Vector3d& vertex : mesh.vertices) {
      EXPECT_EQ(vertex.z(), 2.0) << name;
    }
  }
}

// A 1 m square at UTM-like x = 5e6 would be read 0.3 m off in single
// precision: refused, saying what to do; nonsense is refused too.
TEST(AssimpMesh, CoordinatesSinglePrecisionCannotHoldAreRefused) {
  const fs::path dir = testing::FreshTestDir("uw_assimp_mesh_test");
  std::ofstream(dir / "far.stl") << SquareStl(5e6);
  ExpectErrorContaining([&] { ReadMesh(dir / "far.stl"); },
                        "far.stl: coordinates up to 5e+06 lose up to 0.298 "
                        "units in the single precision");
  std::ofstream(dir / "notes.xyz") << "not a mesh\n";
  ExpectErrorContaining([&] { ReadMesh(dir / "notes.xyz"); },
                        "notes.xyz: cannot read the mesh");
}

}  // namespace
}  // namespace uw
