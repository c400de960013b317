#include "colmap_plugins/util/file.h"

#include <unistd.h>

#include <fstream>
#include <sstream>

#include "colmap_plugins/util/error.h"

namespace uw {
namespace {

std::filesystem::path TemporaryPathFor(const std::filesystem::path& path) {
  return path.string() + ".tmp-" + std::to_string(::getpid());
}

void RemoveQuietly(const std::filesystem::path& path) {
  std::error_code ignored;
  std::filesystem::remove(path, ignored);
}

}  // namespace

void WriteFilesAtomically(const std::vector<PendingFile>& files,
                          const bool binary) {
  std::vector<std::filesystem::path> written;
  try {
    for (const PendingFile& file : files) {
      if (file.path.has_parent_path()) {
        std::filesystem::create_directories(file.path.parent_path());
      }
      const std::filesystem::path tmp = TemporaryPathFor(file.path);
      written.push_back(tmp);
      std::ofstream stream(
          tmp, binary ? std::ios::binary | std::ios::trunc : std::ios::trunc);
      if (!stream) {
        throw ErrorAt(file.path.string(), ": cannot open for writing");
      }
      file.write(stream);
      stream.flush();
      if (!stream) {
        throw ErrorAt(file.path.string(), ": write failed (disk full?)");
      }
    }
    // Renaming a file over a directory fails; find that before the first
    // rename so that a set is never installed halfway.
    for (const PendingFile& file : files) {
      if (std::filesystem::is_directory(file.path)) {
        throw ErrorAt(file.path.string(),
                      ": is a directory, cannot replace it with a file");
      }
    }
  } catch (...) {
    for (const auto& tmp : written) RemoveQuietly(tmp);
    throw;
  }
  for (size_t i = 0; i < files.size(); ++i) {
    std::filesystem::rename(written[i], files[i].path);
  }
}

std::string ReadFileToString(const std::filesystem::path& path) {
  std::ifstream stream(path, std::ios::binary);
  if (!stream) {
    throw ErrorAt(path.string(), ": cannot open for reading");
  }
  std::ostringstream content;
  content << stream.rdbuf();
  return content.str();
}

}  // namespace uw
