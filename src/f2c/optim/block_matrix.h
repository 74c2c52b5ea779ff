#pragma once
// The normal equations' matrix H as the Gauss-Newton solvers build it (internal to optim/):
// symmetric, stored as its upper triangle of variable blocks in compressed scalar columns
// (diagonal blocks whole; CHOLMOD reads only their upper part), and its sparse Cholesky by
// CHOLMOD. optim/gauss_newton.h factors it; optim/coarse_pcg.h solves with it iteratively.

#include <Eigen/Core>
#include <memory>
#include <vector>

namespace f2c {

// CHOLMOD's fill-reducing ordering: AMD, or CHOLMOD's nested dissection (METIS), found on the
// graph of the blocks with each block's columns kept together.
enum class FillOrdering { kAmd, kNestedDissection };

class BlockSymmetricMatrix {
 public:
  // The pattern of the blocks (a, b) that share one of `coupled` (lists of variables, each
  // list's variables coupled pairwise); `start` each variable's first scalar column (< 0: not
  // in the matrix) and `tangent` its number of columns. Values zero. Keeps references to
  // `start` and `tangent`.
  BlockSymmetricMatrix(const std::vector<std::vector<int>>& coupled, const std::vector<int>& start,
                       const std::vector<int>& tangent);

  int size() const { return static_cast<int>(column_pointers_.size()) - 1; }
  int variables() const { return static_cast<int>(start_.size()); }
  const std::vector<int>& start() const { return start_; }
  const std::vector<int>& tangent() const { return tangent_; }
  // Block column b's block rows a <= b, ascending.
  const std::vector<int>& rows(int b) const { return rows_[b]; }

  void Clear();
  // Where block (a, b), a <= b, starts in each of b's scalar columns.
  int Offset(int a, int b) const;
  // Adds `block` (tangent[a] x tangent[b], column-major) at variables (a, b), a <= b, whose
  // place in b's columns is `offset` (from Offset). Touches b's columns only.
  void Add(int a, int b, int offset, const double* block);
  // Block (a, b), a <= b, of an existing pattern entry.
  Eigen::MatrixXd Block(int a, int b) const;
  // The k-th block of block column b (its row is rows(b)[k]), in place.
  using ConstBlock = Eigen::Map<const Eigen::MatrixXd, 0, Eigen::OuterStride<>>;
  ConstBlock BlockAt(int b, int k) const {
    const int first = column_pointers_[start_[b]];
    const int stride = column_pointers_[start_[b] + 1] - first;  // b's columns are equally long
    return ConstBlock(values_.data() + first + offsets_[b][k], tangent_[rows_[b][k]], tangent_[b],
                      Eigen::OuterStride<>(stride));
  }

  // H's diagonal, and setting it (each column's entry on its own row).
  Eigen::VectorXd Diagonal() const;
  void SetDiagonal(const Eigen::VectorXd& d);
  // y = H x, H symmetric from its upper triangle.
  Eigen::VectorXd Multiply(const Eigen::VectorXd& x) const;

  std::vector<int>& column_pointers() { return column_pointers_; }
  std::vector<int>& row_indices() { return row_indices_; }
  std::vector<double>& values() { return values_; }

 private:
  size_t DiagonalIndex(int c) const;

  const std::vector<int>& start_;
  const std::vector<int>& tangent_;
  std::vector<std::vector<int>> rows_;              // per block column: its block rows, sorted
  std::vector<std::vector<int>> offsets_;           // per block column: each block row's first scalar row
  std::vector<int> column_pointers_, row_indices_;  // rows within a column ascend
  std::vector<double> values_;
};

// H x = b by CHOLMOD's supernodal or simplicial Cholesky (H from its upper triangle). The
// symbolic analysis (the fill-reducing ordering and the factor's structure) is done once, by
// Analyze or else at the first Solve: later solves must use the same pattern.
class SparseCholesky {
 public:
  explicit SparseCholesky(FillOrdering ordering);
  ~SparseCholesky();
  SparseCholesky(const SparseCholesky&) = delete;
  SparseCholesky& operator=(const SparseCholesky&) = delete;

  // Reads H's pattern only, so it may run while H's values are being computed.
  void Analyze(BlockSymmetricMatrix* h);
  // Factors H and solves; false if H is not positive definite (or CHOLMOD fails otherwise).
  bool Factorize(BlockSymmetricMatrix* h);
  // With the last factorization; false if it failed.
  bool Solve(const Eigen::VectorXd& b, Eigen::VectorXd* x);
  bool Solve(BlockSymmetricMatrix* h, const Eigen::VectorXd& b, Eigen::VectorXd* x) {
    return Factorize(h) && Solve(b, x);
  }
  bool supernodal() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace f2c
