#include "colmap_plugins/scene/model_io.h"

#include <algorithm>

#include "common/util/error.h"
#include "common/util/file.h"

namespace uw {
namespace {

namespace fs = std::filesystem;

bool HasAll(const fs::path& dir, const std::vector<std::string>& names) {
  for (const std::string& name : names) {
    if (!fs::is_regular_file(dir / name)) return false;
  }
  return true;
}

bool HasAny(const fs::path& dir, const std::vector<std::string>& names) {
  for (const std::string& name : names) {
    if (fs::exists(dir / name)) return true;
  }
  return false;
}

std::vector<std::string> FileNames(const std::string& extension) {
  return {"cameras" + extension, "images" + extension, "points3D" + extension};
}

std::vector<std::string> RigFileNames(const std::string& extension) {
  return {"rigs" + extension, "frames" + extension};
}

ModelLayout DetectLayout(const fs::path& dir, const std::string& extension) {
  if (HasAll(dir, RigFileNames(extension))) return ModelLayout::kColmap4;
  if (HasAny(dir, RigFileNames(extension))) {
    throw ErrorAt(dir.string(), ": has only one of rigs", extension,
                  " and frames", extension, "; a COLMAP 4.x model needs both");
  }
  return ModelLayout::kColmap3;
}

using Parser = void (*)(const std::string&, const std::string&,
                        Reconstruction*);

void ParseFile(const fs::path& path, Parser parser,
               Reconstruction* reconstruction) {
  parser(ReadFileToString(path), path.string(), reconstruction);
}

}  // namespace

ModelFiles DetectModelFiles(const fs::path& dir) {
  if (!fs::is_directory(dir)) {
    throw ErrorAt(dir.string(),
                  ": not a directory (expected a COLMAP model "
                  "folder such as sparse/0)");
  }
  if (HasAll(dir, FileNames(".bin"))) {
    return {ModelFormat::kBinary, DetectLayout(dir, ".bin")};
  }
  if (HasAll(dir, FileNames(".txt"))) {
    return {ModelFormat::kText, DetectLayout(dir, ".txt")};
  }
  throw ErrorAt(dir.string(),
                ": no complete COLMAP model (need cameras, images and "
                "points3D, all .bin or all .txt)");
}

Reconstruction ReadModel(const fs::path& dir) {
  const ModelFiles files = DetectModelFiles(dir);
  return files.format == ModelFormat::kBinary
             ? ReadModelBinary(dir, files.layout)
             : ReadModelText(dir, files.layout);
}

Reconstruction ReadModelBinary(const fs::path& dir, const ModelLayout layout) {
  Reconstruction reconstruction;
  reconstruction.layout = layout;
  if (layout == ModelLayout::kColmap4) {
    ParseFile(dir / "rigs.bin", ParseRigsBinary, &reconstruction);
  }
  ParseFile(dir / "cameras.bin", ParseCamerasBinary, &reconstruction);
  if (layout == ModelLayout::kColmap4) {
    ParseFile(dir / "frames.bin", ParseFramesBinary, &reconstruction);
  }
  ParseFile(dir / "images.bin", ParseImagesBinary, &reconstruction);
  ParseFile(dir / "points3D.bin", ParsePoints3DBinary, &reconstruction);
  reconstruction.Check(dir.string());
  return reconstruction;
}

Reconstruction ReadModelText(const fs::path& dir, const ModelLayout layout) {
  Reconstruction reconstruction;
  reconstruction.layout = layout;
  if (layout == ModelLayout::kColmap4) {
    ParseFile(dir / "rigs.txt", ParseRigsText, &reconstruction);
  }
  ParseFile(dir / "cameras.txt", ParseCamerasText, &reconstruction);
  if (layout == ModelLayout::kColmap4) {
    ParseFile(dir / "frames.txt", ParseFramesText, &reconstruction);
  }
  ParseFile(dir / "images.txt", ParseImagesText, &reconstruction);
  ParseFile(dir / "points3D.txt", ParsePoints3DText, &reconstruction);
  reconstruction.Check(dir.string());
  return reconstruction;
}

void WriteModel(const Reconstruction& reconstruction, const fs::path& dir,
                const ModelFormat format) {
  using Writer = std::string (*)(const Reconstruction&);
  struct Part {
    const char* stem;
    Writer binary;
    Writer text;
  };
  std::vector<Part> parts = {{"cameras", CamerasBinary, CamerasText},
                             {"images", ImagesBinary, ImagesText},
                             {"points3D", Points3DBinary, Points3DText}};
  if (reconstruction.layout == ModelLayout::kColmap4) {
    parts.push_back({"rigs", RigsBinary, RigsText});
    parts.push_back({"frames", FramesBinary, FramesText});
  }
  const bool binary = format == ModelFormat::kBinary;
  // Files of another model left in the folder (the other format, or rigs
  // and frames of a 4.x model when writing 3.x) would be read together with
  // ours, so refuse rather than produce a mixed model.
  for (const std::string extension : {".bin", ".txt"}) {
    for (const char* stem :
         {"cameras", "images", "points3D", "rigs", "frames"}) {
      const bool ours =
          extension == (binary ? ".bin" : ".txt") &&
          std::any_of(parts.begin(), parts.end(), [&](const Part& part) {
            return std::string(part.stem) == stem;
          });
      const fs::path path = dir / (std::string(stem) + extension);
      if (!ours && fs::exists(path)) {
        throw ErrorAt(path.string(),
                      ": belongs to another model; write into an empty "
                      "folder or remove it first");
      }
    }
  }
  std::vector<PendingFile> files;
  for (const Part& part : parts) {
    const Writer writer = binary ? part.binary : part.text;
    files.push_back(
        {dir / (std::string(part.stem) + (binary ? ".bin" : ".txt")),
         [writer, &reconstruction](std::ostream& stream) {
           const std::string content = writer(reconstruction);
           stream.write(content.data(), content.size());
         }});
  }
  WriteFilesAtomically(files, binary);
}

}  // namespace uw
