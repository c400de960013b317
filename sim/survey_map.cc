#include "sim/survey_map.h"

#include <algorithm>
#include <cctype>
#include <unordered_map>

#include <opencv2/imgcodecs.hpp>

#include "colmap_plugins/nav/nav_csv.h"
#include "colmap_plugins/scene/model_io.h"
#include "common/util/error.h"
#include "common/util/file.h"

namespace uw::sim {
namespace fs = std::filesystem;
namespace {

// nav.csv through the importer's reader: a damaged file is refused rather
// than drawn halfway.
std::vector<SurveyMapPoint> ReadNavCsv(const fs::path& path) {
  std::vector<SurveyMapPoint> points;
  for (const NavRecord& record : ReadNavigationCsv(path)) {
    points.push_back({record.image_name, record.dive, record.position});
  }
  return points;
}

fs::path RequireFile(const fs::path& sim_dir, const fs::path& relative) {
  const fs::path path = sim_dir / relative;
  if (!fs::is_regular_file(path)) {
    throw ErrorAt(path.string(), ": missing (", sim_dir.string(),
                  " should be an output folder of uwsim generate)");
  }
  return path;
}

std::string LowerCase(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return text;
}

}  // namespace

SurveyMapData ReadSurveyMapData(const fs::path& sim_dir) {
  if (!fs::is_directory(sim_dir)) {
    throw ErrorAt(sim_dir.string(),
                  ": not a folder (expected an output folder of uwsim "
                  "generate)");
  }
  // Every file is checked before the (large) mesh is read.
  const fs::path mesh_path = RequireFile(sim_dir, "truth/mesh.ply");
  const fs::path images_path = RequireFile(sim_dir, "truth/images.txt");
  const fs::path true_nav_path = RequireFile(sim_dir, "truth/nav.csv");
  const fs::path nav_path = RequireFile(sim_dir, "nav.csv");

  SurveyMapData data;
  data.true_track = ReadNavCsv(true_nav_path);
  data.navigation = ReadNavCsv(nav_path);
  Reconstruction truth;
  ParseImagesText(ReadFileToString(images_path), images_path.string(), &truth);
  std::unordered_map<std::string, int> dive_of_image;
  for (const SurveyMapPoint& point : data.true_track) {
    dive_of_image.emplace(point.image_name, point.dive);
  }
  for (const Image& image : truth.Images()) {
    const auto found = dive_of_image.find(image.name);
    if (found == dive_of_image.end()) {
      throw ErrorAt(images_path.string(), ": image '", image.name,
                    "' has no row in ", true_nav_path.string());
    }
    data.cameras.push_back(
        {image.name, found->second, image.ProjectionCenter()});
  }
  data.cameras_label = "true camera centres";
  data.true_track_label = "true vehicle track (truth/nav.csv)";
  data.navigation_label = "navigation with errors (nav.csv)";
  data.mesh = ReadPly(mesh_path);
  return data;
}

void WriteSurveyMap(const fs::path& sim_dir, const fs::path& out,
                    const SurveyMapOptions& options) {
  options.Check();
  const std::string extension = LowerCase(out.extension().string());
  std::vector<int> parameters;
  if (extension == ".png") {
    parameters = {cv::IMWRITE_PNG_COMPRESSION, 9};
  } else if (extension == ".jpg" || extension == ".jpeg") {
    parameters = {cv::IMWRITE_JPEG_QUALITY, 90};
  } else {
    throw ErrorAt(out.string(), ": unknown image type '", extension,
                  "'; use .png, .jpg or .jpeg");
  }
  const SurveyMap map = DrawSurveyMap(ReadSurveyMapData(sim_dir), options);
  std::vector<uchar> bytes;
  if (!cv::imencode(extension, map.image, bytes, parameters)) {
    throw ErrorAt(out.string(), ": cannot encode the map");
  }
  WriteFilesAtomically({{out,
                         [&bytes](std::ostream& stream) {
                           stream.write(
                               reinterpret_cast<const char*>(bytes.data()),
                               static_cast<std::streamsize>(bytes.size()));
                         }}},
                       true);
}

}  // namespace uw::sim
