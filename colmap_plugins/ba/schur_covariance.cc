#include "colmap_plugins/ba/schur_covariance.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <numeric>
#include <unordered_set>

#include <ceres/ceres.h>
#include <cholmod.h>
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <Eigen/SparseCore>

#include "common/util/error.h"
#include "common/util/random.h"

namespace uw {

void SchurCovarianceOptions::Check() const {
  if (null_space_reduced.empty() && !null_space_points.empty()) {
    throw ErrorAt("a null space needs rows for the reduced variables");
  }
  if (!(min_reciprocal_condition >= 0.0 && min_reciprocal_condition < 1.0)) {
    throw ErrorAt("min_reciprocal_condition must be in [0, 1)");
  }
  if (num_samples < 0) {
    throw ErrorAt("num_samples must be >= 0, got ", num_samples);
  }
  if (num_threads < 1) {
    throw ErrorAt("num_threads must be >= 1, got ", num_threads);
  }
}

namespace {

using Clock = std::chrono::steady_clock;

double Seconds(Clock::time_point since) {
  return std::chrono::duration<double>(Clock::now() - since).count();
}

// A column of the Jacobian: which variable and which of its coordinates.
struct ColumnOwner {
  int reduced = -1;  // reduced variable, or -1 for a point's
  int local = 0;     // coordinate within the variable (full tangent)
  int kept = -1;     // index in S (reduced coordinates not held), or -1
};

struct CholmodDeleter {
  cholmod_common* common;
  void operator()(cholmod_factor* factor) const {
    cholmod_free_factor(&factor, common);
  }
  void operator()(cholmod_sparse* matrix) const {
    cholmod_free_sparse(&matrix, common);
  }
  void operator()(cholmod_dense* matrix) const {
    cholmod_free_dense(&matrix, common);
  }
};

// RAII for CHOLMOD's workspace; its messages are ours to give.
class CholmodCommon {
 public:
  CholmodCommon() {
    cholmod_start(&common_);
    common_.print = 0;
    common_.error_handler = nullptr;
    common_.supernodal = CHOLMOD_SUPERNODAL;
    // AMD alone: deterministic and quick to analyse; the camera graphs of
    // surveys are near-planar, where it fills little more than METIS.
    common_.nmethods = 1;
    common_.method[0].ordering = CHOLMOD_AMD;
    common_.postorder = 1;
  }
  ~CholmodCommon() { cholmod_finish(&common_); }
  CholmodCommon(const CholmodCommon&) = delete;
  CholmodCommon& operator=(const CholmodCommon&) = delete;
  cholmod_common* get() { return &common_; }

 private:
  cholmod_common common_;
};

// Z = S^-1 on the pattern of the supernodal factor S = L L^T.
class SparseInverse {
 public:
  SparseInverse(const cholmod_factor& factor) : factor_(factor) {
    const int n = static_cast<int>(factor.n);
    const int* super = static_cast<const int*>(factor.super);
    column_super_.resize(n);
    for (size_t s = 0; s < factor.nsuper; ++s) {
      for (int c = super[s]; c < super[s + 1]; ++c) {
        column_super_[c] = static_cast<int>(s);
      }
    }
    const int* perm = static_cast<const int*>(factor.Perm);
    inverse_perm_.resize(n);
    for (int k = 0; k < n; ++k) inverse_perm_[perm[k]] = k;
    values_.assign(factor.xsize, 0.0);
    CheckSortedRows();
    Recurse();
  }

  // S^-1 at original coordinates (i, j), which must lie on the pattern.
  double At(int i, int j) const {
    int p = inverse_perm_[i];
    int q = inverse_perm_[j];
    if (p < q) std::swap(p, q);
    const int t = column_super_[q];
    const int* super = static_cast<const int*>(factor_.super);
    const int* pi = static_cast<const int*>(factor_.pi);
    const int* px = static_cast<const int*>(factor_.px);
    const int* rows = static_cast<const int*>(factor_.s) + pi[t];
    const int num_rows = pi[t + 1] - pi[t];
    const int* found = std::lower_bound(rows, rows + num_rows, p);
    if (found == rows + num_rows || *found != p) {
      throw ErrorAt("internal: covariance entry (", i, ", ", j,
                    ") is off the factor's pattern");
    }
    return values_[px[t] + (found - rows) +
                   static_cast<size_t>(q - super[t]) * num_rows];
  }

 private:
  void CheckSortedRows() const {
    const int* pi = static_cast<const int*>(factor_.pi);
    const int* rows = static_cast<const int*>(factor_.s);
    for (size_t s = 0; s < factor_.nsuper; ++s) {
      if (!std::is_sorted(rows + pi[s], rows + pi[s + 1])) {
        throw ErrorAt("internal: CHOLMOD's supernode rows are not sorted");
      }
    }
  }

  // With Z L = L^-T (upper triangular) and, for a supernode of columns J
  // and rows I below them:
  //   Z_IJ = -Z_II L_IJ L_JJ^-1,   Z_JJ = (L_JJ^-T - Z_IJ^T L_IJ) L_JJ^-1.
  // Z_II lies on the pattern of later supernodes (the rows of a column form
  // a clique of the filled graph), which the reverse order has done.
  void Recurse() {
    const int* super = static_cast<const int*>(factor_.super);
    const int* pi = static_cast<const int*>(factor_.pi);
    const int* px = static_cast<const int*>(factor_.px);
    const int* all_rows = static_cast<const int*>(factor_.s);
    const double* lx = static_cast<const double*>(factor_.x);
    for (int s = static_cast<int>(factor_.nsuper) - 1; s >= 0; --s) {
      const int num_cols = super[s + 1] - super[s];
      const int num_rows = pi[s + 1] - pi[s];
      const int num_below = num_rows - num_cols;
      const int* rows = all_rows + pi[s];
      const Eigen::Map<const Eigen::MatrixXd> l(lx + px[s], num_rows, num_cols);
      const Eigen::MatrixXd l_jj = l.topRows(num_cols);
      Eigen::MatrixXd z_jj =
          Eigen::MatrixXd::Identity(num_cols, num_cols);  // -> L_JJ^-T
      l_jj.transpose().triangularView<Eigen::Upper>().solveInPlace(z_jj);
      Eigen::MatrixXd z_ij;
      if (num_below > 0) {
        const Eigen::MatrixXd z_ii = GatherBelow(rows + num_cols, num_below);
        z_ij =
            -(z_ii.selfadjointView<Eigen::Lower>() * l.bottomRows(num_below));
        l_jj.triangularView<Eigen::Lower>().solveInPlace<Eigen::OnTheRight>(
            z_ij);
        z_jj.noalias() -= z_ij.transpose() * l.bottomRows(num_below);
      }
      l_jj.triangularView<Eigen::Lower>().solveInPlace<Eigen::OnTheRight>(z_jj);
      Eigen::Map<Eigen::MatrixXd> z(values_.data() + px[s], num_rows, num_cols);
      z.topRows(num_cols) = 0.5 * (z_jj + z_jj.transpose());
      if (num_below > 0) z.bottomRows(num_below) = z_ij;
    }
  }

  // Z at rows x rows (lower triangle) for sorted `rows` of later supernodes.
  Eigen::MatrixXd GatherBelow(const int* rows, int count) const {
    const int* super = static_cast<const int*>(factor_.super);
    const int* pi = static_cast<const int*>(factor_.pi);
    const int* px = static_cast<const int*>(factor_.px);
    const int* all_rows = static_cast<const int*>(factor_.s);
    Eigen::MatrixXd z(count, count);
    for (int b = 0; b < count; ++b) {
      const int column = rows[b];
      const int t = column_super_[column];
      const int local = column - super[t];
      const int* t_rows = all_rows + pi[t];
      const int t_num_rows = pi[t + 1] - pi[t];
      const double* t_values =
          values_.data() + px[t] + static_cast<size_t>(local) * t_num_rows;
      int position = local;  // the row equal to `column`
      for (int a = b; a < count; ++a) {
        while (position < t_num_rows && t_rows[position] < rows[a]) {
          ++position;
        }
        if (position == t_num_rows || t_rows[position] != rows[a]) {
          throw ErrorAt("internal: the factor's pattern is not closed");
        }
        z(a, b) = t_values[position];
      }
    }
    return z;
  }

  const cholmod_factor& factor_;
  std::vector<int> column_super_;
  std::vector<int> inverse_perm_;
  std::vector<double> values_;
};

// A point's coupling to one reduced variable: B_j's block (kept dims x 3).
struct PointCoupling {
  int reduced = 0;
  int point = 0;
  size_t offset = 0;  // into the coupling pool, column-major kept x 3
};
using PointBlock = Eigen::Matrix<double, Eigen::Dynamic, 3>;

// S's lower triangle by columns: variable b's column holds the blocks
// (a, b), a >= b, ascending in a, each column-major kept_a x kept_b at
// offsets[k] of values (S) and of inverse (S^-1 at the same entries). Lower,
// not upper: the variables many images share (intrinsics, offsets) come
// after the images, so each image's column carries its own pairs with them
// and the shared variables' columns stay short.
struct ReducedColumn {
  std::vector<int> rows;
  std::vector<size_t> offsets;
  std::vector<double> values;
  std::vector<double> inverse;
};

class Computation {
 public:
  Computation(ceres::Problem* problem,
              const std::vector<ReducedVariable>& reduced,
              const std::vector<EliminatedPoint>& points,
              const SchurCovarianceOptions& options)
      : problem_(problem),
        reduced_(reduced),
        points_(points),
        options_(options) {}

  SchurCovariance Run() {
    // Every parallel loop gives each output to one task, which sums in a
    // fixed order: the same bits for any thread count.
    tbb::task_arena arena(options_.num_threads);
    return arena.execute([&] { return RunInArena(); });
  }

 private:
  SchurCovariance RunInArena() {
    auto start = Clock::now();
    ListColumns();
    EvaluateJacobian();
    if (!options_.null_space_reduced.empty()) ChooseHeldCoordinates();
    ComputeKeptOffsets();
    ScaleColumns();
    result_.jacobian_time_s = Seconds(start);

    start = Clock::now();
    AssembleReducedSystem();
    result_.schur_time_s = Seconds(start);

    start = Clock::now();
    Factor();
    result_.factor_time_s = Seconds(start);

    start = Clock::now();
    const SparseInverse inverse(*factor_);
    ReadMarginals(inverse);
    if (gauge_dimension_ > 0) ProjectOntoGaugeComplement();
    if (options_.num_samples > 0) DrawSamples();
    result_.inverse_time_s = Seconds(start);
    return std::move(result_);
  }

  void ListColumns() {
    std::vector<double*> all;
    problem_->GetParameterBlocks(&all);
    std::unordered_set<const double*> listed;
    int column = 0;
    reduced_dim_.assign(reduced_.size(), 0);
    reduced_first_column_.assign(reduced_.size(), 0);
    for (size_t a = 0; a < reduced_.size(); ++a) {
      reduced_first_column_[a] = column;
      for (double* block : reduced_[a].blocks) {
        if (!problem_->HasParameterBlock(block)) {
          throw ErrorAt(reduced_[a].name, " has a block not in the problem");
        }
        listed.insert(block);
        if (problem_->IsParameterBlockConstant(block)) continue;
        CheckFinite(block, reduced_[a].name);
        const int size = problem_->ParameterBlockTangentSize(block);
        for (int k = 0; k < size; ++k) {
          owners_.push_back({static_cast<int>(a), reduced_dim_[a] + k});
        }
        reduced_dim_[a] += size;
        column += size;
        blocks_.push_back(block);
      }
    }
    num_reduced_columns_ = column;
    for (size_t j = 0; j < points_.size(); ++j) {
      double* block = points_[j].block;
      if (!problem_->HasParameterBlock(block) ||
          problem_->ParameterBlockSize(block) != 3 ||
          problem_->ParameterBlockTangentSize(block) != 3) {
        throw ErrorAt(points_[j].name, " is not a 3-vector of the problem");
      }
      listed.insert(block);
      if (problem_->IsParameterBlockConstant(block)) {
        throw ErrorAt(points_[j].name, " is constant; its covariance is 0");
      }
      CheckFinite(block, points_[j].name);
      for (int k = 0; k < 3; ++k) {
        owners_.push_back({-1, k});
      }
      blocks_.push_back(block);
    }
    for (double* block : all) {
      if (listed.count(block) == 0 &&
          !problem_->IsParameterBlockConstant(block)) {
        throw ErrorAt(
            "internal: a variable parameter block of the problem "
            "is neither a reduced variable nor a point");
      }
    }
  }

  void CheckFinite(const double* block, const std::string& name) const {
    const int size = problem_->ParameterBlockSize(block);
    for (int k = 0; k < size; ++k) {
      if (!std::isfinite(block[k])) {
        throw ErrorAt(name, " has a non-finite parameter (", block[k], ")");
      }
    }
  }

  void EvaluateJacobian() {
    ceres::Problem::EvaluateOptions evaluate;
    evaluate.parameter_blocks = blocks_;
    evaluate.apply_loss_function = true;
    evaluate.num_threads = options_.num_threads;
    double cost = 0.0;
    if (!problem_->Evaluate(evaluate, &cost, nullptr, nullptr, &jacobian_)) {
      throw ErrorAt("the problem's Jacobian could not be evaluated");
    }
    if (jacobian_.num_cols != static_cast<int>(owners_.size())) {
      throw ErrorAt("internal: Jacobian has ", jacobian_.num_cols,
                    " columns, expected ", owners_.size());
    }
    for (const double value : jacobian_.values) {
      if (!std::isfinite(value)) {
        throw ErrorAt("the problem's Jacobian has non-finite entries");
      }
    }
    result_.num_residuals = jacobian_.num_rows;
    // Kept coordinates: all reduced ones until a gauge is held.
    int kept = 0;
    for (ColumnOwner& owner : owners_) {
      if (owner.reduced >= 0) owner.kept = kept++;
    }
    num_kept_ = kept;
    kept_dim_ = reduced_dim_;
  }

  // Jacobi scaling: every column to unit norm. Poses in radians and metres
  // against focal lengths in pixels leave Lambda's condition number near
  // 1e12 unscaled; scaled, the factor loses only what the geometry itself
  // leaves undetermined. Everything is computed in scaled coordinates and
  // scaled back, Sigma = D Sigma~ D.
  void ScaleColumns() {
    Eigen::VectorXd squared = Eigen::VectorXd::Zero(jacobian_.num_cols);
    for (size_t e = 0; e < jacobian_.values.size(); ++e) {
      squared(jacobian_.cols[e]) += jacobian_.values[e] * jacobian_.values[e];
    }
    column_scale_ = Eigen::VectorXd::Ones(jacobian_.num_cols);
    for (int c = 0; c < jacobian_.num_cols; ++c) {
      if (squared(c) > 0.0) column_scale_(c) = 1.0 / std::sqrt(squared(c));
    }
    for (size_t e = 0; e < jacobian_.values.size(); ++e) {
      jacobian_.values[e] *= column_scale_(jacobian_.cols[e]);
    }
  }

  // D's entries of a reduced variable (full tangent) or a point.
  Eigen::VectorXd ReducedScale(int a) const {
    return column_scale_.segment(reduced_first_column_[a], reduced_dim_[a]);
  }
  Eigen::Vector3d PointScale(int j) const {
    return column_scale_.segment<3>(num_reduced_columns_ + 3 * j);
  }

  // Rows of the null space in the Jacobian's column order.
  Eigen::MatrixXd StackNullSpace() const {
    const std::vector<Eigen::MatrixXd>& on_reduced =
        options_.null_space_reduced;
    const std::vector<Eigen::MatrixXd>& on_points = options_.null_space_points;
    if (on_reduced.size() != reduced_.size() ||
        (!on_points.empty() && on_points.size() != points_.size())) {
      throw ErrorAt("internal: the null space needs rows for every variable");
    }
    const int k = static_cast<int>(on_reduced.front().cols());
    Eigen::MatrixXd n = Eigen::MatrixXd::Zero(owners_.size(), k);
    int row = 0;
    for (size_t a = 0; a < reduced_.size(); ++a) {
      if (on_reduced[a].rows() != reduced_dim_[a] ||
          on_reduced[a].cols() != k) {
        throw ErrorAt("internal: null-space rows of ", reduced_[a].name,
                      " are ", on_reduced[a].rows(), "x", on_reduced[a].cols(),
                      ", expected ", reduced_dim_[a], "x", k);
      }
      n.middleRows(row, reduced_dim_[a]) = on_reduced[a];
      row += reduced_dim_[a];
    }
    for (size_t j = 0; j < on_points.size(); ++j) {
      n.middleRows(row, 3) = on_points[j];
      row += 3;
    }
    return n;
  }

  // Orthonormalises the null space and holds, among the reduced
  // coordinates, those where it is best conditioned (pivoted QR).
  void ChooseHeldCoordinates() {
    const Eigen::MatrixXd n = StackNullSpace();
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(n);
    gauge_dimension_ = static_cast<int>(n.cols());
    null_basis_ = qr.householderQ() *
                  Eigen::MatrixXd::Identity(n.rows(), gauge_dimension_);
    // The basis must be the problem's: |J N| small against |J| |N|.
    Eigen::Map<const Eigen::SparseMatrix<double, Eigen::RowMajor>> jacobian(
        jacobian_.num_rows, jacobian_.num_cols, jacobian_.values.size(),
        jacobian_.rows.data(), jacobian_.cols.data(), jacobian_.values.data());
    const double residual = (jacobian * null_basis_).norm();
    const double scale = Eigen::Map<const Eigen::VectorXd>(
                             jacobian_.values.data(), jacobian_.values.size())
                             .norm();
    if (!(residual <= 1e-6 * scale)) {
      throw ErrorAt(
          "the gauge null space given is not the problem's: |J N| "
          "= ",
          residual, " against |J| = ", scale,
          " (a prior or rig term fixes part of the gauge)");
    }
    const int num_reduced = static_cast<int>(
        std::count_if(owners_.begin(), owners_.end(),
                      [](const ColumnOwner& o) { return o.reduced >= 0; }));
    const Eigen::MatrixXd on_reduced_t =
        null_basis_.topRows(num_reduced).transpose();
    const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> pivoted(on_reduced_t);
    const double first = std::abs(pivoted.matrixR()(0, 0));
    const double last =
        std::abs(pivoted.matrixR()(gauge_dimension_ - 1, gauge_dimension_ - 1));
    if (!(last > 1e-9 * first)) {
      throw ErrorAt("the gauge cannot be held on the reduced variables");
    }
    std::vector<bool> held(num_reduced, false);
    for (int k = 0; k < gauge_dimension_; ++k) {
      held[pivoted.colsPermutation().indices()(k)] = true;
    }
    int kept = 0;
    kept_dim_ = reduced_dim_;
    for (int c = 0; c < num_reduced; ++c) {
      ColumnOwner& owner = owners_[c];
      if (held[c]) {
        owner.kept = -1;
        --kept_dim_[owner.reduced];
      } else {
        owner.kept = kept++;
      }
    }
    num_kept_ = kept;
    result_.gauge_dimension = gauge_dimension_;
  }

  // The point Jacobian row r sees (its entries at point columns), or -1.
  int RowPoint(int r) const {
    int point = -1;
    for (int e = point_entries_begin_[r]; e < jacobian_.rows[r + 1]; ++e) {
      const int on_point = PointOfColumn(jacobian_.cols[e]);
      if (point >= 0 && on_point != point) {
        throw ErrorAt("a residual couples ", points_[point].name, " and ",
                      points_[on_point].name,
                      "; points must be independent given the reduced "
                      "variables");
      }
      point = on_point;
    }
    return point;
  }

  // Points' columns follow the reduced ones, three each (ListColumns); the
  // owner is computed rather than read, since owners_ is mostly points' and
  // far larger than the cache.
  int PointOfColumn(int c) const { return (c - num_reduced_columns_) / 3; }
  int PointCoordinate(int c) const { return (c - num_reduced_columns_) % 3; }

  // The reduced variables with kept coordinates that point j's rows see,
  // ascending, into *vars (through a held coordinate too: its B_j block is
  // then zero, but the pair stays co-visible).
  void CoupledVariables(int j, std::vector<int>* vars) const {
    vars->clear();
    for (int x = point_row_begin_[j]; x < point_row_begin_[j + 1]; ++x) {
      const int r = point_rows_[x];
      for (int e = jacobian_.rows[r]; e < point_entries_begin_[r]; ++e) {
        const ColumnOwner& owner = owners_[jacobian_.cols[e]];
        if (kept_dim_[owner.reduced] > 0) {
          vars->push_back(owner.reduced);
        }
      }
    }
    std::sort(vars->begin(), vars->end());
    vars->erase(std::unique(vars->begin(), vars->end()), vars->end());
  }

  // Rows by point and by reduced variable, and each point's couplings with
  // their places in the pool. Every index lists its entries ascending, so
  // that what is summed from them is summed in one order for any number of
  // threads.
  void IndexCouplings() {
    // A variable's columns are contiguous (ListColumns), so its entries are
    // contiguous in a row whose columns ascend, as Ceres writes them; the
    // row scans below rely on it.
    // The reduced variables' entries of a row come first, then its point's.
    point_entries_begin_.resize(jacobian_.num_rows);
    for (int r = 0; r < jacobian_.num_rows; ++r) {
      for (int e = jacobian_.rows[r] + 1; e < jacobian_.rows[r + 1]; ++e) {
        if (jacobian_.cols[e] <= jacobian_.cols[e - 1]) {
          throw ErrorAt("internal: the Jacobian's row ", r,
                        " has columns out of order");
        }
      }
      int e = jacobian_.rows[r];
      while (e < jacobian_.rows[r + 1] &&
             jacobian_.cols[e] < num_reduced_columns_) {
        ++e;
      }
      point_entries_begin_[r] = e;
    }
    const int num_points = static_cast<int>(points_.size());
    std::vector<int> row_point(jacobian_.num_rows);
    point_row_begin_.assign(num_points + 1, 0);
    variable_row_begin_.assign(reduced_.size() + 1, 0);
    for (int r = 0; r < jacobian_.num_rows; ++r) {
      row_point[r] = RowPoint(r);
      if (row_point[r] >= 0) ++point_row_begin_[row_point[r] + 1];
      ForEachRowVariable(r, [&](int a) { ++variable_row_begin_[a + 1]; });
    }
    std::partial_sum(point_row_begin_.begin(), point_row_begin_.end(),
                     point_row_begin_.begin());
    std::partial_sum(variable_row_begin_.begin(), variable_row_begin_.end(),
                     variable_row_begin_.begin());
    point_rows_.resize(point_row_begin_.back());
    variable_rows_.resize(variable_row_begin_.back());
    std::vector<int> point_next(point_row_begin_.begin(),
                                point_row_begin_.end() - 1);
    std::vector<int> variable_next(variable_row_begin_.begin(),
                                   variable_row_begin_.end() - 1);
    for (int r = 0; r < jacobian_.num_rows; ++r) {
      if (row_point[r] >= 0) point_rows_[point_next[row_point[r]]++] = r;
      ForEachRowVariable(
          r, [&](int a) { variable_rows_[variable_next[a]++] = r; });
    }

    std::vector<int> num_couplings(num_points);
    tbb::enumerable_thread_specific<std::vector<int>> scratch;
    tbb::parallel_for(tbb::blocked_range<int>(0, num_points, 1024),
                      [&](const tbb::blocked_range<int>& range) {
                        std::vector<int>& vars = scratch.local();
                        for (int j = range.begin(); j < range.end(); ++j) {
                          CoupledVariables(j, &vars);
                          num_couplings[j] = static_cast<int>(vars.size());
                        }
                      });
    coupling_begin_.assign(num_points + 1, 0);
    for (int j = 0; j < num_points; ++j) {
      coupling_begin_[j + 1] = coupling_begin_[j] + num_couplings[j];
    }
    couplings_.resize(coupling_begin_.back());
    tbb::parallel_for(
        tbb::blocked_range<int>(0, num_points, 1024),
        [&](const tbb::blocked_range<int>& range) {
          std::vector<int>& vars = scratch.local();
          for (int j = range.begin(); j < range.end(); ++j) {
            CoupledVariables(j, &vars);
            for (size_t k = 0; k < vars.size(); ++k) {
              couplings_[coupling_begin_[j] + k] = {vars[k], j, 0};
            }
          }
        });
    size_t pool = 0;
    variable_coupling_begin_.assign(reduced_.size() + 1, 0);
    for (PointCoupling& coupling : couplings_) {
      coupling.offset = pool;
      pool += 3 * static_cast<size_t>(kept_dim_[coupling.reduced]);
      ++variable_coupling_begin_[coupling.reduced + 1];
    }
    std::partial_sum(variable_coupling_begin_.begin(),
                     variable_coupling_begin_.end(),
                     variable_coupling_begin_.begin());
    variable_couplings_.resize(couplings_.size());
    std::vector<size_t> next(variable_coupling_begin_.begin(),
                             variable_coupling_begin_.end() - 1);
    for (size_t x = 0; x < couplings_.size(); ++x) {
      variable_couplings_[next[couplings_[x].reduced]++] = x;
    }
    coupling_pool_.assign(pool, 0.0);
  }

  // f(a) once for every reduced variable with kept coordinates in row r (a
  // variable's columns are contiguous, and so are its entries in a row).
  template <typename F>
  void ForEachRowVariable(int r, F&& f) const {
    int last = -1;
    for (int e = jacobian_.rows[r]; e < point_entries_begin_[r]; ++e) {
      const ColumnOwner& owner = owners_[jacobian_.cols[e]];
      if (owner.kept >= 0 && owner.reduced != last) {
        last = owner.reduced;
        f(last);
      }
    }
  }

  const PointCoupling* FindCoupling(int point, int a) const {
    const PointCoupling* begin = couplings_.data() + coupling_begin_[point];
    const PointCoupling* end = couplings_.data() + coupling_begin_[point + 1];
    return std::lower_bound(
        begin, end, a,
        [](const PointCoupling& c, int value) { return c.reduced < value; });
  }

  Eigen::Map<PointBlock> Coupling(const PointCoupling& coupling) {
    return {coupling_pool_.data() + coupling.offset,
            kept_dim_[coupling.reduced], 3};
  }
  Eigen::Map<const PointBlock> Coupling(const PointCoupling& coupling) const {
    return {coupling_pool_.data() + coupling.offset,
            kept_dim_[coupling.reduced], 3};
  }

  // Row r's entries at its point's columns.
  Eigen::Vector3d OnPoint(int r) const {
    Eigen::Vector3d on_point = Eigen::Vector3d::Zero();
    for (int e = point_entries_begin_[r]; e < jacobian_.rows[r + 1]; ++e) {
      on_point(PointCoordinate(jacobian_.cols[e])) = jacobian_.values[e];
    }
    return on_point;
  }

  // Point j's information C_j = J_j^T J_j.
  Eigen::Matrix3d PointInformation(int j) const {
    Eigen::Matrix3d information = Eigen::Matrix3d::Zero();
    for (int x = point_row_begin_[j]; x < point_row_begin_[j + 1]; ++x) {
      const Eigen::Vector3d on_point = OnPoint(point_rows_[x]);
      information.noalias() += on_point * on_point.transpose();
    }
    return information;
  }

  // Point j's couplings B_j = J_c^T J_j, into the pool.
  void AccumulateCouplings(int j) {
    for (int x = point_row_begin_[j]; x < point_row_begin_[j + 1]; ++x) {
      const int r = point_rows_[x];
      const Eigen::Vector3d on_point = OnPoint(r);
      for (int e = jacobian_.rows[r]; e < point_entries_begin_[r]; ++e) {
        const ColumnOwner& owner = owners_[jacobian_.cols[e]];
        if (owner.kept < 0) continue;
        Coupling(*FindCoupling(j, owner.reduced))
            .row(owner.kept - KeptOffset(owner.reduced))
            .noalias() += jacobian_.values[e] * on_point.transpose();
      }
    }
  }

  [[noreturn]] void ThrowUndetermined(int j) const {
    const Eigen::Vector3d values =
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(PointInformation(j))
            .eigenvalues();
    throw ErrorAt(points_[j].name, " is not determined by its ",
                  point_row_begin_[j + 1] - point_row_begin_[j],
                  " residuals (information eigenvalues ", values(0), ", ",
                  values(1), ", ", values(2),
                  "): seen once, or along parallel rays");
  }

  // S = A - sum_j B_j C_j^-1 B_j^T, with A = J_c^T J_c: the points one by
  // one (C_j^-1 and B_j), then S's columns one by one. Each point and each
  // column is one task's, so the sums are the same for any thread count.
  void AssembleReducedSystem() {
    IndexCouplings();
    const int num_points = static_cast<int>(points_.size());
    point_inverse_.resize(num_points);
    std::vector<char> determined(num_points, 1);
    tbb::parallel_for(
        tbb::blocked_range<int>(0, num_points, 256),
        [&](const tbb::blocked_range<int>& range) {
          for (int j = range.begin(); j < range.end(); ++j) {
            AccumulateCouplings(j);
            const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(
                PointInformation(j));
            const Eigen::Vector3d values = eigen.eigenvalues();
            if (!(values(0) > 1e-12 * values(2) && values(0) > 0.0)) {
              determined[j] = 0;
              continue;
            }
            point_inverse_[j] = eigen.eigenvectors() *
                                values.cwiseInverse().asDiagonal() *
                                eigen.eigenvectors().transpose();
          }
        });
    for (int j = 0; j < num_points; ++j) {
      if (!determined[j]) ThrowUndetermined(j);
    }

    columns_.assign(reduced_.size(), {});
    tbb::enumerable_thread_specific<std::vector<int>> slots(
        std::vector<int>(reduced_.size(), -1));
    tbb::parallel_for(
        tbb::blocked_range<int>(0, static_cast<int>(reduced_.size()), 1),
        [&](const tbb::blocked_range<int>& range) {
          std::vector<int>& slot = slots.local();
          for (int b = range.begin(); b < range.end(); ++b) {
            if (kept_dim_[b] > 0) AssembleColumn(b, &slot);
          }
        });
    result_.num_point_coordinates = 3 * num_points;
    result_.num_reduced_coordinates = num_kept_ + gauge_dimension_;
  }

  // S's column b: the blocks (a, b), a >= b, of every variable a sharing a
  // row or a point with b; A's products row by row, then the points' terms
  // point by point. `slot` is -1 for every variable on entry and exit.
  void AssembleColumn(int b, std::vector<int>* slot) {
    ReducedColumn& column = columns_[b];
    const auto mark = [&](int a) {
      if (a >= b && (*slot)[a] < 0) {
        (*slot)[a] = 0;
        column.rows.push_back(a);
      }
    };
    for (int x = variable_row_begin_[b]; x < variable_row_begin_[b + 1]; ++x) {
      ForEachRowVariable(variable_rows_[x], mark);
    }
    for (size_t x = variable_coupling_begin_[b];
         x < variable_coupling_begin_[b + 1]; ++x) {
      const int j = couplings_[variable_couplings_[x]].point;
      for (size_t y = coupling_begin_[j]; y < coupling_begin_[j + 1]; ++y) {
        mark(couplings_[y].reduced);
      }
    }
    std::sort(column.rows.begin(), column.rows.end());
    const int kept_b = kept_dim_[b];
    size_t size = 0;
    for (size_t k = 0; k < column.rows.size(); ++k) {
      (*slot)[column.rows[k]] = static_cast<int>(k);
      column.offsets.push_back(size);
      size += static_cast<size_t>(kept_dim_[column.rows[k]]) * kept_b;
    }
    column.values.assign(size, 0.0);

    for (int x = variable_row_begin_[b]; x < variable_row_begin_[b + 1]; ++x) {
      const int r = variable_rows_[x];
      const int end = point_entries_begin_[r];
      // b's entries are contiguous in the row: [b_begin, b_end).
      int b_begin = jacobian_.rows[r];
      while (owners_[jacobian_.cols[b_begin]].reduced != b) ++b_begin;
      int b_end = b_begin;
      while (b_end < end && owners_[jacobian_.cols[b_end]].reduced == b) {
        ++b_end;
      }
      for (int f = jacobian_.rows[r]; f < end; ++f) {
        const ColumnOwner& on_a = owners_[jacobian_.cols[f]];
        if (on_a.kept < 0 || on_a.reduced < b) continue;
        const int a = on_a.reduced;
        double* row_of_a = column.values.data() + column.offsets[(*slot)[a]] +
                           (on_a.kept - KeptOffset(a));
        for (int e = b_begin; e < b_end; ++e) {
          const int kept = owners_[jacobian_.cols[e]].kept;
          if (kept < 0) continue;
          row_of_a[static_cast<size_t>(kept - KeptOffset(b)) * kept_dim_[a]] +=
              jacobian_.values[f] * jacobian_.values[e];
        }
      }
    }
    if (kept_b == 6) {
      // A pose, most of the columns: fixed sizes let Eigen unroll.
      SubtractPointTerms<6>(b, *slot, &column);
    } else {
      SubtractPointTerms<Eigen::Dynamic>(b, *slot, &column);
    }
    for (const int a : column.rows) (*slot)[a] = -1;
  }

  // Column b's blocks (a, b), a >= b, minus sum_j B_aj C_j^-1 B_bj^T over
  // the points j that b sees; kCols is b's kept dimension when fixed.
  template <int kCols>
  void SubtractPointTerms(int b, const std::vector<int>& slot,
                          ReducedColumn* column) const {
    const int kept_b = kept_dim_[b];
    Eigen::Matrix<double, 3, kCols> c_b(3, kept_b);  // C_j^-1 B_bj^T
    for (size_t x = variable_coupling_begin_[b];
         x < variable_coupling_begin_[b + 1]; ++x) {
      const PointCoupling& on_b = couplings_[variable_couplings_[x]];
      const int j = on_b.point;
      c_b.noalias() = point_inverse_[j] *
                      Eigen::Map<const Eigen::Matrix<double, kCols, 3>>(
                          coupling_pool_.data() + on_b.offset, kept_b, 3)
                          .transpose();
      for (size_t y = coupling_begin_[j]; y < coupling_begin_[j + 1]; ++y) {
        const int a = couplings_[y].reduced;
        if (a < b) continue;
        double* block = column->values.data() + column->offsets[slot[a]];
        const double* coupling = coupling_pool_.data() + couplings_[y].offset;
        if (kCols == 6 && kept_dim_[a] == 6) {
          Eigen::Map<Eigen::Matrix<double, 6, kCols>>(block, 6, kept_b)
              .noalias() -=
              Eigen::Map<const Eigen::Matrix<double, 6, 3>>(coupling) * c_b;
        } else {
          Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, kCols>>(
              block, kept_dim_[a], kept_b)
              .noalias() -=
              Eigen::Map<const PointBlock>(coupling, kept_dim_[a], 3)
                  .lazyProduct(c_b);
        }
      }
    }
  }

  static Eigen::Map<Eigen::MatrixXd> Block(ReducedColumn& column, int k,
                                           int rows, int cols) {
    return {column.values.data() + column.offsets[k], rows, cols};
  }

  void ComputeKeptOffsets() {
    kept_offset_.assign(reduced_.size(), 0);
    int offset = 0;
    for (size_t a = 0; a < reduced_.size(); ++a) {
      kept_offset_[a] = offset;
      offset += kept_dim_[a];
    }
  }
  int KeptOffset(int a) const { return kept_offset_[a]; }

  void Factor() {
    size_t nonzeros = 0;
    for (size_t b = 0; b < reduced_.size(); ++b) {
      if (kept_dim_[b] > 0 && BlockPosition(b, b) < 0) {
        throw ErrorAt(reduced_[b].name,
                      " is in no residual: its covariance is undefined");
      }
      for (const int a : columns_[b].rows) {
        nonzeros += static_cast<size_t>(kept_dim_[a]) * kept_dim_[b];
      }
    }
    cholmod_common* common = cholmod_.get();
    std::unique_ptr<cholmod_sparse, CholmodDeleter> s(
        cholmod_allocate_sparse(num_kept_, num_kept_, nonzeros, 1, 1, -1,
                                CHOLMOD_REAL, common),
        CholmodDeleter{common});
    if (!s) throw ErrorAt("out of memory for the reduced system");
    int* column_start = static_cast<int*>(s->p);
    int* row_index = static_cast<int*>(s->i);
    double* value = static_cast<double*>(s->x);
    int entry = 0;
    for (size_t b = 0; b < reduced_.size(); ++b) {
      ReducedColumn& column = columns_[b];
      for (int cb = 0; cb < kept_dim_[b]; ++cb) {
        column_start[KeptOffset(b) + cb] = entry;
        for (size_t k = 0; k < column.rows.size(); ++k) {
          const int a = column.rows[k];
          const auto block =
              Block(column, static_cast<int>(k), kept_dim_[a], kept_dim_[b]);
          const int first = a == static_cast<int>(b) ? cb : 0;
          for (int ra = first; ra < kept_dim_[a]; ++ra) {
            row_index[entry] = KeptOffset(a) + ra;
            value[entry] = block(ra, cb);
            ++entry;
          }
        }
      }
    }
    column_start[num_kept_] = entry;
    factor_.reset(cholmod_analyze(s.get(), common));
    if (!factor_) throw ErrorAt("CHOLMOD could not analyse the reduced system");
    cholmod_factorize(s.get(), factor_.get(), common);
    if (common->status == CHOLMOD_NOT_POSDEF || factor_->minor < factor_->n) {
      const int failed = static_cast<const int*>(factor_->Perm)[factor_->minor];
      throw ErrorAt(
          "the covariance is undefined: the problem is rank "
          "deficient at ",
          NameOfKept(failed),
          " (its coordinates are not determined by the residuals "
          "that see it given the others: too few or degenerate "
          "observations, or a gauge freedom not fixed)");
    }
    if (common->status != CHOLMOD_OK || !factor_->is_super) {
      throw ErrorAt("CHOLMOD failed to factor the reduced system (status ",
                    common->status, ")");
    }
    result_.reciprocal_condition = cholmod_rcond(factor_.get(), common);
    result_.factor_nonzeros = static_cast<long>(common->lnz);
    if (!(result_.reciprocal_condition >= options_.min_reciprocal_condition)) {
      throw ErrorAt(
          "the covariance is undefined: the reduced system is "
          "numerically singular (reciprocal condition ",
          result_.reciprocal_condition,
          "); a gauge freedom or a variable is not fixed");
    }
    // S_inverse for the gauge projection and the sparse inverse need L.
  }

  std::string NameOfKept(int kept) const {
    for (size_t a = 0; a < reduced_.size(); ++a) {
      const int begin = kept_offset_[a];
      if (kept >= begin && kept < begin + kept_dim_[a]) {
        return reduced_[a].name + " (coordinate " +
               std::to_string(kept - begin) + ")";
      }
    }
    return "coordinate " + std::to_string(kept);
  }

  // A reduced block of S^-1 in kept coordinates.
  Eigen::MatrixXd KeptBlock(const SparseInverse& inverse, int a, int b) const {
    Eigen::MatrixXd block(kept_dim_[a], kept_dim_[b]);
    for (int x = 0; x < kept_dim_[a]; ++x) {
      for (int y = 0; y < kept_dim_[b]; ++y) {
        block(x, y) = inverse.At(kept_offset_[a] + x, kept_offset_[b] + y);
      }
    }
    return block;
  }

  // Kept-coordinate rows into the full tangent rows of a variable (zeros at
  // held coordinates).
  Eigen::MatrixXd Embed(int a, int b, const Eigen::MatrixXd& kept) const {
    if (gauge_dimension_ == 0) return kept;
    Eigen::MatrixXd full =
        Eigen::MatrixXd::Zero(reduced_dim_[a], reduced_dim_[b]);
    const std::vector<int>& rows = kept_locals_[a];
    const std::vector<int>& cols = kept_locals_[b];
    for (size_t x = 0; x < rows.size(); ++x) {
      for (size_t y = 0; y < cols.size(); ++y) {
        full(rows[x], cols[y]) = kept(x, y);
      }
    }
    return full;
  }

  void ReadMarginals(const SparseInverse& inverse) {
    kept_locals_.assign(reduced_.size(), {});
    for (const ColumnOwner& owner : owners_) {
      if (owner.reduced >= 0 && owner.kept >= 0) {
        kept_locals_[owner.reduced].push_back(owner.local);
      }
    }
    // S^-1 at every block of S: the marginals (a, a) and the co-visible
    // pairs, which the points need.
    tbb::parallel_for(
        tbb::blocked_range<int>(0, static_cast<int>(reduced_.size()), 1),
        [&](const tbb::blocked_range<int>& range) {
          for (int b = range.begin(); b < range.end(); ++b) {
            ReducedColumn& column = columns_[b];
            column.inverse.resize(column.values.size());
            for (size_t k = 0; k < column.rows.size(); ++k) {
              const int a = column.rows[k];
              Eigen::Map<Eigen::MatrixXd>(
                  column.inverse.data() + column.offsets[k], kept_dim_[a],
                  kept_dim_[b]) = KeptBlock(inverse, a, b);
            }
          }
        });
    result_.reduced.resize(reduced_.size());
    for (size_t a = 0; a < reduced_.size(); ++a) {
      if (kept_dim_[a] == 0) {
        result_.reduced[a] =
            Eigen::MatrixXd::Zero(reduced_dim_[a], reduced_dim_[a]);
        continue;
      }
      result_.reduced[a] = Embed(a, a, InverseBlock(a, a));
    }
    if (options_.covisible_cross) {
      for (size_t b = 0; b < reduced_.size(); ++b) {
        for (const int a : columns_[b].rows) {
          if (a == static_cast<int>(b)) continue;
          result_.cross[{static_cast<int>(b), a}] =
              Embed(b, a, InverseBlock(a, b).transpose());
        }
      }
    }
    if (options_.point_marginals || gauge_dimension_ > 0) {
      result_.points.resize(points_.size());
      tbb::parallel_for(
          tbb::blocked_range<int>(0, static_cast<int>(points_.size()), 256),
          [&](const tbb::blocked_range<int>& range) {
            for (int j = range.begin(); j < range.end(); ++j) {
              const Eigen::Vector3d d = PointScale(j);
              result_.points[j] =
                  d.asDiagonal() * PointMarginal(j) * d.asDiagonal();
            }
          });
    }
    for (size_t a = 0; a < reduced_.size(); ++a) {
      const Eigen::VectorXd d = ReducedScale(static_cast<int>(a));
      result_.reduced[a] = d.asDiagonal() * result_.reduced[a] * d.asDiagonal();
    }
    for (auto& [pair, block] : result_.cross) {
      block = ReducedScale(pair.first).asDiagonal() * block *
              ReducedScale(pair.second).asDiagonal();
    }
  }

  // Where block (a, b), a >= b, is in column b, or -1.
  int BlockPosition(int a, int b) const {
    const std::vector<int>& rows = columns_[b].rows;
    const auto found = std::lower_bound(rows.begin(), rows.end(), a);
    return found != rows.end() && *found == a
               ? static_cast<int>(found - rows.begin())
               : -1;
  }

  // S^-1's block (a, b), a >= b, in kept coordinates.
  Eigen::Map<const Eigen::MatrixXd> InverseBlock(int a, int b) const {
    const int k = BlockPosition(a, b);
    if (k < 0) {
      throw ErrorAt("internal: no covariance block for ", reduced_[a].name,
                    " and ", reduced_[b].name);
    }
    return {columns_[b].inverse.data() + columns_[b].offsets[k], kept_dim_[a],
            kept_dim_[b]};
  }

  // Sigma_j = C^-1 + C^-1 (sum_ab B_a^T Z_ab B_b) C^-1, B_a = Lambda's block.
  Eigen::Matrix3d PointMarginal(int j) const {
    Eigen::Matrix3d inner = Eigen::Matrix3d::Zero();
    for (size_t x = coupling_begin_[j]; x < coupling_begin_[j + 1]; ++x) {
      const int a = couplings_[x].reduced;
      const auto b_a = Coupling(couplings_[x]);
      for (size_t y = coupling_begin_[j]; y < coupling_begin_[j + 1]; ++y) {
        const int b = couplings_[y].reduced;
        const auto b_b = Coupling(couplings_[y]);
        // Z_ab column by column: no temporaries for any block size.
        const auto z = InverseBlock(std::max(a, b), std::min(a, b));
        for (int q = 0; q < kept_dim_[b]; ++q) {
          const Eigen::Vector3d b_a_z =
              a >= b ? Eigen::Vector3d(b_a.transpose().lazyProduct(z.col(q)))
                     : Eigen::Vector3d(
                           b_a.transpose().lazyProduct(z.row(q).transpose()));
          inner.noalias() += b_a_z * b_b.row(q);
        }
      }
    }
    const Eigen::Matrix3d& c = point_inverse_[j];
    const Eigen::Matrix3d sigma = c + c * inner * c;
    return 0.5 * (sigma + sigma.transpose());
  }

  // Lambda^+ = P G P: with W = G Q (solved through the Schur complement)
  // and M = Q^T W, each block (x, y) is
  //   G_xy - Q_x W_y^T - W_x Q_y^T + Q_x M Q_y^T.
  void ProjectOntoGaugeComplement() {
    const int k = gauge_dimension_;
    const int num_reduced_full = static_cast<int>(
        std::accumulate(reduced_dim_.begin(), reduced_dim_.end(), 0));
    // Q at kept reduced coordinates and at points.
    // In scaled coordinates, W = D G~ (D Q).
    const Eigen::MatrixXd scaled_basis =
        column_scale_.asDiagonal() * null_basis_;
    Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(num_kept_, k);
    for (int c = 0; c < num_reduced_full; ++c) {
      if (owners_[c].kept >= 0) rhs.row(owners_[c].kept) = scaled_basis.row(c);
    }
    const auto point_rows = [&](int j) {
      return scaled_basis.middleRows(num_reduced_full + 3 * j, 3);
    };
    // rhs_c = Q_c - sum_j B_j C_j^-1 Q_j.
    for (size_t j = 0; j < points_.size(); ++j) {
      const Eigen::MatrixXd c_q = point_inverse_[j] * point_rows(j);
      for (size_t x = coupling_begin_[j]; x < coupling_begin_[j + 1]; ++x) {
        const int a = couplings_[x].reduced;
        const Eigen::Map<const Eigen::MatrixXd> b_a(
            coupling_pool_.data() + couplings_[x].offset, kept_dim_[a], 3);
        rhs.middleRows(kept_offset_[a], kept_dim_[a]).noalias() -= b_a * c_q;
      }
    }
    const Eigen::MatrixXd w_kept = SolveFactor(CHOLMOD_A, rhs);
    // W over all coordinates (held ones 0).
    Eigen::MatrixXd w = ScatterKept(w_kept);
    for (size_t j = 0; j < points_.size(); ++j) {
      w.middleRows(num_reduced_full + 3 * j, 3) =
          point_inverse_[j] *
          (point_rows(static_cast<int>(j)) - CouplingTransposeTimes(j, w_kept));
    }
    w = column_scale_.asDiagonal() * w;
    const Eigen::MatrixXd m = null_basis_.transpose() * w;
    const auto project = [&](const Eigen::MatrixXd& g, int row_x, int rows,
                             int row_y, int cols) {
      const auto q_x = null_basis_.middleRows(row_x, rows);
      const auto q_y = null_basis_.middleRows(row_y, cols);
      const auto w_x = w.middleRows(row_x, rows);
      const auto w_y = w.middleRows(row_y, cols);
      return Eigen::MatrixXd(g - q_x * w_y.transpose() - w_x * q_y.transpose() +
                             q_x * m * q_y.transpose());
    };
    for (size_t a = 0; a < reduced_.size(); ++a) {
      const int row = reduced_first_column_[a];
      result_.reduced[a] = project(result_.reduced[a], row, reduced_dim_[a],
                                   row, reduced_dim_[a]);
    }
    for (auto& [pair, block] : result_.cross) {
      block = project(
          block, reduced_first_column_[pair.first], reduced_dim_[pair.first],
          reduced_first_column_[pair.second], reduced_dim_[pair.second]);
    }
    for (size_t j = 0; j < points_.size(); ++j) {
      const int row = num_reduced_full + 3 * static_cast<int>(j);
      result_.points[j] = project(result_.points[j], row, 3, row, 3);
    }
    if (!options_.point_marginals) result_.points.clear();
  }

  void DrawSamples() {
    const int m = options_.num_samples;
    // z: one stream per sample, so that a draw does not depend on how many
    // others are drawn after it.
    std::vector<SplitMix64Stream> streams;
    for (int s = 0; s < m; ++s) {
      streams.emplace_back(SplitMix64(SplitMix64(options_.sample_seed) ^
                                      SplitMix64(static_cast<uint64_t>(s))));
    }
    Eigen::MatrixXd z(num_kept_, m);
    for (int s = 0; s < m; ++s) {
      for (int r = 0; r < num_kept_; ++r) z(r, s) = streams[s].Gaussian();
    }
    // Reduced, scaled: x~_c = P^T L^-T z has covariance S~^-1.
    const Eigen::MatrixXd x_kept =
        SolveFactor(CHOLMOD_Pt, SolveFactor(CHOLMOD_Lt, z));
    Eigen::MatrixXd x = ScatterKept(x_kept);
    for (size_t j = 0; j < points_.size(); ++j) {
      const Eigen::MatrixXd coupled = -CouplingTransposeTimes(j, x_kept);
      const Eigen::Matrix3d root = point_inverse_[j].llt().matrixL();
      Eigen::MatrixXd own(3, m);
      for (int s = 0; s < m; ++s) {
        for (int k = 0; k < 3; ++k) own(k, s) = streams[s].Gaussian();
      }
      x.middleRows(num_reduced_columns_ + 3 * static_cast<int>(j), 3) =
          point_inverse_[j] * coupled + root * own;
    }
    x = column_scale_.asDiagonal() * x;
    // Free network: P x has covariance P G P = Lambda^+.
    if (gauge_dimension_ > 0) {
      x -= null_basis_ * (null_basis_.transpose() * x);
    }
    result_.samples = std::move(x);
    result_.sample_row_of_reduced = reduced_first_column_;
    result_.sample_row_of_points = num_reduced_columns_;
  }

  // A matrix over the kept reduced coordinates laid out over all
  // coordinates (rows in the Jacobian's column order; held and point rows
  // zero).
  Eigen::MatrixXd ScatterKept(const Eigen::MatrixXd& kept) const {
    Eigen::MatrixXd all = Eigen::MatrixXd::Zero(owners_.size(), kept.cols());
    for (int c = 0; c < num_reduced_columns_; ++c) {
      if (owners_[c].kept >= 0) all.row(c) = kept.row(owners_[c].kept);
    }
    return all;
  }

  // B_j^T y for point j and y over the kept reduced coordinates.
  Eigen::MatrixXd CouplingTransposeTimes(size_t j,
                                         const Eigen::MatrixXd& kept) const {
    Eigen::MatrixXd product = Eigen::MatrixXd::Zero(3, kept.cols());
    for (size_t e = coupling_begin_[j]; e < coupling_begin_[j + 1]; ++e) {
      const int a = couplings_[e].reduced;
      const Eigen::Map<const Eigen::MatrixXd> b_a(
          coupling_pool_.data() + couplings_[e].offset, kept_dim_[a], 3);
      product.noalias() +=
          b_a.transpose() * kept.middleRows(kept_offset_[a], kept_dim_[a]);
    }
    return product;
  }

  // CHOLMOD's solve of `system` (CHOLMOD_A, _Lt, _Pt, ...) with the factor.
  Eigen::MatrixXd SolveFactor(int system, const Eigen::MatrixXd& rhs) {
    cholmod_common* common = cholmod_.get();
    cholmod_dense b;
    b.nrow = rhs.rows();
    b.ncol = rhs.cols();
    b.nzmax = rhs.size();
    b.d = rhs.rows();
    b.x = const_cast<double*>(rhs.data());
    b.z = nullptr;
    b.xtype = CHOLMOD_REAL;
    b.dtype = CHOLMOD_DOUBLE;
    std::unique_ptr<cholmod_dense, CholmodDeleter> x(
        cholmod_solve(system, factor_.get(), &b, common),
        CholmodDeleter{common});
    if (!x) throw ErrorAt("CHOLMOD failed to solve with the reduced system");
    return Eigen::Map<const Eigen::MatrixXd>(static_cast<const double*>(x->x),
                                             rhs.rows(), rhs.cols());
  }

  ceres::Problem* problem_;
  const std::vector<ReducedVariable>& reduced_;
  const std::vector<EliminatedPoint>& points_;
  const SchurCovarianceOptions& options_;
  SchurCovariance result_;

  std::vector<double*> blocks_;
  std::vector<ColumnOwner> owners_;
  std::vector<int> reduced_dim_;  // full tangent size per reduced variable
  std::vector<int> reduced_first_column_;
  std::vector<int> kept_dim_;  // without held coordinates
  std::vector<int> kept_offset_;
  std::vector<std::vector<int>> kept_locals_;
  int num_kept_ = 0;
  int num_reduced_columns_ = 0;
  ceres::CRSMatrix jacobian_;
  Eigen::VectorXd column_scale_;

  int gauge_dimension_ = 0;
  Eigen::MatrixXd null_basis_;  // orthonormal, Jacobian column order

  // Per Jacobian row, where its point's entries begin.
  std::vector<int> point_entries_begin_;
  // Jacobian rows by point and by reduced variable (CSR, ascending).
  std::vector<int> point_row_begin_;
  std::vector<int> point_rows_;
  std::vector<int> variable_row_begin_;
  std::vector<int> variable_rows_;
  // Couplings by point, and their indices by reduced variable.
  std::vector<PointCoupling> couplings_;
  std::vector<size_t> coupling_begin_;
  std::vector<size_t> variable_coupling_begin_;
  std::vector<size_t> variable_couplings_;
  std::vector<double> coupling_pool_;
  std::vector<Eigen::Matrix3d> point_inverse_;

  std::vector<ReducedColumn> columns_;

  CholmodCommon cholmod_;
  std::unique_ptr<cholmod_factor, CholmodDeleter> factor_{
      nullptr, CholmodDeleter{cholmod_.get()}};
};

}  // namespace

SchurCovariance ComputeSchurCovariance(
    ceres::Problem* problem, const std::vector<ReducedVariable>& reduced,
    const std::vector<EliminatedPoint>& points,
    const SchurCovarianceOptions& options) {
  options.Check();
  Computation computation(problem, reduced, points, options);
  return computation.Run();
}

}  // namespace uw
