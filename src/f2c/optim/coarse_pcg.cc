#include "f2c/optim/coarse_pcg.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstdint>
#include <utility>

#include "f2c/util/error.h"

namespace f2c {

TwoLevelPcg::TwoLevelPcg(std::vector<std::vector<CoarseBasis>> basis, std::vector<int> block_sizes,
                         std::vector<int> group)
    : basis_(std::move(basis)), block_sizes_(std::move(block_sizes)), group_(std::move(group)) {}

TwoLevelPcg::~TwoLevelPcg() = default;

void TwoLevelPcg::BuildStructure(const BlockSymmetricMatrix& h) {
  const std::vector<int>& start = h.start();
  const std::vector<int>& tangent = h.tangent();
  const int nv = h.variables();
  // The coarse blocks: the given ones; a free variable without a basis follows the variables
  // with one that it is coupled to (its basis extended below), or where it is coupled to
  // none, or to the blocks of a long stretch, it is a coarse block of its own.
  coarse_tangent_ = block_sizes_;
  std::vector<char> given(nv, 0);
  for (int v = 0; v < nv; ++v) {
    if (start[v] < 0) basis_[v].clear();
    given[v] = !basis_[v].empty();
  }
  // Each free variable without a basis: the variables with one that it is coupled to.
  auto find_neighbours = [&] {
    neighbours_.assign(nv, {});
    for (int b = 0; b < nv; ++b) {
      if (start[b] < 0) continue;
      for (int a : h.rows(b)) {
        if (a == b) continue;
        if (given[a] && !given[b]) neighbours_[b].push_back(a);
        if (given[b] && !given[a]) neighbours_[a].push_back(b);
      }
    }
  };
  auto blocks_of = [&](int v) {
    std::vector<int> blocks;
    for (int a : neighbours_[v]) {
      for (const CoarseBasis& c : basis_[a]) blocks.push_back(c.block);
    }
    std::sort(blocks.begin(), blocks.end());
    blocks.erase(std::unique(blocks.begin(), blocks.end()), blocks.end());
    return blocks;
  };
  auto own_block = [&](int v) {
    basis_[v] = {{static_cast<int>(coarse_tangent_.size()), Eigen::MatrixXd::Identity(tangent[v], tangent[v])}};
    coarse_tangent_.push_back(tangent[v]);
  };
  // First those coupled to none of the given ones, or to the blocks of a long stretch (for
  // planes: the parents, which only their children see, and planes seen from far apart):
  // coarse blocks of their own. Then the rest (children) follow both: their extension
  // moves a child with its frames and with its parent.
  find_neighbours();
  std::vector<char> own(nv, 0);
  for (int v = 0; v < nv; ++v) {
    if (start[v] < 0 || given[v]) continue;
    const size_t blocks = blocks_of(v).size();
    own[v] = blocks == 0 || static_cast<int>(blocks) > kMaxExtensionBlocks;
  }
  for (int v = 0; v < nv; ++v) {
    if (!own[v]) continue;
    own_block(v);
    given[v] = 1;
  }
  find_neighbours();
  for (int v = 0; v < nv; ++v) {
    if (start[v] < 0 || given[v]) continue;
    for (int c : blocks_of(v)) basis_[v].push_back({c, Eigen::MatrixXd::Zero(tangent[v], coarse_tangent_[c])});
  }
  coarse_start_.assign(coarse_tangent_.size(), 0);
  coarse_columns_ = 0;
  for (size_t c = 0; c < coarse_tangent_.size(); ++c) {
    coarse_start_[c] = coarse_columns_;
    coarse_columns_ += coarse_tangent_[c];
  }
  // The coarse pattern: coarse blocks (c, d) coupled wherever H couples their variables.
  std::vector<std::uint64_t> pairs;
  for (int b = 0; b < nv; ++b) {
    if (start[b] < 0) continue;
    for (int a : h.rows(b)) {
      for (const CoarseBasis& ca : basis_[a]) {
        for (const CoarseBasis& cb : basis_[b]) {
          const auto lo = static_cast<std::uint64_t>(std::min(ca.block, cb.block));
          const auto hi = static_cast<std::uint64_t>(std::max(ca.block, cb.block));
          pairs.push_back(lo << 32 | hi);
        }
      }
    }
    if (pairs.size() > (std::size_t{1} << 22)) {  // keep the list short on large problems
      std::sort(pairs.begin(), pairs.end());
      pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    }
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  std::vector<std::vector<int>> coupled;
  coupled.reserve(pairs.size() + coarse_tangent_.size());
  for (size_t c = 0; c < coarse_tangent_.size(); ++c) coupled.push_back({static_cast<int>(c)});
  for (std::uint64_t p : pairs) coupled.push_back({static_cast<int>(p >> 32), static_cast<int>(p & 0xffffffffu)});
  coarse_ = std::make_unique<BlockSymmetricMatrix>(coupled, coarse_start_, coarse_tangent_);
  coarse_cholesky_ = std::make_unique<SparseCholesky>(FillOrdering::kNestedDissection);

  // The smoother's groups, each its free variables in order. An extended variable joins
  // the group of its first neighbour in one (a plane seen from a stretch is solved with it).
  for (int v = 0; v < nv; ++v) {
    if (group_[v] >= 0) continue;
    for (int a : neighbours_[v]) {
      if (group_[a] < 0) continue;
      group_[v] = group_[a];
      break;
    }
  }
  std::vector<std::vector<int>> members;
  std::vector<int> slot_of_group;
  for (int v = 0; v < nv; ++v) {
    if (start[v] < 0) continue;
    const int g = group_[v];
    if (g >= static_cast<int>(slot_of_group.size())) slot_of_group.resize(g + 1, -1);
    if (g >= 0 && slot_of_group[g] >= 0) {
      members[slot_of_group[g]].push_back(v);
      continue;
    }
    if (g >= 0) slot_of_group[g] = static_cast<int>(members.size());
    members.push_back({v});
  }
  groups_.resize(members.size());
  group_members_ = std::move(members);
}

bool TwoLevelPcg::Setup(const BlockSymmetricMatrix& h) {
  const std::vector<int>& start = h.start();
  const std::vector<int>& tangent = h.tangent();
  const int nv = h.variables();
  F2C_CHECK(static_cast<int>(basis_.size()) == nv && static_cast<int>(group_.size()) == nv,
            "a coarse basis and a group per variable");
  start_ = &start;
  if (coarse_ == nullptr) BuildStructure(h);

  // Each extended variable's basis: where its neighbours' coarse motion leaves it at least
  // energy with everything else held, -H_vv^-1 sum_a H_va B_a (a harmonic extension).
  tbb::parallel_for(0, nv, [&](int v) {  // each writes its own basis
    if (neighbours_[v].empty()) return;
    for (CoarseBasis& c : basis_[v]) c.basis.setZero();
    for (int a : neighbours_[v]) {
      const Eigen::MatrixXd hva = a < v ? Eigen::MatrixXd(h.Block(a, v).transpose()) : h.Block(v, a);
      for (const CoarseBasis& ca : basis_[a]) {
        auto it = std::lower_bound(basis_[v].begin(), basis_[v].end(), ca.block,
                                   [](const CoarseBasis& c, int block) { return c.block < block; });
        it->basis.noalias() -= hva * ca.basis;
      }
    }
    const Eigen::MatrixXd hvv = h.Block(v, v).selfadjointView<Eigen::Upper>();
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(hvv);
    for (CoarseBasis& c : basis_[v]) c.basis = ldlt.solve(c.basis);
  });

  // B^T H B, block by block: H's block (a, b), a <= b, stands for itself and, off the
  // diagonal, for its transpose at (b, a).
  coarse_->Clear();
  auto add = [&](int c, int d, const Eigen::MatrixXd& m) {  // m at coarse (c, d), c <= d
    coarse_->Add(c, d, coarse_->Offset(c, d), m.data());
  };
  auto add_transposed = [&](int c, int d, const Eigen::MatrixXd& m) {
    const Eigen::MatrixXd t = m.transpose();
    add(c, d, t);
  };
  Eigen::MatrixXd hab, hb, x;  // reused: most blocks have the same shapes
  for (int b = 0; b < nv; ++b) {
    if (start[b] < 0) continue;
    const std::vector<int>& rows = h.rows(b);
    for (size_t k = 0; k < rows.size(); ++k) {
      const int a = rows[k];
      hab = h.BlockAt(b, static_cast<int>(k));
      if (a == b) hab = hab.selfadjointView<Eigen::Upper>();
      for (const CoarseBasis& cb : basis_[b]) {
        hb.noalias() = hab * cb.basis;
        for (const CoarseBasis& ca : basis_[a]) {
          if (a == b && ca.block > cb.block) continue;  // the lower half of a diagonal block
          x.noalias() = ca.basis.transpose() * hb;
          if (ca.block < cb.block) {
            add(ca.block, cb.block, x);
          } else if (ca.block > cb.block) {
            add_transposed(cb.block, ca.block, x);
          } else if (a == b) {
            add(ca.block, ca.block, x);
          } else {
            add(ca.block, ca.block, x);
            add_transposed(ca.block, ca.block, x);
          }
        }
      }
    }
  }
  if (!coarse_cholesky_->Factorize(coarse_.get())) return false;

  // Each group's block of H, factored densely; the groups in parallel (each writes its own).
  std::vector<char> factored(group_members_.size(), 0);
  tbb::parallel_for(size_t{0}, group_members_.size(), [&](size_t k) {
    const std::vector<int>& vars = group_members_[k];
    Group& group = groups_[k];
    group.columns.clear();
    std::vector<int> offset;
    for (int v : vars) {
      offset.push_back(static_cast<int>(group.columns.size()));
      for (int q = 0; q < tangent[v]; ++q) group.columns.push_back(start[v] + q);
    }
    const int n = static_cast<int>(group.columns.size());
    Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(n, n);
    for (size_t j = 0; j < vars.size(); ++j) {
      const std::vector<int>& rows = h.rows(vars[j]);
      for (size_t i = 0; i <= j; ++i) {
        const auto it = std::lower_bound(rows.begin(), rows.end(), vars[i]);
        if (it == rows.end() || *it != vars[i]) continue;
        dense.block(offset[i], offset[j], tangent[vars[i]], tangent[vars[j]]) =
            h.BlockAt(vars[j], static_cast<int>(it - rows.begin()));
      }
    }
    group.llt.compute(dense.selfadjointView<Eigen::Upper>());
    factored[k] = group.llt.info() == Eigen::Success;
  });
  return std::find(factored.begin(), factored.end(), 0) == factored.end();
}

Eigen::VectorXd TwoLevelPcg::Smooth(const Eigen::VectorXd& r) const {
  Eigen::VectorXd z(r.size());
  tbb::parallel_for(size_t{0}, groups_.size(), [&](size_t g) {  // disjoint columns
    const Group& group = groups_[g];
    Eigen::VectorXd local(group.columns.size());
    for (size_t k = 0; k < group.columns.size(); ++k) local[k] = r[group.columns[k]];
    local = group.llt.solve(local);
    for (size_t k = 0; k < group.columns.size(); ++k) z[group.columns[k]] = local[k];
  });
  return z;
}

Eigen::VectorXd TwoLevelPcg::Coarse(const Eigen::VectorXd& r) const {
  const std::vector<int>& start = *start_;
  Eigen::VectorXd rc = Eigen::VectorXd::Zero(coarse_columns_);
  for (size_t v = 0; v < basis_.size(); ++v) {
    for (const CoarseBasis& c : basis_[v]) {
      rc.segment(coarse_start_[c.block], coarse_tangent_[c.block]).noalias() +=
          c.basis.transpose() * r.segment(start[v], c.basis.rows());
    }
  }
  Eigen::VectorXd z = Eigen::VectorXd::Zero(r.size());
  Eigen::VectorXd yc;
  if (!coarse_cholesky_->Solve(rc, &yc)) return z;
  for (size_t v = 0; v < basis_.size(); ++v) {
    for (const CoarseBasis& c : basis_[v]) {
      z.segment(start[v], c.basis.rows()).noalias() +=
          c.basis * yc.segment(coarse_start_[c.block], coarse_tangent_[c.block]);
    }
  }
  return z;
}

Eigen::VectorXd TwoLevelPcg::Precondition(const Eigen::VectorXd& r) const { return Smooth(r) + Coarse(r); }

TwoLevelPcgSummary TwoLevelPcg::Solve(const BlockSymmetricMatrix& h, const Eigen::VectorXd& b,
                                      const TwoLevelPcgOptions& options, Eigen::VectorXd* x) const {
  TwoLevelPcgSummary summary;
  *x = Eigen::VectorXd::Zero(b.size());
  const double b_norm = b.norm();
  if (b_norm == 0) {
    summary.converged = true;
    return summary;
  }
  Eigen::VectorXd r = b;
  Eigen::VectorXd z = Precondition(r);
  Eigen::VectorXd p = z;
  double rz = r.dot(z);
  while (summary.iterations < options.max_iterations) {
    const Eigen::VectorXd hp = h.Multiply(p);
    const double curvature = p.dot(hp);
    if (!(curvature > 0)) break;
    const double alpha = rz / curvature;
    *x += alpha * p;
    r -= alpha * hp;
    ++summary.iterations;
    summary.relative_residual = r.norm() / b_norm;
    if (summary.relative_residual <= options.tolerance) {
      summary.converged = true;
      break;
    }
    z = Precondition(r);
    const double rz_next = r.dot(z);
    p = z + (rz_next / rz) * p;
    rz = rz_next;
  }
  return summary;
}

}  // namespace f2c
