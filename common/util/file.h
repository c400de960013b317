// Writing files so that an interrupted or failed run never leaves a half
// written output behind (DESIGN.md §4): content goes to a temporary sibling
// and is renamed into place only once every file of a set is complete.
#pragma once

#include <filesystem>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

namespace uw {

// One output file: its final path and the function that writes its content.
struct PendingFile {
  std::filesystem::path path;
  std::function<void(std::ostream&)> write;
};

// Writes every file to "<path>.tmp-<pid>" first; if any writer throws or a
// stream fails, all temporaries are removed, no final file is touched and
// the error propagates. Otherwise the temporaries are renamed into place.
// Parent directories are created as needed.
void WriteFilesAtomically(const std::vector<PendingFile>& files, bool binary);

// Reads a whole file; throws uw::Error naming the path if it cannot.
std::string ReadFileToString(const std::filesystem::path& path);

// Whether the name ends like an image file (.png .jpg .jpeg .tif .tiff, any
// case).
bool IsImageFile(const std::filesystem::path& path);

// The images a command processes, named relative to images_dir: the
// non-empty lines of image_list_path if given (as colmap's
// --image_list_path), else every image file directly in images_dir (or,
// `recursive`, below it, named "cam1/0001.png" as COLMAP names them) for
// which `keep` (if any) is true, sorted. Throws uw::Error when none.
std::vector<std::string> ListImages(
    const std::filesystem::path& images_dir, const std::string& image_list_path,
    const std::function<bool(const std::string&)>& keep = nullptr,
    bool recursive = false);

}  // namespace uw
