// Heightfields and grids of vertices: how the worlds become triangle
// meshes (every world but the vent's chimney is one heightfield or one
// parametric grid).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "common/mesh/mesh.h"

namespace uw::sim {

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
                         TriangleMesh* mesh);

// The grid's vertices (x, y, z) and triangles; normals point up.
void AppendHeightGrid(const HeightGrid& grid, TriangleMesh* mesh);

// Raises every vertex of the grid to at least the cone of slope max_slope
// (rise over run) hanging from each other vertex, so that no slope is
// steeper: two raster passes propagate the cones over 8-neighbours
// (chamfer distances, within 8 % of Euclidean). Cliffs, which a
// heightfield renders as stair-stepped one-cell walls, become skirts a
// few cells wide.
void LimitSlope(double max_slope, HeightGrid* grid);

}  // namespace uw::sim
