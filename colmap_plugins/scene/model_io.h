// Reading and writing COLMAP sparse models (.bin and .txt), in the COLMAP
// 3.x layout (cameras, images, points3D) and the 4.x layout (+ rigs,
// frames). Formats: COLMAP's doc/format.rst and scene/reconstruction_io_*.cc.
//
// Every reader validates what it reads and throws uw::Error naming the file
// and the position (byte offset for .bin, line for .txt) of the first
// problem. Writers write every file of a model to a temporary name first and
// rename them only when all succeeded, so a failure leaves nothing behind.
#pragma once

#include <filesystem>

#include "colmap_plugins/scene/model.h"

namespace uw {

struct ModelFiles {
  ModelFormat format = ModelFormat::kBinary;
  ModelLayout layout = ModelLayout::kColmap3;
};

// Which model a directory holds. Like COLMAP, a complete binary model wins
// over a text model. Throws uw::Error when neither is complete.
ModelFiles DetectModelFiles(const std::filesystem::path& dir);

Reconstruction ReadModel(const std::filesystem::path& dir);
Reconstruction ReadModelBinary(const std::filesystem::path& dir,
                               ModelLayout layout);
Reconstruction ReadModelText(const std::filesystem::path& dir,
                             ModelLayout layout);

// Writes the layout the model was read in (reconstruction.layout).
void WriteModel(const Reconstruction& reconstruction,
                const std::filesystem::path& dir, ModelFormat format);

// Text of each file exactly as COLMAP's writer formats it (3.8 for the
// 3.x layout); exposed for tests and for writing to other places.
std::string CamerasText(const Reconstruction& reconstruction);
std::string ImagesText(const Reconstruction& reconstruction);
std::string Points3DText(const Reconstruction& reconstruction);
std::string RigsText(const Reconstruction& reconstruction);
std::string FramesText(const Reconstruction& reconstruction);

std::string CamerasBinary(const Reconstruction& reconstruction);
std::string ImagesBinary(const Reconstruction& reconstruction);
std::string Points3DBinary(const Reconstruction& reconstruction);
std::string RigsBinary(const Reconstruction& reconstruction);
std::string FramesBinary(const Reconstruction& reconstruction);

// Parsers over a file's whole content; `source` names the file in errors.
void ParseCamerasBinary(const std::string& data, const std::string& source,
                        Reconstruction* reconstruction);
void ParseImagesBinary(const std::string& data, const std::string& source,
                       Reconstruction* reconstruction);
void ParsePoints3DBinary(const std::string& data, const std::string& source,
                         Reconstruction* reconstruction);
void ParseRigsBinary(const std::string& data, const std::string& source,
                     Reconstruction* reconstruction);
void ParseFramesBinary(const std::string& data, const std::string& source,
                       Reconstruction* reconstruction);
void ParseCamerasText(const std::string& data, const std::string& source,
                      Reconstruction* reconstruction);
void ParseImagesText(const std::string& data, const std::string& source,
                     Reconstruction* reconstruction);
void ParsePoints3DText(const std::string& data, const std::string& source,
                       Reconstruction* reconstruction);
void ParseRigsText(const std::string& data, const std::string& source,
                   Reconstruction* reconstruction);
void ParseFramesText(const std::string& data, const std::string& source,
                     Reconstruction* reconstruction);

}  // namespace uw
