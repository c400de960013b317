#include <cstdio>

#include "colmap_plugins/align/sim3.h"
#include "colmap_plugins/scene/model_io.h"
#include "common/cli/command.h"
#include "common/mesh/mesh.h"
#include "common/util/error.h"
#include "laserscale/exe/commands.h"
#include "laserscale/scale_report.h"

namespace uw {

int RunApply(int argc, char** argv) {
  CLI::App app(
      "Scales a COLMAP model to metres by the scale s of `laserscale "
      "estimate` (about the world origin: points and camera centres times s, "
      "orientations unchanged), and optionally its mesh (vertices times s). "
      "The inputs are never modified.\n\n"
      "Example:\n"
      "  laserscale apply --input_path sparse/0 --scale report/scale.json "
      "--output_path sparse_metric --input_mesh mesh.ply --output_mesh "
      "mesh_metric.ply",
      "laserscale apply");
  std::string input_path;
  std::string scale_path;
  std::string output_path;
  std::string output_type = "BIN";
  app.add_option("--input_path", input_path, "COLMAP model")->required();
  app.add_option("--scale", scale_path, "scale.json of laserscale estimate")
      ->required();
  app.add_option("--output_path", output_path,
                 "Folder for the scaled model (created; must not be the input)")
      ->required();
  app.add_option("--output_type", output_type, "BIN or TXT")
      ->capture_default_str();
  std::string input_mesh;
  std::string output_mesh;
  app.add_option("--input_mesh", input_mesh,
                 "The model's mesh (PLY or OBJ, model frame) to scale too");
  app.add_option("--output_mesh", output_mesh,
                 "PLY for the scaled mesh (with --input_mesh)");
  return RunCommand(app, argc, argv, [&] {
    if (output_type != "BIN" && output_type != "TXT") {
      throw ErrorAt("--output_type must be BIN or TXT, got ", output_type);
    }
    if (std::filesystem::exists(output_path) &&
        std::filesystem::equivalent(input_path, output_path)) {
      throw ErrorAt("--output_path is the input model; choose another folder");
    }
    if (input_mesh.empty() != output_mesh.empty()) {
      throw Error("--input_mesh and --output_mesh go together");
    }
    if (!input_mesh.empty() && std::filesystem::exists(output_mesh) &&
        std::filesystem::equivalent(input_mesh, output_mesh)) {
      throw ErrorAt("--output_mesh is the input mesh; choose another file");
    }
    const double scale = ReadScaleFromJson(scale_path);
    Reconstruction model = ReadModel(input_path);
    Sim3d scaled_from_model;
    scaled_from_model.scale = scale;
    TransformReconstruction(scaled_from_model, &model);
    std::filesystem::create_directories(output_path);
    WriteModel(
        model, output_path,
        output_type == "BIN" ? ModelFormat::kBinary : ModelFormat::kText);
    std::printf("[apply] model scaled by %.6f into %s\n", scale,
                output_path.c_str());
    if (!input_mesh.empty()) {
      TriangleMesh mesh = ReadMesh(input_mesh);
      for (Eigen::Vector3d& vertex : mesh.vertices) {
        vertex = scaled_from_model * vertex;
      }
      WritePly(mesh, output_mesh);
      std::printf("[apply] mesh scaled by %.6f into %s\n", scale,
                  output_mesh.c_str());
    }
  });
}

}  // namespace uw
