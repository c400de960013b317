// `laserscale detect`'s method: the laser images of a folder, each with its
// auxiliary image (texture removal), through DetectSpots with the camera
// and the laser set-up they were taken with.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "laserscale/spot_detector.h"
#include "laserscale/spots_io.h"

namespace uw {

// Which auxiliary image goes with each laser image of a list, by `aux`:
// "auto" (NAME_aux.EXT beside NAME.EXT, else the next image of the list, the
// previous one for the last), "none", or the path of a CSV of image,aux
// lines (names relative to the images folder), read here.
class AuxiliaryImages {
 public:
  AuxiliaryImages(std::filesystem::path images_dir,
                  std::vector<std::string> names, std::string aux);

  // The path of image i's auxiliary image; empty: none. Throws uw::Error
  // when the CSV has no line for it.
  std::filesystem::path For(size_t i) const;

 private:
  std::filesystem::path images_dir_;
  std::vector<std::string> names_;
  std::string aux_;
  std::map<std::string, std::string> aux_of_;  // from the CSV
};

// Whether `name` is an auxiliary image of the "auto" convention (its stem
// ends in "_aux"), which the image list leaves out.
bool IsAuxiliaryImageName(const std::string& name);

struct LaserImageDetectionOptions {
  std::string images_dir;
  // One name per line; empty: every image of the folder but the *_aux ones.
  std::string image_list_path;
  std::string aux = "auto";  // see AuxiliaryImages
  std::string lasers_path;   // lasers.json
  std::string setup_name;    // empty: the only set-up of lasers.json
  // The camera: camera_id of the model at input_path, or else camera_model
  // with camera_params (COLMAP order); its size is the first image's.
  std::string input_path;
  uint32_t camera_id = 1;
  std::string camera_model;
  std::vector<double> camera_params;
  uint64_t seed = 0;  // image i's detection Monte Carlo uses seed + i
  SpotDetectorOptions detector;

  // The detector's options, and a camera to use.
  void Check() const;
};

// Called after each image with its index, the number of images, the image
// (8-bit BGR) and its spots.
using DetectedImageCallback = std::function<void(
    size_t index, size_t count, const cv::Mat& image, const ImageSpots& spots)>;

// The spots of every image, in list order. Throws uw::Error naming the file
// for an unreadable image, one whose size is not the camera's, an unknown
// camera, model or set-up.
std::vector<ImageSpots> DetectLaserImages(
    const LaserImageDetectionOptions& options,
    const DetectedImageCallback& done = nullptr);

}  // namespace uw
