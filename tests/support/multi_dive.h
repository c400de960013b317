// A multi-dive uwsim survey fused by `uwcolmap bundle_adjuster
// --Dive.offsets 1` with default flags, and what it found against uwsim's
// truth (issue 17, acceptance 3): the default test on two worlds and the
// heavy matrix over every world and several seeds share it.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace uw::testing {

struct MultiDiveChain {
  int exit_code = -1;
  std::string output;
  std::filesystem::path output_dir;  // bundle_adjuster's --output_path
  std::string termination;           // ba_report.json's, "" without a report
  int iterations = 0;
  // RMS per axis of the logged navigation minus the truth minus the dive's
  // bias (what the navigation's noise really was), m.
  double realised_nav_m = 0.0;
  double nav_sigma_m = 0.0;  // --Nav.weight auto's estimate, 0 without
  // Per non-reference dive: its offset minus the true one (the offset is
  // added to the dive's navigation: -(its bias - the reference's)), and
  // the offset's sigma, m per axis; no sigma: NaN.
  std::vector<int> dives;
  std::vector<Eigen::Vector3d> offset_errors;
  std::vector<Eigen::Vector3d> offset_sigmas;
  // The offset minus the ideal estimate's: the joint least-squares fit of
  // a similarity and the offsets (similarity_with_offsets.h) of the true
  // vehicle positions to the logged ones of the registered images,
  // weighted by the stated sigmas. It is what the logs allow: a dive's
  // mean navigation error (a drift over a long dive) moves it from the
  // bias uwsim applied, and no estimator can tell the two apart.
  std::vector<Eigen::Vector3d> ideal_offset_errors;
  std::vector<std::string> warnings;
};

// uwsim generate --survey multi_dive with `config` (a JSON file), uwsim
// observe (0.5 px, `num_points`), then the adjustment (fixed intrinsics,
// the survey's camera mount), all under `dir`. Binaries from `bin_dir`.
MultiDiveChain RunMultiDiveChain(const std::filesystem::path& bin_dir,
                                 const std::filesystem::path& config,
                                 const std::filesystem::path& dir,
                                 int num_points = 5000);

}  // namespace uw::testing
