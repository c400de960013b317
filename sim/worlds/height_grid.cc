#include "sim/worlds/height_grid.h"

namespace uw::sim {

void AppendGridTriangles(int first, int nu, int nv, bool wrap_u,
                         TriangleMesh* mesh) {
  const int cells_u = wrap_u ? nu : nu - 1;
  const auto index = [&](int i, int j) { return first + j * nu + i % nu; };
  mesh->triangles.reserve(mesh->triangles.size() +
                          2 * static_cast<size_t>(cells_u) * (nv - 1));
  for (int j = 0; j + 1 < nv; ++j) {
    for (int i = 0; i < cells_u; ++i) {
      const int a = index(i, j), b = index(i + 1, j);
      const int c = index(i + 1, j + 1), d = index(i, j + 1);
      if ((i + j) % 2 == 0) {
        mesh->triangles.emplace_back(a, b, c);
        mesh->triangles.emplace_back(a, c, d);
      } else {
        mesh->triangles.emplace_back(a, b, d);
        mesh->triangles.emplace_back(b, c, d);
      }
    }
  }
}

void AppendHeightGrid(const HeightGrid& grid, TriangleMesh* mesh) {
  const int first = static_cast<int>(mesh->vertices.size());
  mesh->vertices.reserve(mesh->vertices.size() + grid.z.size());
  for (int j = 0; j < grid.ny; ++j) {
    for (int i = 0; i < grid.nx; ++i) {
      mesh->vertices.emplace_back(grid.x(i), grid.y(j),
                                  grid.z[static_cast<size_t>(j) * grid.nx + i]);
    }
  }
  AppendGridTriangles(first, grid.nx, grid.ny, /*wrap_u=*/false, mesh);
}

void LimitSlope(double max_slope, HeightGrid* grid) {
  const double drop_x = max_slope * grid->dx, drop_y = max_slope * grid->dy;
  const double drop_xy = max_slope * std::hypot(grid->dx, grid->dy);
  const auto raise = [grid](int i, int j, int ni, int nj, double drop) {
    if (ni < 0 || ni >= grid->nx || nj < 0 || nj >= grid->ny) return;
    grid->at(i, j) = std::max(grid->at(i, j), grid->at(ni, nj) - drop);
  };
  for (int j = 0; j < grid->ny; ++j) {
    for (int i = 0; i < grid->nx; ++i) {
      raise(i, j, i - 1, j, drop_x);
      raise(i, j, i - 1, j - 1, drop_xy);
      raise(i, j, i, j - 1, drop_y);
      raise(i, j, i + 1, j - 1, drop_xy);
    }
  }
  for (int j = grid->ny - 1; j >= 0; --j) {
    for (int i = grid->nx - 1; i >= 0; --i) {
      raise(i, j, i + 1, j, drop_x);
      raise(i, j, i + 1, j + 1, drop_xy);
      raise(i, j, i, j + 1, drop_y);
      raise(i, j, i - 1, j + 1, drop_xy);
    }
  }
}

}  // namespace uw::sim
