// Triangle meshes of synthetic worlds, in metres, in the world frame of the
// survey (local East-North-Up: x east, y north, z up; DESIGN.md §4).
#pragma once

#include <filesystem>
#include <vector>

#include <Eigen/Core>

namespace uw::sim {

struct TriangleMesh {
  std::vector<Eigen::Vector3d> vertices;
  // Vertex indices; counter-clockwise seen from the side the surface faces
  // (the water side), so that the geometric normal points into the water.
  std::vector<Eigen::Vector3i> triangles;

  Eigen::Vector3d TriangleNormal(size_t triangle) const;  // unit length
};

// Binary little-endian PLY ("vertex" x y z as double, "face" as uchar count
// + int indices), written to a temporary file and renamed.
void WritePly(const TriangleMesh& mesh, const std::filesystem::path& path);

// Reads what WritePly writes and ASCII / binary PLY with float or double
// vertices and triangle faces; throws uw::Error naming the file otherwise.
TriangleMesh ReadPly(const std::filesystem::path& path);

}  // namespace uw::sim
