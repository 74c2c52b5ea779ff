#include "f2c/optim/gauss_newton.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_group.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <memory>
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

// Per variable of the problem, its coarse basis and its smoother group (optim/coarse_pcg.h).
std::vector<std::vector<CoarseBasis>> CoarseOf(const CoarseSpace& space,
                                               const std::unordered_map<const double*, int>& index, int nv) {
  std::vector<std::vector<CoarseBasis>> basis(nv);
  for (const auto& [x, list] : space.basis) {
    const auto it = index.find(x);
    if (it != index.end()) basis[it->second] = list;
  }
  return basis;
}

std::vector<int> GroupsOf(const CoarseSpace& space, const std::unordered_map<const double*, int>& index, int nv) {
  std::vector<int> group(nv, -1);
  for (const auto& [x, g] : space.group) {
    const auto it = index.find(x);
    if (it != index.end()) group[it->second] = g;
  }
  return group;
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
  std::optional<BlockSymmetricMatrix> pattern;  // the same for every step
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
  // The blocks are linearised a chunk at a time into one buffer (options.linearisation_chunk),
  // each chunk summed into H and g before the next: every entry still adds its blocks in their
  // order, so the result is the same as with one buffer for all, and the buffer does not grow
  // with the scan (at 5,000 frames one buffer for all would be 120 MB, zeroed and faulted in
  // by one thread at each step: measured, a fifth of the refinement's time).
  std::vector<size_t> chunk_begin{0};
  for (size_t i = 0; i < residuals.size(); ++i) {
    if (i > chunk_begin.back() && slot[i + 1] - slot[chunk_begin.back()] > options.linearisation_chunk) {
      chunk_begin.push_back(i);
    }
  }
  chunk_begin.push_back(residuals.size());
  size_t buffer_size = 0;
  for (size_t c = 0; c + 1 < chunk_begin.size(); ++c) {
    buffer_size = std::max(buffer_size, slot[chunk_begin[c + 1]] - slot[chunk_begin[c]]);
  }
  // Written whole by Linearise before it is read: not initialised.
  std::unique_ptr<double[]> linear(new double[std::max<size_t>(buffer_size, 1)]);
  std::vector<RowMatrix> plus_jacobians(nv);
  SparseCholesky cholesky(options.ordering);
  std::optional<TwoLevelPcg> pcg;
  if (options.coarse != nullptr)
    pcg.emplace(CoarseOf(*options.coarse, index_, nv), options.coarse->block_sizes,
                GroupsOf(*options.coarse, index_, nv));
  // H step = b: by conjugate gradients where a coarse space is given and they converge far
  // enough for the step test to judge the step, else by Cholesky.
  auto solve = [&](BlockSymmetricMatrix* h, const Eigen::VectorXd& b, Eigen::VectorXd* step) {
    if (pcg && pcg->Setup(*h)) {
      const TwoLevelPcgSummary s = pcg->Solve(*h, b, options.pcg, step);
      summary.linear_iterations += s.iterations;
      summary.relative_residual = std::max(summary.relative_residual, s.relative_residual);
      if (s.relative_residual <= options.pcg_accept) return true;
    }
    ++summary.factorizations;
    const bool solved = cholesky.Solve(h, b, step);
    summary.supernodal = cholesky.supernodal();
    return solved;
  };
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
        if (!pcg) cholesky.Analyze(&*pattern);
      });
    }
    Eigen::VectorXd g = Eigen::VectorXd::Zero(columns);
    std::vector<size_t> next(nv, 0);  // per variable, its first entry of `into` not yet summed
    bool finite = true;
    for (size_t c = 0; c + 1 < chunk_begin.size() && finite; ++c) {
      const size_t first = chunk_begin[c], last = chunk_begin[c + 1];
      const size_t base = slot[first];
      std::vector<char> good(last - first, 1);
      tbb::parallel_for(tbb::blocked_range<size_t>(first, last), [&](const tbb::blocked_range<size_t>& range) {
        Scratch scratch;
        for (size_t i = range.begin(); i != range.end(); ++i) {
          good[i - first] = Linearise(residuals[i], block_vars[i], free_vars[i], start, size, tangent, plus_jacobians,
                                      &scratch, linear.get() + (slot[i] - base));
        }
      });
      if (c == 0) {
        analysis.wait();
        pattern->Clear();
      }
      if (std::find(good.begin(), good.end(), 0) != good.end()) {
        finite = false;
        break;
      }
      BlockSymmetricMatrix& h = *pattern;
      const size_t end = slot[last];
      tbb::parallel_for(tbb::blocked_range<int>(0, nv), [&](const tbb::blocked_range<int>& range) {
        for (int v = range.begin(); v != range.end(); ++v) {
          const std::vector<Into>& list = into[v];
          size_t& e = next[v];
          for (; e < list.size() && list[e].from < end; ++e) {
            const double* values = linear.get() + (list[e].from - base);
            if (list[e].row < 0) {
              g.segment(start[v], tangent[v]) += Eigen::Map<const Eigen::VectorXd>(values, tangent[v]);
            } else {
              h.Add(list[e].row, v, list[e].offset, values);
            }
          }
        }
      });
    }
    if (!finite) {
      analysis.wait();
      summary.termination = "the residuals or Jacobians are not finite";
      return summary;
    }
    BlockSymmetricMatrix& h = *pattern;
    ++summary.iterations;
    Eigen::VectorXd step;
    const bool solved = solve(&h, -g, &step);
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
        const bool damped_solved = solve(&h, -g, &step);
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
