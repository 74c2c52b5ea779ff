#include "f2c/optim/block_matrix.h"

#include <cholmod.h>

#include <algorithm>

namespace f2c {
namespace {

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

// A fill-reducing ordering of H's scalar columns, found on the blocks' graph (a ninth of the
// scalar one's entries, so the ordering costs a fraction of what it does on the scalars) by
// CHOLMOD's AMD or nested dissection, each block's columns kept together. Empty if CHOLMOD
// fails.
std::vector<int> BlockOrdering(const BlockSymmetricMatrix& h, FillOrdering ordering, cholmod_common* common) {
  const std::vector<int>& start = h.start();
  std::vector<int> node_of(start.size(), -1), variable_of;
  for (size_t v = 0; v < start.size(); ++v) {
    if (start[v] < 0) continue;
    node_of[v] = static_cast<int>(variable_of.size());
    variable_of.push_back(static_cast<int>(v));
  }
  std::vector<int> p{0}, i;
  for (int v : variable_of) {
    for (int a : h.rows(v)) i.push_back(node_of[a]);
    p.push_back(static_cast<int>(i.size()));
  }
  const int n = static_cast<int>(variable_of.size());
  cholmod_sparse graph = UpperView(n, &p, &i, nullptr);
  std::vector<int> perm(n), parent(n), member(n);
  if (ordering == FillOrdering::kAmd) {
    if (!cholmod_amd(&graph, nullptr, 0, perm.data(), common)) return {};
  } else if (cholmod_nested_dissection(&graph, nullptr, 0, perm.data(), parent.data(), member.data(), common) < 0) {
    return {};
  }
  std::vector<int> scalar;
  for (int node : perm) {
    const int v = variable_of[node];
    for (int q = 0; q < h.tangent()[v]; ++q) scalar.push_back(start[v] + q);
  }
  return scalar;
}

}  // namespace

BlockSymmetricMatrix::BlockSymmetricMatrix(const std::vector<std::vector<int>>& coupled, const std::vector<int>& start,
                                           const std::vector<int>& tangent)
    : start_(start), tangent_(tangent) {
  const int nv = static_cast<int>(start.size());
  rows_.resize(nv);
  for (const std::vector<int>& vars : coupled) {
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

void BlockSymmetricMatrix::Clear() { std::fill(values_.begin(), values_.end(), 0.0); }

int BlockSymmetricMatrix::Offset(int a, int b) const {
  const std::vector<int>& r = rows_[b];
  const int k = static_cast<int>(std::lower_bound(r.begin(), r.end(), a) - r.begin());
  return offsets_[b][k];
}

void BlockSymmetricMatrix::Add(int a, int b, int offset, const double* block) {
  for (int q = 0; q < tangent_[b]; ++q) {
    double* column = values_.data() + column_pointers_[start_[b] + q] + offset;
    for (int p = 0; p < tangent_[a]; ++p) column[p] += block[q * tangent_[a] + p];
  }
}

Eigen::MatrixXd BlockSymmetricMatrix::Block(int a, int b) const {
  const std::vector<int>& r = rows_[b];
  return BlockAt(b, static_cast<int>(std::lower_bound(r.begin(), r.end(), a) - r.begin()));
}

Eigen::VectorXd BlockSymmetricMatrix::Diagonal() const {
  Eigen::VectorXd d(size());
  for (int c = 0; c < d.size(); ++c) d[c] = values_[DiagonalIndex(c)];
  return d;
}

void BlockSymmetricMatrix::SetDiagonal(const Eigen::VectorXd& d) {
  for (int c = 0; c < d.size(); ++c) values_[DiagonalIndex(c)] = d[c];
}

Eigen::VectorXd BlockSymmetricMatrix::Multiply(const Eigen::VectorXd& x) const {
  Eigen::VectorXd y = Eigen::VectorXd::Zero(x.size());
  for (int c = 0; c < size(); ++c) {
    for (int k = column_pointers_[c]; k < column_pointers_[c + 1]; ++k) {
      const int r = row_indices_[k];
      if (r > c) continue;  // the lower part of a diagonal block
      y[r] += values_[k] * x[c];
      if (r < c) y[c] += values_[k] * x[r];
    }
  }
  return y;
}

// Rows within a column ascend (block rows in order, each block's rows in order).
size_t BlockSymmetricMatrix::DiagonalIndex(int c) const {
  const auto first = row_indices_.begin() + column_pointers_[c], last = row_indices_.begin() + column_pointers_[c + 1];
  return static_cast<size_t>(std::lower_bound(first, last, c) - row_indices_.begin());
}

struct SparseCholesky::Impl {
  FillOrdering ordering;
  cholmod_common common;
  cholmod_factor* factor = nullptr;
  bool factorized = false;
};

SparseCholesky::SparseCholesky(FillOrdering ordering) : impl_(new Impl) {
  impl_->ordering = ordering;
  cholmod_common& common = impl_->common;
  cholmod_start(&common);
  common.print = 0;
  common.nmethods = 1;  // only the ordering asked for, not CHOLMOD's trial of several
  common.method[0].ordering = CHOLMOD_AMD;
}

SparseCholesky::~SparseCholesky() {
  if (impl_->factor != nullptr) cholmod_free_factor(&impl_->factor, &impl_->common);
  cholmod_finish(&impl_->common);
}

void SparseCholesky::Analyze(BlockSymmetricMatrix* h) {
  if (impl_->factor != nullptr) return;
  cholmod_common& common = impl_->common;
  const int n = h->size();
  cholmod_sparse a = UpperView(n, &h->column_pointers(), &h->row_indices(), nullptr);
  std::vector<int> perm = BlockOrdering(*h, impl_->ordering, &common);
  if (static_cast<int>(perm.size()) == n) {
    common.method[0].ordering = CHOLMOD_GIVEN;
    impl_->factor = cholmod_analyze_p(&a, perm.data(), nullptr, 0, &common);
  }
  if (impl_->factor == nullptr) {  // CHOLMOD's own AMD on the scalars
    common.method[0].ordering = CHOLMOD_AMD;
    impl_->factor = cholmod_analyze(&a, &common);
  }
}

bool SparseCholesky::Factorize(BlockSymmetricMatrix* h) {
  Analyze(h);
  cholmod_sparse a = UpperView(h->size(), &h->column_pointers(), &h->row_indices(), &h->values());
  impl_->factorized = impl_->factor != nullptr && cholmod_factorize(&a, impl_->factor, &impl_->common) &&
                      impl_->common.status == CHOLMOD_OK;
  return impl_->factorized;
}

bool SparseCholesky::Solve(const Eigen::VectorXd& b, Eigen::VectorXd* x) {
  if (!impl_->factorized) return false;
  const int n = static_cast<int>(b.size());
  cholmod_dense rhs{};
  rhs.nrow = n;
  rhs.ncol = 1;
  rhs.nzmax = n;
  rhs.d = n;
  rhs.x = const_cast<double*>(b.data());
  rhs.xtype = CHOLMOD_REAL;
  rhs.dtype = CHOLMOD_DOUBLE;
  cholmod_dense* solution = cholmod_solve(CHOLMOD_A, impl_->factor, &rhs, &impl_->common);
  if (solution == nullptr) return false;
  *x = Eigen::Map<const Eigen::VectorXd>(static_cast<double*>(solution->x), n);
  cholmod_free_dense(&solution, &impl_->common);
  return x->allFinite();
}

bool SparseCholesky::supernodal() const { return impl_->factor != nullptr && impl_->factor->is_super; }

}  // namespace f2c
