// Triangle meshes: uwsim's worlds (metres, the survey's local East-North-Up
// frame, DESIGN.md §4) and the surfaces of reconstructed models (model
// units and frame), which laser spots are ray cast onto.
#pragma once

#include <filesystem>
#include <vector>

#include <Eigen/Core>

namespace uw {

struct TriangleMesh {
  std::vector<Eigen::Vector3d> vertices;
  // Vertex indices; counter-clockwise seen from the side the surface faces
  // (the water side), so that the geometric normal points into the water.
  std::vector<Eigen::Vector3i> triangles;

  Eigen::Vector3d TriangleNormal(size_t triangle) const;  // unit length
};

// Binary little-endian PLY ("vertex" x y z as double, "face" as uchar count
// + int indices), written to a temporary file and renamed. `frame` (one
// line, not empty) goes into the header as a comment: which frame and
// units the vertices are in, as the writer knows them ("uwsim world mesh;
// metres, x east, y north, z up", or a COLMAP model's own frame and units).
void WritePly(const TriangleMesh& mesh, const std::filesystem::path& path,
              const std::string& frame);

// Reads what WritePly writes and ASCII / binary PLY with float or double
// vertices and triangle faces; throws uw::Error naming the file otherwise.
TriangleMesh ReadPly(const std::filesystem::path& path);

// ReadPly for a mesher's output: a non-finite vertex is dropped, with every
// face that uses it, instead of refused; *num_dropped (when given) counts
// them. colmap's Poisson (PoissonRecon 8.0) leaves a few NaN vertices on
// some clouds (4 of 236 015 on one uwsim survey); a user's mesh with one is
// still an error (ReadPly).
TriangleMesh ReadPlyDroppingNonFinite(const std::filesystem::path& path,
                                      size_t* num_dropped);

// Wavefront OBJ: "v x y z" vertices and "f" faces (indices 1-based or
// negative, with or without /texture/normal parts; polygons are fanned into
// triangles); other statements are ignored. Throws uw::Error naming the
// file and line of anything malformed.
TriangleMesh ReadObj(const std::filesystem::path& path);

// ReadPly or ReadObj by the file's extension (.ply, .obj; any case); any
// other extension through Assimp (assimp_mesh.h: STL, glTF, ...).
TriangleMesh ReadMesh(const std::filesystem::path& path);

}  // namespace uw
