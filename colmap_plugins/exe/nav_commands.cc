#include "colmap_plugins/exe/nav_commands.h"

#include <iostream>

#include "colmap_plugins/exe/nav_flags.h"
#include "common/util/error.h"

namespace uw {
namespace {

void PrintSummary(const std::string& database_path,
                  const PosePriorImportOptions& options,
                  const PosePriorImportSummary& summary) {
  const PosePriorWriteSummary& written = summary.written;
  std::cout << "Database: " << database_path << " ("
            << DatabaseSchemaName(summary.schema) << "), "
            << summary.num_database_images << " images\n"
            << "Navigation: " << options.nav_path.string() << ", "
            << summary.num_nav_rows << " rows, " << summary.num_dives
            << (summary.num_dives == 1 ? " dive\n" : " dives\n")
            << "World frame: " << WorldFrameText(summary.frame) << "\n"
            << "Image times: "
            << (options.image_times_path.empty()
                    ? (summary.num_rig_cameras > 0
                           ? "the reference camera's navigation rows plus "
                             "the rig's time offsets"
                           : "the navigation rows, matched by image name")
                    : options.image_times_path.string())
            << "\n";
  if (summary.num_rig_cameras > 0) {
    std::cout << "Rig: " << options.rig_config_path.string() << ", "
              << summary.num_rig_cameras << " cameras\n";
  }
  std::cout << "Camera on the vehicle: "
            << DescribeNavToCamera(options.nav_to_camera) << "\n"
            << "Images with priors: " << summary.num_priors << " ("
            << summary.num_exact << " at a navigation row, "
            << summary.num_interpolated << " interpolated, "
            << summary.num_extrapolated << " extrapolated)\n"
            << "Images without priors: " << summary.num_images_without_priors
            << "\n";
  if (!summary.other_images.empty()) {
    std::cout << "Rows naming no image of the database, left out: "
              << summary.other_images.size() << " (e.g. "
              << summary.other_images.front() << ")\n";
  }
  if (summary.num_singular_covariances > 0) {
    std::cout << "Priors without covariance (a zero sigma in the log): "
              << summary.num_singular_covariances << "\n";
  }
  std::string dropped;
  for (const auto& [name, count] :
       {std::pair<const char*, size_t>{"position covariance",
                                       written.num_dropped_covariances},
        {"rotation", written.num_dropped_rotations},
        {"gravity", written.num_dropped_gravities},
        {"coordinate system", written.num_dropped_coordinate_systems}}) {
    if (count > 0) {
      dropped += (dropped.empty() ? " " : ", ") + std::string(name) + " " +
                 std::to_string(count);
    }
  }
  if (!dropped.empty()) {
    std::cout << "Not stored (" << DatabaseSchemaName(summary.schema)
              << " has no place for them):" << dropped << "\n";
  }
  for (const std::string& warning : summary.warnings) {
    std::cerr << "WARNING: " << warning << "\n";
  }
}

void AddPosePriorImporterFlags(CommandLine* cli,
                               PosePriorImporterOptions* options) {
  cli->Add("--database_path", &options->database_path, "COLMAP database")
      ->required();
  AddNavFlags(cli, &options->import, true, "--rig_config");
  cli->Add("--coordinate_system", &options->coordinate_system,
           "Frame of the positions written: cartesian (the log's x,y,z, or a "
           "geographic log's local east-north-up at --origin)");
}

void RunPosePriorImporter(const PosePriorImporterOptions& options) {
  const PosePriorImportSummary summary =
      ImportPosePriors(options.database_path, options.import);
  PrintSummary(options.database_path, options.import, summary);
}

}  // namespace

void PosePriorImporterOptions::Check() const {
  if (coordinate_system != "cartesian") {
    throw ErrorAt("--coordinate_system ", coordinate_system,
                  ": the priors are written in a local metric frame "
                  "(cartesian); a geographic log is read into one (--origin)");
  }
  import.Check();
}

Subcommand PosePriorImporterCommand() {
  return MakeSubcommand<PosePriorImporterOptions>(
      "pose_prior_importer",
      "write camera pose priors from a navigation log into a database",
      "Writes camera pose priors from a navigation log into a COLMAP "
      "database, in the database's own schema (3.8 to 4.x): the camera "
      "centre (vehicle position + lever arm), its covariance and the "
      "camera's rotation where the schema has a place for them. The vehicle "
      "pose is taken at each image's time: the navigation row of the same "
      "name, or with --image_times interpolated at the time given there. "
      "Everything is checked before anything is written; on an error the "
      "database is unchanged. Formats: docs/formats.md.\n\n"
      "Example (uwsim's floor survey: camera looking down, lever arm and "
      "boresight of truth/sim.json):\n"
      "  uwcolmap pose_prior_importer --database_path database.db "
      "--nav sim/nav.csv --mount down --lever_arm 0.6,0,-0.3 "
      "--boresight 0.3,-0.5,0.8",
      AddPosePriorImporterFlags, RunPosePriorImporter);
}

}  // namespace uw
