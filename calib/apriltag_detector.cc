#include "calib/apriltag_detector.h"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <memory>

#include <apriltag/apriltag.h>
#include <apriltag/tag16h5.h>
#include <apriltag/tag25h9.h>
#include <apriltag/tag36h10.h>
#include <apriltag/tag36h11.h>
#include <apriltag/tagCircle21h7.h>
#include <apriltag/tagCircle49h12.h>
#include <apriltag/tagCustom48h12.h>
#include <apriltag/tagStandard41h12.h>
#include <apriltag/tagStandard52h13.h>

#include "calib/grey_image.h"
#include "common/util/error.h"

namespace uw {
namespace {

struct FamilyFunctions {
  const char* name;
  apriltag_family_t* (*create)();
  void (*destroy)(apriltag_family_t*);
};

const FamilyFunctions kFamilies[] = {
    {"tag16h5", tag16h5_create, tag16h5_destroy},
    {"tag25h9", tag25h9_create, tag25h9_destroy},
    {"tag36h10", tag36h10_create, tag36h10_destroy},
    {"tag36h11", tag36h11_create, tag36h11_destroy},
    {"tagCircle21h7", tagCircle21h7_create, tagCircle21h7_destroy},
    {"tagCircle49h12", tagCircle49h12_create, tagCircle49h12_destroy},
    {"tagCustom48h12", tagCustom48h12_create, tagCustom48h12_destroy},
    {"tagStandard41h12", tagStandard41h12_create, tagStandard41h12_destroy},
    {"tagStandard52h13", tagStandard52h13_create, tagStandard52h13_destroy},
};

const FamilyFunctions& FindFamily(const std::string& name) {
  for (const FamilyFunctions& family : kFamilies) {
    if (name == family.name) return family;
  }
  std::string known;
  for (const FamilyFunctions& family : kFamilies) {
    known += std::string(known.empty() ? "" : ", ") + family.name;
  }
  throw ErrorAt("AprilTag family '", name, "' is not one of libapriltag's (",
                known, ")");
}

// A family and, for a wider border, the same codes with every bit one cell
// further in per extra border cell: libapriltag samples the border ring at
// width_at_border and the bits at bit_x/bit_y, nothing else.
class Family {
 public:
  Family(const FamilyFunctions& functions, int border_cells)
      : functions_(functions), stock_(functions.create()) {
    if (border_cells == 1) {
      family_ = stock_;
      return;
    }
    if (stock_->reversed_border) {
      throw ErrorAt("AprilTag family ", functions.name,
                    " has its border inside; it has no wider-border variant");
    }
    const int extra = border_cells - 1;
    wide_ = *stock_;
    wide_.width_at_border = stock_->width_at_border + 2 * extra;
    wide_.total_width = stock_->total_width + 2 * extra;
    bit_x_.resize(stock_->nbits);
    bit_y_.resize(stock_->nbits);
    for (uint32_t i = 0; i < stock_->nbits; ++i) {
      bit_x_[i] = stock_->bit_x[i] + extra;
      bit_y_[i] = stock_->bit_y[i] + extra;
    }
    wide_.bit_x = bit_x_.data();
    wide_.bit_y = bit_y_.data();
    wide_.impl = nullptr;
    family_ = &wide_;
  }
  ~Family() { functions_.destroy(stock_); }
  Family(const Family&) = delete;
  Family& operator=(const Family&) = delete;

  apriltag_family_t* get() { return family_; }

 private:
  const FamilyFunctions& functions_;
  apriltag_family_t* stock_;
  apriltag_family_t wide_{};
  std::vector<uint32_t> bit_x_;
  std::vector<uint32_t> bit_y_;
  apriltag_family_t* family_ = nullptr;
};

}  // namespace

void AprilTagOptions::Check() const {
  FindFamily(family);
  if (border_cells < 1 || border_cells > 3) {
    throw Error("AprilTag options: border_cells must be 1, 2 or 3");
  }
  if (!(quad_decimate >= 1.0)) {
    throw Error("AprilTag options: quad_decimate must be >= 1");
  }
  if (max_hamming < 0 || max_hamming > 2) {
    throw Error("AprilTag options: max_hamming must be 0, 1 or 2");
  }
}

std::vector<AprilTagDetection> DetectAprilTags(const cv::Mat& image,
                                               const AprilTagOptions& options) {
  options.Check();
  const cv::Mat grey = GreyImage(image, "DetectAprilTags");
  // The family lives until the detector is gone: the detector keeps
  // decoding tables in it.
  Family family(FindFamily(options.family), options.border_cells);
  std::unique_ptr<apriltag_detector_t, void (*)(apriltag_detector_t*)> detector(
      apriltag_detector_create(), apriltag_detector_destroy);
  apriltag_detector_add_family_bits(detector.get(), family.get(),
                                    options.max_hamming);
  detector->quad_decimate = static_cast<float>(options.quad_decimate);
  detector->refine_edges = options.refine_edges;
  detector->nthreads = std::max(options.num_threads, 1);
  image_u8_t frame{grey.cols, grey.rows, static_cast<int32_t>(grey.step[0]),
                   grey.data};
  zarray_t* found = apriltag_detector_detect(detector.get(), &frame);
  std::vector<AprilTagDetection> tags;
  for (int i = 0; i < zarray_size(found); ++i) {
    apriltag_detection_t* detection = nullptr;
    zarray_get(found, i, &detection);
    AprilTagDetection tag;
    tag.id = detection->id;
    tag.hamming = detection->hamming;
    tag.decision_margin = detection->decision_margin;
    for (int k = 0; k < 4; ++k) {
      // libapriltag's (0, 0) is the top-left pixel's corner.
      tag.corners[k] =
          Eigen::Vector2d(detection->p[k][0] - 0.5, detection->p[k][1] - 0.5);
    }
    tags.push_back(tag);
  }
  apriltag_detections_destroy(found);
  std::sort(tags.begin(), tags.end(),
            [](const AprilTagDetection& a, const AprilTagDetection& b) {
              if (a.id != b.id) return a.id < b.id;
              return std::make_pair(a.corners[0].x(), a.corners[0].y()) <
                     std::make_pair(b.corners[0].x(), b.corners[0].y());
            });
  return tags;
}

}  // namespace uw
