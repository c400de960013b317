// The detector a board's kind calls for, on one image or on every image of
// a folder (what uwcalib detect writes as corners.vnl).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "calib/board.h"
#include "calib/corners_vnl.h"

namespace uw {

// DetectChessboard, DetectAprilGrid or DetectCharuco with their default
// options, by board.kind.
BoardObservation DetectBoardCorners(const cv::Mat& image,
                                    const CalibrationBoard& board,
                                    const std::string& image_name);

// The board in each image `names` of `images_dir`, read as 8-bit grey, in
// parallel on num_threads threads (<= 0: all); the observations in the
// order of `names`, an image without the board as one not Found(). The
// detectors are deterministic, so the thread count does not change them.
// `progress(done, total)` is called once an image is done, from the worker
// threads. Throws uw::Error naming the image for a name with white space
// (corners.vnl cannot hold it; nothing is read then) or an image that
// cannot be read.
std::vector<BoardObservation> DetectBoardInImages(
    const std::string& images_dir, const std::vector<std::string>& names,
    const CalibrationBoard& board, int num_threads,
    const std::function<void(int done, int total)>& progress = nullptr);

}  // namespace uw
