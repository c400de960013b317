// Binary files that belong to one model (covariance.bin, samples.bin): an
// 8-byte magic, the model's fingerprint, then little-endian values as the
// machine holds them. A file of another model, or of the same model
// adjusted since, must be refused, not read as if it were this one's.
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <ostream>
#include <string>

#include "colmap_plugins/scene/model.h"
#include "common/util/error.h"

namespace uw {

// FNV-1a over the model's structure: which images (ids, names, cameras) and
// points (ids, track lengths) a file belongs to.
uint64_t ModelFingerprint(const Reconstruction& model);

void WriteModelFileHead(const char (&magic)[8], const Reconstruction& model,
                        std::ostream& out);

// Opens `path` and reads its head; throws uw::Error naming the file when it
// is not a `kind` ("covariance sidecar") or belongs to another model.
std::ifstream OpenModelFile(const std::filesystem::path& path,
                            const char (&magic)[8], const std::string& kind,
                            const Reconstruction& model);

template <typename T>
void PutValue(std::ostream& out, const T& value) {
  out.write(reinterpret_cast<const char*>(&value), sizeof(T));
}

template <typename T>
void PutValues(std::ostream& out, const T* data, size_t count) {
  out.write(reinterpret_cast<const char*>(data), sizeof(T) * count);
}

// Throws uw::Error "PATH: truncated" at the end of the file.
template <typename T>
void GetValues(std::istream& in, const std::filesystem::path& path, T* data,
               size_t count) {
  in.read(reinterpret_cast<char*>(data), sizeof(T) * count);
  if (!in) throw ErrorAt(path.string(), ": truncated");
}

template <typename T>
T GetValue(std::istream& in, const std::filesystem::path& path) {
  T value;
  GetValues(in, path, &value, 1);
  return value;
}

}  // namespace uw
