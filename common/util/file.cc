#include "common/util/file.h"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <sstream>

#include "common/util/error.h"

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
  // Folders this call creates are removed again on failure, deepest first,
  // so that a failed write leaves the file system as it was.
  std::vector<std::filesystem::path> created_dirs;
  try {
    for (const PendingFile& file : files) {
      for (std::filesystem::path dir = file.path.parent_path();
           !dir.empty() && !std::filesystem::exists(dir);
           dir = dir.parent_path()) {
        created_dirs.push_back(dir);
      }
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
    std::sort(created_dirs.begin(), created_dirs.end(),
              [](const auto& a, const auto& b) {
                return a.string().size() > b.string().size();
              });
    for (const auto& dir : created_dirs) RemoveQuietly(dir);
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

bool IsImageFile(const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return extension == ".png" || extension == ".jpg" || extension == ".jpeg" ||
         extension == ".tif" || extension == ".tiff";
}

std::vector<std::string> ListImages(
    const std::filesystem::path& images_dir, const std::string& image_list_path,
    const std::function<bool(const std::string&)>& keep, bool recursive) {
  std::vector<std::string> names;
  if (!image_list_path.empty()) {
    std::ifstream in(image_list_path);
    if (!in) throw ErrorAt(image_list_path, ": cannot open");
    std::string line;
    while (std::getline(in, line)) {
      if (!line.empty() && line.back() == '\r') line.pop_back();
      if (!line.empty()) names.push_back(line);
    }
    if (names.empty()) throw ErrorAt(image_list_path, ": no images listed");
    return names;
  }
  std::error_code error;
  const auto add = [&](const std::filesystem::directory_entry& entry) {
    const std::string name =
        entry.path().lexically_relative(images_dir).generic_string();
    if (entry.is_regular_file() && IsImageFile(entry.path()) &&
        (!keep || keep(name))) {
      names.push_back(name);
    }
  };
  if (recursive) {
    for (const auto& entry :
         std::filesystem::recursive_directory_iterator(images_dir, error)) {
      add(entry);
    }
  } else {
    for (const auto& entry :
         std::filesystem::directory_iterator(images_dir, error)) {
      add(entry);
    }
  }
  if (error) {
    throw ErrorAt(images_dir.string(), ": cannot list: ", error.message());
  }
  if (names.empty()) throw ErrorAt(images_dir.string(), ": no images");
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace uw
