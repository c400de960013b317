#include "colmap_plugins/ba/model_file.h"

#include <cstring>

namespace uw {

uint64_t ModelFingerprint(const Reconstruction& model) {
  uint64_t hash = 1469598103934665603ull;
  const auto add = [&](const void* data, size_t size) {
    const unsigned char* bytes = static_cast<const unsigned char*>(data);
    for (size_t k = 0; k < size; ++k) {
      hash ^= bytes[k];
      hash *= 1099511628211ull;
    }
  };
  for (const Image& image : model.Images()) {
    add(&image.image_id, sizeof(image.image_id));
    add(&image.camera_id, sizeof(image.camera_id));
    add(image.name.data(), image.name.size());
  }
  for (const Point3D& point : model.Points3D()) {
    const uint64_t track = point.track.size();
    add(&point.point3D_id, sizeof(point.point3D_id));
    add(&track, sizeof(track));
  }
  return hash;
}

void WriteModelFileHead(const char (&magic)[8], const Reconstruction& model,
                        std::ostream& out) {
  out.write(magic, sizeof(magic));
  PutValue<uint64_t>(out, ModelFingerprint(model));
}

std::ifstream OpenModelFile(const std::filesystem::path& path,
                            const char (&magic)[8], const std::string& kind,
                            const Reconstruction& model) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ErrorAt(path.string(), ": cannot open");
  char head[8];
  in.read(head, sizeof(head));
  if (!in || std::memcmp(head, magic, sizeof(head)) != 0) {
    throw ErrorAt(path.string(), ": not a uwmetric ", kind);
  }
  uint64_t fingerprint = 0;
  in.read(reinterpret_cast<char*>(&fingerprint), sizeof(fingerprint));
  if (!in || fingerprint != ModelFingerprint(model)) {
    throw ErrorAt(path.string(), ": the ", kind,
                  " belongs to another model (its images or points differ "
                  "from this one's)");
  }
  return in;
}

}  // namespace uw
