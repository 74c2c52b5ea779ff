#pragma once
// H x = b by conjugate gradients with a two-level preconditioner (internal to optim/), for
// normal equations too large to factor. Why: the refinement's H at thousands of frames fills in
// under Cholesky (loops and the structure tie distant frames together; measured at 5,000
// frames, factoring is most of the refinement's time), while a step of conjugate gradients
// costs one product with H, linear in its entries.
//
// The preconditioner is additive two-level Schwarz (Smith, Bjorstad and Gropp, "Domain
// Decomposition", 1996, ch. 2):
//
//   M^-1 = sum_g R_g^T H_gg^-1 R_g  +  B (B^T H B)^-1 B^T
//
// the first sum a block Jacobi over groups of variables (H_gg the group's block of H, inverted
// densely: what couples the variables within a group, such as consecutive frames), the second
// an exact solve in a coarse space whose columns B span the smooth, long-range moves that a
// local smoother cannot (for poses: each segment of the trajectory moving rigidly, blended
// between control frames; see optim/pose_problem.h). Both parts are symmetric positive
// (semi-)definite, so M is, and conjugate gradients converge to H's exact solution; the coarse
// system has as many blocks as there are controls, and factors in a fraction of H's time.

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <memory>
#include <vector>

#include "f2c/optim/block_matrix.h"

namespace f2c {

struct CoarseBasis {
  int block;              // the coarse block
  Eigen::MatrixXd basis;  // the variable's tangent step per unit of the block's step
};

struct TwoLevelPcgOptions {
  // Stop when |H x - b| <= tolerance |b|.
  double tolerance = 1e-8;
  int max_iterations = 500;
};

struct TwoLevelPcgSummary {
  int iterations = 0;
  double relative_residual = 0;
  bool converged = false;
};

class TwoLevelPcg {
 public:
  // `basis`: per variable of H, its coarse blocks (empty for a free variable: it is a coarse
  // block of its own, with the identity); `block_sizes`: the coarse blocks' sizes; `group`:
  // per variable, its smoother group (< 0: a group of its own).
  TwoLevelPcg(std::vector<std::vector<CoarseBasis>> basis, std::vector<int> block_sizes, std::vector<int> group);
  ~TwoLevelPcg();

  // The preconditioner for `h` (its values as they are now); false where the coarse system
  // or a group's block is not positive definite.
  bool Setup(const BlockSymmetricMatrix& h);
  // x solving h x = b (h as given to Setup).
  TwoLevelPcgSummary Solve(const BlockSymmetricMatrix& h, const Eigen::VectorXd& b, const TwoLevelPcgOptions& options,
                           Eigen::VectorXd* x) const;
  // M^-1 r.
  Eigen::VectorXd Precondition(const Eigen::VectorXd& r) const;
  int coarse_size() const { return coarse_columns_; }

 private:
  // The coarse blocks, each variable's basis blocks, the coarse pattern and the groups: all
  // from H's pattern, once.
  void BuildStructure(const BlockSymmetricMatrix& h);
  Eigen::VectorXd Smooth(const Eigen::VectorXd& r) const;  // the groups' block Jacobi
  Eigen::VectorXd Coarse(const Eigen::VectorXd& r) const;  // B (B^T H B)^-1 B^T r
  std::vector<std::vector<CoarseBasis>> basis_;
  std::vector<int> block_sizes_, group_;
  // The coarse blocks: the given ones, then one per free variable without a basis.
  std::vector<int> coarse_start_, coarse_tangent_;
  int coarse_columns_ = 0;
  std::unique_ptr<BlockSymmetricMatrix> coarse_;
  std::unique_ptr<SparseCholesky> coarse_cholesky_;
  struct Group {
    std::vector<int> columns;  // H's scalar columns
    Eigen::LLT<Eigen::MatrixXd> llt;
  };
  // A variable without a basis coupled to variables with one: those (its basis is extended
  // from theirs); empty for the others.
  std::vector<std::vector<int>> neighbours_;
  static constexpr int kMaxExtensionBlocks = 16;
  std::vector<Group> groups_;
  std::vector<std::vector<int>> group_members_;  // each group's free variables
  const std::vector<int>* start_ = nullptr;
};

}  // namespace f2c
