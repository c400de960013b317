#include "laserscale/laser_image_detection.h"

#include <fstream>
#include <utility>

#include <opencv2/imgcodecs.hpp>

#include "colmap_plugins/cameras/camera_models.h"
#include "colmap_plugins/scene/model_io.h"
#include "common/util/error.h"
#include "common/util/file.h"
#include "laserscale/laser_setup.h"

namespace uw {
namespace {

namespace fs = std::filesystem;

cv::Mat ReadImage(const fs::path& path) {
  const cv::Mat image = cv::imread(path.string(), cv::IMREAD_COLOR);
  if (image.empty()) throw ErrorAt(path.string(), ": cannot read the image");
  return image;
}

const LaserSetup& ChooseSetup(const std::vector<LaserSetup>& setups,
                              const LaserImageDetectionOptions& options) {
  const LaserSetup* setup = nullptr;
  for (const LaserSetup& candidate : setups) {
    if (candidate.name == options.setup_name ||
        (options.setup_name.empty() && setups.size() == 1)) {
      setup = &candidate;
    }
  }
  if (setup == nullptr) {
    throw ErrorAt(options.lasers_path, ": choose a set-up with --setup (",
                  setups.size(), " set-ups)");
  }
  return *setup;
}

Camera ChooseCamera(const LaserImageDetectionOptions& options) {
  Camera camera;
  if (!options.input_path.empty()) {
    const Reconstruction model = ReadModel(options.input_path);
    const Camera* found = model.FindCamera(options.camera_id);
    if (found == nullptr) {
      throw ErrorAt(options.input_path, ": no camera ", options.camera_id);
    }
    return *found;
  }
  camera.model_id = CameraModelNameToId(options.camera_model);
  if (camera.model_id == CameraModelId::kInvalid) {
    throw ErrorAt("--camera_model: unknown model '", options.camera_model, "'");
  }
  camera.params = options.camera_params;
  CheckCameraModelParams(camera.model_id, camera.params.size());
  return camera;
}

}  // namespace

bool IsAuxiliaryImageName(const std::string& name) {
  const std::string stem = fs::path(name).stem().string();
  return stem.size() > 4 && stem.substr(stem.size() - 4) == "_aux";
}

AuxiliaryImages::AuxiliaryImages(fs::path images_dir,
                                 std::vector<std::string> names,
                                 std::string aux)
    : images_dir_(std::move(images_dir)),
      names_(std::move(names)),
      aux_(std::move(aux)) {
  if (aux_ == "auto" || aux_ == "none") return;
  std::ifstream in(aux_);
  if (!in) throw ErrorAt(aux_, ": cannot open the auxiliary list");
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    const size_t comma = line.find(',');
    if (comma == std::string::npos) {
      throw ErrorAt(aux_, ":", number, ": expected image,aux");
    }
    aux_of_[line.substr(0, comma)] = line.substr(comma + 1);
  }
}

fs::path AuxiliaryImages::For(size_t i) const {
  if (aux_ == "none") return {};
  if (aux_ == "auto") {
    const fs::path path = images_dir_ / names_[i];
    const fs::path beside =
        path.parent_path() /
        (path.stem().string() + "_aux" + path.extension().string());
    if (fs::exists(beside)) return beside;
    if (names_.size() < 2) return {};
    return images_dir_ / names_[i + 1 < names_.size() ? i + 1 : i - 1];
  }
  const auto found = aux_of_.find(names_[i]);
  if (found == aux_of_.end()) {
    throw ErrorAt(aux_, ": no auxiliary image for ", names_[i]);
  }
  return images_dir_ / found->second;
}

void LaserImageDetectionOptions::Check() const {
  detector.Check();
  if (input_path.empty() && (camera_model.empty() || camera_params.empty())) {
    throw ErrorAt("give --input_path or --camera_model and --camera_params");
  }
}

std::vector<ImageSpots> DetectLaserImages(
    const LaserImageDetectionOptions& options,
    const DetectedImageCallback& done) {
  options.Check();
  const std::vector<LaserSetup> setups = ReadLasersJson(options.lasers_path);
  const LaserSetup& setup = ChooseSetup(setups, options);
  Camera camera = ChooseCamera(options);
  const std::vector<std::string> names = ListImages(
      options.images_dir, options.image_list_path,
      [](const std::string& name) { return !IsAuxiliaryImageName(name); });
  const AuxiliaryImages aux(options.images_dir, names, options.aux);
  std::vector<ImageSpots> results;
  for (size_t i = 0; i < names.size(); ++i) {
    const fs::path path = fs::path(options.images_dir) / names[i];
    const cv::Mat image = ReadImage(path);
    if (camera.width == 0) {
      camera.width = static_cast<uint64_t>(image.cols);
      camera.height = static_cast<uint64_t>(image.rows);
    }
    if (static_cast<int>(camera.width) != image.cols ||
        static_cast<int>(camera.height) != image.rows) {
      throw ErrorAt(path.string(), ": ", image.cols, "x", image.rows,
                    " pixels, the camera has ", camera.width, "x",
                    camera.height);
    }
    const fs::path aux_path = aux.For(i);
    const cv::Mat aux_image =
        aux_path.empty() ? cv::Mat() : ReadImage(aux_path);
    ImageSpots spots;
    spots.name = names[i];
    spots.setup = setup.name;
    spots.spots = DetectSpots(image, aux_image, camera, setup, options.detector,
                              options.seed + i);
    if (done) done(i, names.size(), image, spots);
    results.push_back(std::move(spots));
  }
  return results;
}

}  // namespace uw
