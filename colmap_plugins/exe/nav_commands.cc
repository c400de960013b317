#include "colmap_plugins/exe/nav_commands.h"

#include <iostream>

#include <fmt/format.h>

#include "colmap_plugins/exe/nav_flags.h"
#include "common/util/error.h"
#include "common/util/file.h"
#include "common/util/time_text.h"

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

void AddImageTimesFlags(CommandLine* cli, ImageTimesOptions* options) {
  ImageTimesFromImagesOptions& images = options->images;
  cli->Add("--image_path", &images.image_path,
           "Folder of the images (as colmap's --image_path: every JPEG/PNG "
           "below it, named relative to it)")
      ->required();
  cli->Add("--output_path", &options->output_path,
           "image_times.csv to write (image_name,time in Unix seconds)")
      ->required();
  cli->Add<ImageTimeSource>(
      "--source", &images.source,
      "Where the times are: exif (DateTimeOriginal + SubSecTimeOriginal + "
      "OffsetTimeOriginal) or filename (--filename_pattern)",
      ImageTimeSourceFromName, ImageTimeSourceName);
  cli->Add("--filename_pattern", &images.filename_pattern,
           "With --source filename, the file name without extension: %Y %m "
           "%d %H %M %S, %f (decimals), %z (zone), * (anything), e.g. "
           "IMG_%Y%m%d_%H%M%S_%f");
  AddTimeZoneFlag(cli, &images.time_zone_offset_s,
                  "Zone (+hh:mm, -hh:mm or Z) of the camera clock, for times "
                  "that do not state one; default: such times are an error");
  cli->Add("--clock_offset", &images.clock_offset_s,
           "Seconds added to every camera time (the camera clock's error "
           "against the navigation's); or give it to pose_prior_importer as "
           "--time_offset, not both");
}

void PrintImageTimesProgress(size_t done, size_t total) {
  if (done % 100 != 0 && done != total) return;
  fmt::print("\r[image_times] {}/{} images", done, total);
  if (done == total) fmt::print("\n");
  std::fflush(stdout);
}

void RunImageTimes(const ImageTimesOptions& options) {
  const ImageTimesFromImages read =
      ReadImageTimesFromImages(options.images, PrintImageTimesProgress);
  const ImageTimesFromImagesOptions& images = options.images;
  const std::string source =
      images.source == ImageTimeSource::kExif
          ? std::string("EXIF DateTimeOriginal")
          : "file names (" + images.filename_pattern + ")";
  std::string comment =
      fmt::format("uwcolmap image_times: Unix time (s) from the {} of {}",
                  source, images.image_path);
  if (read.zone_assumed > 0) {
    comment += fmt::format(", {} read on a clock at {}", read.zone_assumed,
                           ZoneOffsetText(*images.time_zone_offset_s));
  }
  if (images.clock_offset_s != 0.0) {
    comment += fmt::format(", clock offset {} s added",
                           SecondsText(images.clock_offset_s));
  }
  const std::string text = ImageTimesCsvText(read.times, comment);
  WriteFilesAtomically({{options.output_path,
                         [&text](std::ostream& stream) { stream << text; }}},
                       false);
  double first = read.times.front().time_s;
  double last = first;
  for (const ImageTime& time : read.times) {
    first = std::min(first, time.time_s);
    last = std::max(last, time.time_s);
  }
  fmt::print("[image_times] wrote {}: {} images from {}, {} to {} (span {})\n",
             options.output_path, read.times.size(), source, TimeText(first),
             TimeText(last), DurationText(last - first));
  if (read.zone_assumed > 0) {
    std::cerr << "WARNING: " << read.zone_assumed << " of " << read.times.size()
              << " images do not state their clock's zone; they were read "
                 "at --time_zone "
              << ZoneOffsetText(*images.time_zone_offset_s) << "\n";
  }
}

}  // namespace

void ImageTimesOptions::Check() const {
  if (output_path.empty()) throw ErrorAt("--output_path is required");
  images.Check();
}

Subcommand ImageTimesCommand() {
  return MakeSubcommand<ImageTimesOptions>(
      "image_times", "write image_times.csv from the images' EXIF or names",
      "Writes image_times.csv (image_name,time; docs/formats.md) for every "
      "image below --image_path, named as colmap's database names them, "
      "with the time each was taken as Unix time (UTC): from its EXIF "
      "(DateTimeOriginal, SubSecTimeOriginal and OffsetTimeOriginal, in "
      "JPEG and PNG) or from its file name. A camera clock's zone comes "
      "from the image; where the image states none it must be given "
      "(--time_zone), as a local clock is hours of ambiguity. An image "
      "without a time is an error naming it. The file is then what "
      "pose_prior_importer, bundle_adjuster and model_aligner take as "
      "--image_times.\n\n"
      "Example (a camera set to local time in summer in Marseille, 0.4 s "
      "behind the navigation's GPS clock):\n"
      "  uwcolmap image_times --image_path images --output_path "
      "image_times.csv --time_zone +02:00 --clock_offset 0.4",
      AddImageTimesFlags, RunImageTimes);
}

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
