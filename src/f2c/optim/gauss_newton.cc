#include "f2c/optim/gauss_newton.h"

#include <cholmod.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_group.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <optional>

#include "f2c/util/error.h"

namespace f2c {

void GaussNewtonProblem::AddVariable(double* x, int size, const ceres::Manifold* manifold, bool constant) {
  F2C_CHECK(index_.count(x) == 0, "a variable is added once");
  F2C_CHECK(manifold == nullptr || manifold->AmbientSize() == size, "the manifold fits the variable");
  index_[x] = static_cast<int>(variables_.size());
  variables_.push_back({x, size, manifold, constant});
}

namespace {

using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// One residual block linearised at the current variables is its share of the normal
// equations: per free block i its gradient J_i^T r and per pair i <= j of free blocks
// J_i^T J_j (transposed where the variables' order is the other way round). Stored flat, in
// the block's slot of one buffer for all blocks: the gradients in the blocks' order, then
// the products (i, j), i <= j, in row order (0,0), (0,1), ..., (1,1), ..., each
// column-major. LinearisedSize is a slot's length.
size_t LinearisedSize(const std::vector<int>& free_vars, const std::vector<int>& tangent) {
  size_t total = 0;
  for (size_t a = 0; a < free_vars.size(); ++a) {
    total += tangent[free_vars[a]];
    for (size_t b = a; b < free_vars.size(); ++b) total += tangent[free_vars[a]] * tangent[free_vars[b]];
  }
  return total;
}

// 1/2 rho(|r|^2), and Ceres' corrector for it: residuals scaled by `residual_scale`, the
// Jacobian J <- sqrt(rho') (J - alpha_sq_norm r r^T J) (with the residuals before scaling).
struct Corrector {
  double cost;
  double residual_scale = 1;
  double jacobian_scale = 1;
  double alpha_sq_norm = 0;
};

Corrector Correct(const ceres::LossFunction* loss, double sq_norm) {
  if (loss == nullptr) return {0.5 * sq_norm};
  double rho[3];
  loss->Evaluate(sq_norm, rho);
  Corrector c{0.5 * rho[0]};
  const double sqrt_rho1 = std::sqrt(std::max(rho[1], 0.0));
  c.jacobian_scale = sqrt_rho1;
  c.residual_scale = sqrt_rho1;
  if (sq_norm > 0 && rho[2] > 0 && rho[1] > 0) {
    const double d = 1 + 2 * sq_norm * rho[2] / rho[1];
    const double alpha = 1 - std::sqrt(d);
    c.residual_scale = sqrt_rho1 / (1 - alpha);
    c.alpha_sq_norm = alpha / sq_norm;
  }
  return c;
}

// A CHOLMOD view of a symmetric matrix's upper triangle in compressed columns (int indices;
// values null for a pattern), over arrays the caller keeps.
cholmod_sparse UpperView(int n, std::vector<int>* p, std::vector<int>* i, std::vector<double>* x) {
  cholmod_sparse a{};
  a.nrow = a.ncol = n;
  a.nzmax = i->size();
  a.p = p->data();
  a.i = i->data();
  a.x = x != nullptr ? x->data() : nullptr;
  a.stype = 1;
  a.itype = CHOLMOD_INT;
  a.xtype = x != nullptr ? CHOLMOD_REAL : CHOLMOD_PATTERN;
  a.dtype = CHOLMOD_DOUBLE;
  a.sorted = 1;
  a.packed = 1;
  return a;
}

// The normal equations' pattern: the upper triangle of the variables' blocks (diagonal blocks
// stored whole; CHOLMOD reads only their upper part), as compressed columns.
class Pattern {
 public:
  // `free_vars`: each residual block's free variables.
  Pattern(const std::vector<std::vector<int>>& free_vars, const std::vector<int>& start,
          const std::vector<int>& tangent)
      : start_(start), tangent_(tangent) {
    const int nv = static_cast<int>(start.size());
    rows_.resize(nv);
    for (const std::vector<int>& vars : free_vars) {
      for (size_t i = 0; i < vars.size(); ++i) {
        for (size_t j = i; j < vars.size(); ++j) {
          const int a = std::min(vars[i], vars[j]), b = std::max(vars[i], vars[j]);
          rows_[b].push_back(a);
        }
      }
    }
    offsets_.resize(nv);
    column_pointers_.push_back(0);
    for (int b = 0; b < nv; ++b) {
      if (start[b] < 0) continue;
      std::vector<int>& r = rows_[b];
      std::sort(r.begin(), r.end());
      r.erase(std::unique(r.begin(), r.end()), r.end());
      int length = 0;
      for (int a : r) {
        offsets_[b].push_back(length);
        length += tangent[a];
      }
      for (int q = 0; q < tangent[b]; ++q) {
        for (int a : r) {
          for (int p = 0; p < tangent[a]; ++p) row_indices_.push_back(start[a] + p);
        }
        column_pointers_.push_back(static_cast<int>(row_indices_.size()));
      }
    }
    values_.assign(row_indices_.size(), 0.0);
  }

  void Clear() { std::fill(values_.begin(), values_.end(), 0.0); }

  // Where block (a, b), a <= b, starts in each of b's scalar columns.
  int Offset(int a, int b) const {
    const std::vector<int>& r = rows_[b];
    const int k = static_cast<int>(std::lower_bound(r.begin(), r.end(), a) - r.begin());
    return offsets_[b][k];
  }
  // Adds `block` (tangent[a] x tangent[b], column-major) at variables (a, b), a <= b, whose
  // place in b's columns is `offset` (from Offset). Touches b's columns only.
  void Add(int a, int b, int offset, const double* block) {
    for (int q = 0; q < tangent_[b]; ++q) {
      double* column = values_.data() + column_pointers_[start_[b] + q] + offset;
      for (int p = 0; p < tangent_[a]; ++p) column[p] += block[q * tangent_[a] + p];
    }
  }

  // H's diagonal, and setting it (each column's entry on its own row).
  Eigen::VectorXd Diagonal() const {
    Eigen::VectorXd d(static_cast<int>(column_pointers_.size()) - 1);
    for (int c = 0; c < d.size(); ++c) d[c] = values_[DiagonalIndex(c)];
    return d;
  }
  void SetDiagonal(const Eigen::VectorXd& d) {
    for (int c = 0; c < d.size(); ++c) values_[DiagonalIndex(c)] = d[c];
  }

  // y = H x, H symmetric from its upper triangle.
  Eigen::VectorXd Multiply(const Eigen::VectorXd& x) const {
    Eigen::VectorXd y = Eigen::VectorXd::Zero(x.size());
    for (int c = 0; c + 1 < static_cast<int>(column_pointers_.size()); ++c) {
      for (int k = column_pointers_[c]; k < column_pointers_[c + 1]; ++k) {
        const int r = row_indices_[k];
        if (r > c) continue;  // the lower part of a diagonal block
        y[r] += values_[k] * x[c];
        if (r < c) y[c] += values_[k] * x[r];
      }
    }
    return y;
  }

  // A fill-reducing ordering of the scalar columns, found on the blocks' graph (a ninth of
  // the scalar one's entries, so the ordering costs a fraction of what it does on the
  // scalars) by CHOLMOD's AMD or nested dissection, each block's columns kept together.
  // Empty if CHOLMOD fails.
  std::vector<int> BlockOrdering(GaussNewtonOptions::Ordering ordering, cholmod_common* common) const {
    std::vector<int> node_of(start_.size(), -1), variable_of;
    for (size_t v = 0; v < start_.size(); ++v) {
      if (start_[v] < 0) continue;
      node_of[v] = static_cast<int>(variable_of.size());
      variable_of.push_back(static_cast<int>(v));
    }
    std::vector<int> p{0}, i;
    for (int v : variable_of) {
      for (int a : rows_[v]) i.push_back(node_of[a]);
      p.push_back(static_cast<int>(i.size()));
    }
    const int n = static_cast<int>(variable_of.size());
    cholmod_sparse graph = UpperView(n, &p, &i, nullptr);
    std::vector<int> perm(n), parent(n), member(n);
    if (ordering == GaussNewtonOptions::Ordering::kAmd) {
      if (!cholmod_amd(&graph, nullptr, 0, perm.data(), common)) return {};
    } else if (cholmod_nested_dissection(&graph, nullptr, 0, perm.data(), parent.data(), member.data(), common) < 0) {
      return {};
    }
    std::vector<int> scalar;
    for (int node : perm) {
      const int v = variable_of[node];
      for (int q = 0; q < tangent_[v]; ++q) scalar.push_back(start_[v] + q);
    }
    return scalar;
  }

  std::vector<int>& column_pointers() { return column_pointers_; }
  std::vector<int>& row_indices() { return row_indices_; }
  std::vector<double>& values() { return values_; }

 private:
  // Rows within a column ascend (block rows in order, each block's rows in order).
  size_t DiagonalIndex(int c) const {
    const auto first = row_indices_.begin() + column_pointers_[c],
               last = row_indices_.begin() + column_pointers_[c + 1];
    return static_cast<size_t>(std::lower_bound(first, last, c) - row_indices_.begin());
  }

  const std::vector<int>& start_;
  const std::vector<int>& tangent_;
  std::vector<std::vector<int>> rows_;     // per block column: its block rows, sorted
  std::vector<std::vector<int>> offsets_;  // per block column: each block row's first scalar row
  std::vector<int> column_pointers_, row_indices_;
  std::vector<double> values_;
};

// H x = b by CHOLMOD's Cholesky (H from its upper triangle). The symbolic analysis (the fill-
// reducing ordering and the factor's structure) is done once, by Analyze or else at the first
// solve: the steps of one Solve share their Pattern.
class Cholesky {
 public:
  explicit Cholesky(GaussNewtonOptions::Ordering ordering) : ordering_(ordering) {
    cholmod_start(&common_);
    common_.print = 0;
    common_.nmethods = 1;  // only the ordering asked for, not CHOLMOD's trial of several
    common_.method[0].ordering = CHOLMOD_AMD;
  }
  ~Cholesky() {
    if (factor_ != nullptr) cholmod_free_factor(&factor_, &common_);
    cholmod_finish(&common_);
  }
  Cholesky(const Cholesky&) = delete;
  Cholesky& operator=(const Cholesky&) = delete;

  // The symbolic analysis of H's pattern (n columns); reads the pattern only, so it may run
  // while H's values are being computed.
  void Analyze(Pattern* h, int n) {
    if (factor_ != nullptr) return;
    cholmod_sparse a = UpperView(n, &h->column_pointers(), &h->row_indices(), nullptr);
    std::vector<int> perm = h->BlockOrdering(ordering_, &common_);
    if (static_cast<int>(perm.size()) == n) {
      common_.method[0].ordering = CHOLMOD_GIVEN;
      factor_ = cholmod_analyze_p(&a, perm.data(), nullptr, 0, &common_);
    }
    if (factor_ == nullptr) {  // CHOLMOD's own AMD on the scalars
      common_.method[0].ordering = CHOLMOD_AMD;
      factor_ = cholmod_analyze(&a, &common_);
    }
  }

  bool supernodal() const { return factor_ != nullptr && factor_->is_super; }

  // False if H is not positive definite (or CHOLMOD fails otherwise).
  bool Solve(Pattern* h, const Eigen::VectorXd& b, Eigen::VectorXd* x) {
    const int n = static_cast<int>(b.size());
    Analyze(h, n);
    cholmod_sparse a = UpperView(n, &h->column_pointers(), &h->row_indices(), &h->values());
    if (factor_ == nullptr || !cholmod_factorize(&a, factor_, &common_) || common_.status != CHOLMOD_OK) return false;
    cholmod_dense rhs{};
    rhs.nrow = n;
    rhs.ncol = 1;
    rhs.nzmax = n;
    rhs.d = n;
    rhs.x = const_cast<double*>(b.data());
    rhs.xtype = CHOLMOD_REAL;
    rhs.dtype = CHOLMOD_DOUBLE;
    cholmod_dense* solution = cholmod_solve(CHOLMOD_A, factor_, &rhs, &common_);
    if (solution == nullptr) return false;
    *x = Eigen::Map<const Eigen::VectorXd>(static_cast<double*>(solution->x), n);
    cholmod_free_dense(&solution, &common_);
    return x->allFinite();
  }

 private:
  GaussNewtonOptions::Ordering ordering_;
  cholmod_common common_;
  cholmod_factor* factor_ = nullptr;
};

constexpr int kMaxBlocks = 16;  // parameter blocks per residual block

// Per-thread scratch space for Linearise.
struct Scratch {
  std::vector<double> r, ambient, tangents;
};

// Residual block `res` linearised into `out` (its slot, LinearisedSize long): `vars` its
// blocks' variables, `free_vars` those that move (start >= 0), `size` and `tangent` each
// variable's ambient and tangent sizes, and `plus_jacobians` each free variable's manifold
// Jacobian (empty: Euclidean). False where the residuals are not finite.
bool Linearise(const GaussNewtonResidual& res, const std::vector<int>& vars, const std::vector<int>& free_vars,
               const std::vector<int>& start, const std::vector<int>& size, const std::vector<int>& tangent,
               const std::vector<RowMatrix>& plus_jacobians, Scratch* scratch, double* out) {
  const int m = res.cost->num_residuals();
  const int nb = static_cast<int>(res.blocks.size());
  F2C_CHECK(nb <= kMaxBlocks, "at most 16 parameter blocks per residual block");
  // The ambient Jacobians side by side (each m x size, row-major), then the tangent ones.
  int ambient_size = 0, tangent_size = 0;
  for (int v : free_vars) {
    ambient_size += size[v];
    tangent_size += tangent[v];
  }
  scratch->r.resize(m);
  scratch->ambient.resize(static_cast<size_t>(m) * ambient_size);
  scratch->tangents.resize(static_cast<size_t>(m) * tangent_size);
  double* jacobians[kMaxBlocks] = {};
  for (int b = 0, offset = 0; b < nb; ++b) {
    if (start[vars[b]] < 0) continue;
    jacobians[b] = scratch->ambient.data() + static_cast<size_t>(m) * offset;
    offset += size[vars[b]];
  }
  const Eigen::Map<Eigen::VectorXd> residual(scratch->r.data(), m);
  if (!res.cost->Evaluate(res.blocks.data(), scratch->r.data(), jacobians) || !residual.allFinite()) return false;
  const Corrector c = Correct(res.loss, residual.squaredNorm());
  // Free variable k's tangent Jacobian (m x tangent, row-major) starts at j[k].
  double* j[kMaxBlocks] = {};
  for (size_t k = 0, a_off = 0, t_off = 0; k < free_vars.size(); ++k) {
    const int v = free_vars[k];
    Eigen::Map<const RowMatrix> jac_ambient(scratch->ambient.data() + m * a_off, m, size[v]);
    j[k] = scratch->tangents.data() + m * t_off;
    Eigen::Map<RowMatrix> jk(j[k], m, tangent[v]);
    if (plus_jacobians[v].size() > 0) {
      jk.noalias() = jac_ambient * plus_jacobians[v];
    } else {
      jk = jac_ambient;
    }
    if (c.alpha_sq_norm != 0) jk -= c.alpha_sq_norm * residual * (residual.transpose() * jk);
    jk *= c.jacobian_scale;
    a_off += size[v];
    t_off += tangent[v];
  }
  auto jacobian = [&](size_t k) { return Eigen::Map<const RowMatrix>(j[k], m, tangent[free_vars[k]]); };
  for (size_t a = 0; a < free_vars.size(); ++a) {
    Eigen::Map<Eigen::VectorXd> g(out, tangent[free_vars[a]]);
    g.noalias() = c.residual_scale * (jacobian(a).transpose() * residual);
    out += g.size();
  }
  for (size_t a = 0; a < free_vars.size(); ++a) {
    for (size_t b = a; b < free_vars.size(); ++b) {
      // Stored as (lower-numbered variable, higher): transposed where the order is reversed.
      const bool ordered = free_vars[a] <= free_vars[b];
      const size_t lo = ordered ? a : b, hi = ordered ? b : a;
      Eigen::Map<Eigen::MatrixXd> p(out, tangent[free_vars[lo]], tangent[free_vars[hi]]);
      p.noalias() = jacobian(lo).transpose() * jacobian(hi);
      out += p.size();
    }
  }
  return true;
}

}  // namespace

GaussNewtonSummary GaussNewtonProblem::Solve(const std::vector<GaussNewtonResidual>& residuals,
                                             const GaussNewtonOptions& options) const {
  const int nv = static_cast<int>(variables_.size());
  std::vector<int> start(nv, -1), size(nv), tangent(nv, 0);
  int columns = 0;
  for (int v = 0; v < nv; ++v) {
    const Variable& var = variables_[v];
    size[v] = var.size;
    tangent[v] = var.manifold != nullptr ? var.manifold->TangentSize() : var.size;
    if (var.constant) continue;
    start[v] = columns;
    columns += tangent[v];
  }
  std::vector<std::vector<int>> block_vars(residuals.size());
  for (size_t i = 0; i < residuals.size(); ++i) {
    for (double* b : residuals[i].blocks) {
      const auto it = index_.find(b);
      F2C_CHECK(it != index_.end(), "every residual block's parameters are variables");
      block_vars[i].push_back(it->second);
    }
  }

  // The total cost at the variables' current values (no Jacobians), summed in order.
  auto total_cost = [&](bool* ok) {
    std::vector<double> costs(residuals.size(), 0.0);
    std::vector<char> good(residuals.size(), 1);
    tbb::parallel_for(size_t{0}, residuals.size(), [&](size_t i) {
      const GaussNewtonResidual& res = residuals[i];
      Eigen::VectorXd r(res.cost->num_residuals());
      if (!res.cost->Evaluate(res.blocks.data(), r.data(), nullptr) || !r.allFinite()) {
        good[i] = 0;
        return;
      }
      costs[i] = Correct(res.loss, r.squaredNorm()).cost;
    });
    double cost = 0;
    for (size_t i = 0; i < costs.size(); ++i) {
      cost += costs[i];
      *ok = *ok && good[i];
    }
    return cost;
  };

  GaussNewtonSummary summary;
  bool ok = true;
  summary.initial_cost = summary.final_cost = total_cost(&ok);
  if (!ok) {
    summary.termination = "the residuals are not finite at the start";
    return summary;
  }
  if (columns == 0) {
    summary.termination = "nothing to solve";
    return summary;
  }
  std::vector<std::vector<int>> free_vars(residuals.size());
  for (size_t i = 0; i < residuals.size(); ++i) {
    for (int v : block_vars[i]) {
      if (!variables_[v].constant) free_vars[i].push_back(v);
    }
  }
  // Each block's slot in one buffer of linearisations, and what goes where in the normal
  // equations: per variable, the gradients and the blocks of its columns, in the residual
  // blocks' order. Summed per variable in that order, every entry of H and g adds the same
  // numbers in the same order as a serial sum over the blocks, so the result does not depend
  // on the threads; the variables' columns are disjoint, so they are summed in parallel.
  std::vector<size_t> slot(residuals.size() + 1, 0);
  for (size_t i = 0; i < residuals.size(); ++i) slot[i + 1] = slot[i] + LinearisedSize(free_vars[i], tangent);
  struct Into {
    size_t from;  // in the buffer
    int row;      // the block's variable a (H's block (a, b)); -1 for a gradient
    int offset;   // where block (a, b) starts in b's columns
  };
  std::optional<Pattern> pattern;  // the same for every step
  std::vector<std::vector<Into>> into(nv);
  // The pattern, the lists and the symbolic analysis need no values: serial, they are built
  // beside the first linearisation.
  auto structure = [&] {
    pattern.emplace(free_vars, start, tangent);
    for (size_t i = 0; i < residuals.size(); ++i) {
      const std::vector<int>& vars = free_vars[i];
      size_t from = slot[i];
      for (int v : vars) {
        into[v].push_back({from, -1, 0});
        from += tangent[v];
      }
      for (size_t a = 0; a < vars.size(); ++a) {
        for (size_t b = a; b < vars.size(); ++b) {
          const int lo = std::min(vars[a], vars[b]), hi = std::max(vars[a], vars[b]);
          into[hi].push_back({from, lo, pattern->Offset(lo, hi)});
          from += tangent[lo] * tangent[hi];
        }
      }
    }
  };
  std::vector<double> linear(slot.back());
  std::vector<RowMatrix> plus_jacobians(nv);
  Cholesky cholesky(options.ordering);
  for (int it = 0; it < options.max_iterations; ++it) {
    for (int v = 0; v < nv; ++v) {
      const Variable& var = variables_[v];
      if (var.constant || var.manifold == nullptr) continue;
      plus_jacobians[v].resize(var.size, tangent[v]);
      var.manifold->PlusJacobian(var.x, plus_jacobians[v].data());
    }
    tbb::task_group analysis;
    if (it == 0) {
      analysis.run([&] {
        structure();
        cholesky.Analyze(&*pattern, columns);
      });
    }
    std::vector<char> good(residuals.size(), 1);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, residuals.size()), [&](const tbb::blocked_range<size_t>& range) {
      Scratch scratch;
      for (size_t i = range.begin(); i != range.end(); ++i) {
        good[i] = Linearise(residuals[i], block_vars[i], free_vars[i], start, size, tangent, plus_jacobians, &scratch,
                            linear.data() + slot[i]);
      }
    });
    analysis.wait();
    if (std::find(good.begin(), good.end(), 0) != good.end()) {
      summary.termination = "the residuals or Jacobians are not finite";
      return summary;
    }
    Pattern& h = *pattern;
    h.Clear();
    Eigen::VectorXd g = Eigen::VectorXd::Zero(columns);
    tbb::parallel_for(tbb::blocked_range<int>(0, nv), [&](const tbb::blocked_range<int>& range) {
      for (int v = range.begin(); v != range.end(); ++v) {
        for (const Into& e : into[v]) {
          if (e.row < 0) {
            g.segment(start[v], tangent[v]) += Eigen::Map<const Eigen::VectorXd>(linear.data() + e.from, tangent[v]);
          } else {
            h.Add(e.row, v, e.offset, linear.data() + e.from);
          }
        }
      }
    });
    ++summary.iterations;
    Eigen::VectorXd step;
    const bool solved = cholesky.Solve(&h, -g, &step);
    summary.supernodal = cholesky.supernodal();
    if (!solved) {
      summary.factorized = false;
      summary.termination = "the normal equations are not positive definite";
      return summary;
    }
    // The old values, to step from and to go back to.
    std::vector<std::vector<double>> saved(nv);
    for (int v = 0; v < nv; ++v) {
      if (!variables_[v].constant) saved[v].assign(variables_[v].x, variables_[v].x + variables_[v].size);
    }
    // Tries `d` (each variable on its manifold): kept if the cost falls by enough of what the
    // undamped model predicts, else the variables go back to where they were.
    double new_cost = 0;
    auto try_step = [&](const Eigen::VectorXd& d) {
      const double model_decrease = -(g.dot(d) + 0.5 * d.dot(h.Multiply(d)));
      for (int v = 0; v < nv; ++v) {
        const Variable& var = variables_[v];
        if (var.constant) continue;
        const double* delta = d.data() + start[v];
        if (var.manifold != nullptr) {
          var.manifold->Plus(saved[v].data(), delta, var.x);
        } else {
          for (int k = 0; k < var.size; ++k) var.x[k] = saved[v][k] + delta[k];
        }
      }
      bool new_ok = true;
      new_cost = total_cost(&new_ok);
      const double decrease = summary.final_cost - new_cost;
      if (new_ok && model_decrease > 0 && decrease / model_decrease >= options.min_relative_decrease) return true;
      for (int v = 0; v < nv; ++v) {
        if (!saved[v].empty()) std::copy(saved[v].begin(), saved[v].end(), variables_[v].x);
      }
      return false;
    };
    bool kept = try_step(step);
    // Damped retries (Levenberg-Marquardt): H + lambda D, D = diag(H) clamped as Ceres does,
    // lambda growing from initial_damping by damping_increase. The same pattern, so only
    // the numeric factorization is repeated; H itself is restored after each solve.
    if (!kept && options.max_damped_steps > 0) {
      const Eigen::VectorXd diagonal = h.Diagonal();
      const Eigen::VectorXd scaling = diagonal.cwiseMax(1e-6).cwiseMin(1e32);
      double lambda = options.initial_damping;
      for (int k = 0; k < options.max_damped_steps && !kept; ++k, lambda *= options.damping_increase) {
        h.SetDiagonal(diagonal + lambda * scaling);
        const bool damped_solved = cholesky.Solve(&h, -g, &step);
        h.SetDiagonal(diagonal);
        ++summary.damped;
        if (!damped_solved) break;
        kept = try_step(step);
      }
    }
    if (!kept) {
      summary.termination = "step rejected";
      return summary;
    }
    ++summary.accepted;
    const double previous = summary.final_cost;
    summary.final_cost = new_cost;
    if (std::abs(previous - new_cost) <= options.function_tolerance * previous) {
      summary.termination = "converged";
      return summary;
    }
    summary.termination = "iteration limit";
  }
  return summary;
}

}  // namespace f2c
