#include "sim/worlds/seafloor.h"

#include <algorithm>

#include "common/util/error.h"
#include "sim/world.h"
#include "sim/worlds/height_grid.h"
#include "sim/worlds/option_checks.h"

namespace uw::sim {

void SeafloorOptions::Check() const {
  const std::string section = "seafloor";
  CheckPositive(length_m, section, "length_m");
  CheckPositive(width_m, section, "width_m");
  CheckPositive(vertex_spacing_m, section, "vertex_spacing_m");
  relief.Check(section + ".relief");
  rocks.Check(section + ".rocks");
  if (rocks.count > 0 && rocks.max_diameter_m >= std::min(length_m, width_m)) {
    throw ErrorAt(OptionName(section, "rocks.max_diameter_m"), " = ",
                  rocks.max_diameter_m, ": rocks must fit on the floor");
  }
  CheckTriangles(2.0 * (length_m / vertex_spacing_m + 1.0) *
                     (width_m / vertex_spacing_m + 1.0),
                 section, "vertex_spacing_m");
}

World MakeSeafloor(const SeafloorOptions& options, SplitMix64Stream& random) {
  const Relief relief(options.relief, options.vertex_spacing_m, random);
  const auto ground = [&relief](double x, double y) {
    return relief(Eigen::Vector3d(x, y, 0.0));
  };
  HeightGrid grid(-0.5 * options.length_m, -0.5 * options.width_m,
                  options.length_m, options.width_m, options.vertex_spacing_m);
  for (int j = 0; j < grid.ny; ++j) {
    for (int i = 0; i < grid.nx; ++i)
      grid.at(i, j) = ground(grid.x(i), grid.y(j));
  }
  AddRocks(options.rocks, ground, OutsideDisc(0.0), random, &grid);

  World world;
  world.name = "seafloor";
  AppendHeightGrid(grid, &world.mesh);
  double sum_z = 0.0;
  for (const double z : grid.z) sum_z += z;
  world.survey_origin = Eigen::Vector3d(0.0, 0.0, sum_z / grid.z.size());
  world.survey_normal = Eigen::Vector3d::UnitZ();
  world.survey_along = Eigen::Vector3d::UnitX();
  world.survey_length = options.length_m;
  world.survey_width = options.width_m;
  return world;
}

}  // namespace uw::sim
