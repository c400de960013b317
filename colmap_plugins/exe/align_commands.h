// uwcolmap model_aligner / model_comparer: a model moved onto navigation or
// reference positions by a similarity, and a model measured against another
// model or uwsim's truth (colmap_plugins/align).
#pragma once

#include <filesystem>
#include <string>

#include "colmap_plugins/align/mesh_comparison.h"
#include "colmap_plugins/align/model_alignment.h"
#include "colmap_plugins/align/model_comparison.h"
#include "common/cli/command.h"

namespace uw {

struct ModelAlignerOptions {
  std::string input_path;
  std::string output_path;  // the aligned model, in the input's format
  ModelAlignmentOptions alignment;
  std::string transform_path;  // also the alignment JSON, if given
  // colmap model_aligner's --alignment_type: custom, or enu with
  // --ref_is_gps 1 (the frame it aligns into); plane and ecef are colmap's
  // only.
  std::string alignment_type = "custom";

  // The colmap flags uwcolmap supports (--ref_is_gps 1 only with
  // --alignment_type enu), the alignment's rules, and an output folder that
  // is not the input.
  void Check() const;
};
Subcommand ModelAlignerCommand();

// --alignment of model_comparer.
enum class ComparisonAlignment {
  kSimilarity,  // the model's centres aligned to the reference's
  kRigid,       // without scale
  kNone,        // compared in place (absolute errors)
};

struct ModelComparerOptions {
  std::string input_path;
  // Exactly one reference: a model, or uwsim's output folder (truth/ and
  // truth/mesh.ply).
  std::string ref_path;
  std::string truth_dir;
  std::string mesh_path;        // the reference surface, in its frame
  std::string dense_mesh_path;  // the model's dense surface, in its frame
  std::string output_path;      // also the figures as JSON, if given
  ComparisonAlignment alignment = ComparisonAlignment::kSimilarity;
  // align and alignment.estimate_scale follow `alignment` (Comparison()).
  ModelComparisonOptions comparison;
  MeshComparisonOptions dense;
  // Range within which an image sees the truth (dense.max_range_m): < 0,
  // uwsim's visible range from --truth_dir's truth/sim.json when it states
  // one, else any range; 0: any range.
  double dense_max_range_m = -1.0;

  std::filesystem::path ReferencePath() const;
  // `dense` with the range resolved.
  MeshComparisonOptions Dense() const;
  // The reference surface: --mesh_path, else truth/mesh.ply of --truth_dir;
  // empty without either.
  std::string SurfacePath() const;
  ModelComparisonOptions Comparison() const;
  // One reference, a reference surface for a dense mesh, the comparisons'
  // own rules.
  void Check() const;
};
Subcommand ModelComparerCommand();

}  // namespace uw
