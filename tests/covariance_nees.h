// The covariance's calibration check of issue 16, acceptance 2, shared by
// the seafloor survey's test (covariance_nees_test.cc) and the other
// worlds' (covariance_nees_worlds_test.cc): re-adjustments of a uwsim survey
// from fresh synthetic tracks and navigation noise, and the mean NEES of the
// covariance they report against the truth.
#pragma once

#include <filesystem>

namespace uw::testing {

constexpr int kNeesTrials = 100;

struct Nees {
  double pose = 0.0;   // mean over estimated poses; 6 when calibrated
  double point = 0.0;  // mean over points; 3 when calibrated
};

// kNeesTrials re-adjustments of the survey in `sim_dir`, each observing
// `points_observed` points; `fused`: with the noisy navigation (gauge: the
// priors), otherwise without (gauge: held, the first image's pose and one
// coordinate of the second's translation, which start at the truth and so
// put the estimate in the truth's datum); `attitude` (fused only): the
// log's roll, pitch and yaw as priors too, with fresh noise of their stated
// sigmas.
Nees MeanNees(const std::filesystem::path& sim_dir, bool fused,
              int points_observed, bool attitude = false);

// Within 10 % of the dimension: a covariance too small or too large by 10 %
// in variance fails.
void ExpectCalibrated(const Nees& nees);

}  // namespace uw::testing
