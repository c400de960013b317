#include "colmap_plugins/ba/scale_transfer.h"

#include <algorithm>
#include <map>
#include <numeric>

#include <fmt/format.h>

namespace uw {
namespace {

// Union-find over image indices.
size_t Root(std::vector<size_t>* parent, size_t i) {
  while ((*parent)[i] != i) {
    (*parent)[i] = (*parent)[(*parent)[i]];
    i = (*parent)[i];
  }
  return i;
}

}  // namespace

std::vector<image_t> ImagesWithoutScaleTransfer(const Reconstruction& model) {
  std::map<image_t, size_t> index_of;
  for (const Image& image : model.Images()) {
    index_of.emplace(image.image_id, index_of.size());
  }
  std::vector<size_t> parent(index_of.size());
  std::iota(parent.begin(), parent.end(), size_t(0));
  for (const Point3D& point : model.Points3D()) {
    std::vector<size_t> images;
    for (const TrackElement& element : point.track) {
      const auto it = index_of.find(element.image_id);
      if (it != index_of.end()) images.push_back(it->second);
    }
    std::sort(images.begin(), images.end());
    images.erase(std::unique(images.begin(), images.end()), images.end());
    if (images.size() < 3) continue;
    for (size_t k = 1; k < images.size(); ++k) {
      parent[Root(&parent, images[k])] = Root(&parent, images[0]);
    }
  }
  std::vector<size_t> group_size(parent.size(), 0);
  for (size_t i = 0; i < parent.size(); ++i) ++group_size[Root(&parent, i)];
  const size_t largest = static_cast<size_t>(
      std::max_element(group_size.begin(), group_size.end()) -
      group_size.begin());
  std::vector<image_t> outside;
  for (const auto& [image_id, index] : index_of) {
    if (Root(&parent, index) != largest) outside.push_back(image_id);
  }
  return outside;
}

std::optional<std::string> ScaleTransferWarning(const Reconstruction& model,
                                                bool navigation_priors) {
  const std::vector<image_t> outside = ImagesWithoutScaleTransfer(model);
  if (outside.empty()) return std::nullopt;
  std::string names;
  for (size_t k = 0; k < std::min<size_t>(outside.size(), 3); ++k) {
    names += (k ? ", " : "") + model.FindImage(outside[k])->name;
  }
  return fmt::format(
      "{} images share no point that 3 images see with the other {} (e.g. "
      "{}): the images do not fix their distance to the rest, {}. Track "
      "more points (or longer tracks) where the images overlap",
      outside.size(), model.Images().size() - outside.size(), names,
      navigation_priors
          ? "which the navigation alone sets (within its noise: two cameras "
            "can end up on top of each other, their points undetermined)"
          : "so the adjustment and its covariance are degenerate there");
}

}  // namespace uw
