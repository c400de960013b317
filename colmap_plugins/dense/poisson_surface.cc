#include "colmap_plugins/dense/poisson_surface.h"

#include <algorithm>

#include <Eigen/Geometry>

#include "common/util/error.h"
#include "common/util/file.h"
#include "common/util/subprocess.h"

namespace uw {

void PoissonOptions::Check() const {
  if (depth < 4 || depth > 16) {
    throw ErrorAt("Poisson.depth must be in [4, 16], got ", depth);
  }
  if (!(point_weight >= 0.0)) {
    throw ErrorAt("Poisson.point_weight must be >= 0, got ", point_weight);
  }
  if (num_threads == 0 || num_threads < -1) {
    throw ErrorAt("Poisson.num_threads must be -1 or >= 1, got ", num_threads);
  }
  if (colmap_path.empty()) {
    throw Error("Poisson.colmap_path must not be empty");
  }
}

void WriteOrientedPly(const OrientedPoints& points,
                      const Eigen::Vector3d& origin,
                      const std::filesystem::path& path) {
  if (points.normals.size() != points.points.size()) {
    throw ErrorAt(path.string(), ": ", points.points.size(), " points but ",
                  points.normals.size(), " normals");
  }
  WriteFilesAtomically(
      {{path,
        [&](std::ostream& out) {
          out << "ply\nformat binary_little_endian 1.0\nelement vertex "
              << points.points.size()
              << "\nproperty float x\nproperty float y\nproperty float z\n"
                 "property float nx\nproperty float ny\nproperty float nz\n"
                 "property uchar red\nproperty uchar green\n"
                 "property uchar blue\nend_header\n";
          // colmap's reader requires colours; the points have none.
          const char grey[3] = {char(128), char(128), char(128)};
          for (size_t i = 0; i < points.points.size(); ++i) {
            const Eigen::Vector3f point =
                (points.points[i] - origin).cast<float>();
            const Eigen::Vector3f normal = points.normals[i].cast<float>();
            out.write(reinterpret_cast<const char*>(point.data()),
                      3 * sizeof(float));
            out.write(reinterpret_cast<const char*>(normal.data()),
                      3 * sizeof(float));
            out.write(grey, 3);
          }
        }}},
      /*binary=*/true);
}

TriangleMesh PoissonSurface(const OrientedPoints& points,
                            const PoissonOptions& options,
                            const std::filesystem::path& work_dir,
                            size_t* num_dropped_vertices) {
  options.Check();
  if (points.points.size() < 100) {
    throw ErrorAt("Poisson surface: only ", points.points.size(),
                  " fused points (at least 100 needed)");
  }
  // Float positions lose millimetres at kilometres from the origin; the
  // bounding box centre keeps them at the scale of the survey.
  Eigen::AlignedBox3d box;
  for (const Eigen::Vector3d& point : points.points) {
    box.extend(point);
  }
  const Eigen::Vector3d origin = box.center();
  std::filesystem::create_directories(work_dir);
  const std::filesystem::path input = work_dir / "fused.ply";
  const std::filesystem::path output = work_dir / "poisson.ply";
  const std::filesystem::path log = work_dir / "poisson_mesher.log";
  std::filesystem::remove(output);
  std::filesystem::remove(log);
  WriteOrientedPly(points, origin, input);
  const int code = RunProgram(
      {options.colmap_path, "poisson_mesher", "--input_path", input.string(),
       "--output_path", output.string(), "--PoissonMeshing.depth",
       std::to_string(options.depth), "--PoissonMeshing.point_weight",
       std::to_string(options.point_weight), "--PoissonMeshing.trim", "0",
       "--PoissonMeshing.num_threads", std::to_string(options.num_threads)},
      log);
  if (code != 0 || !std::filesystem::exists(output)) {
    throw ErrorAt(options.colmap_path, " poisson_mesher failed (exit ", code,
                  "; log ", log.string(), "):\n", TailOfFile(log, 10));
  }
  TriangleMesh mesh = ReadPlyDroppingNonFinite(output, num_dropped_vertices);
  for (Eigen::Vector3d& vertex : mesh.vertices) {
    vertex += origin;
  }
  return mesh;
}

}  // namespace uw
