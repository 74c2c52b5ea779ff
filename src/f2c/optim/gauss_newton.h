#pragma once
// Gauss-Newton steps on residual blocks given as Ceres cost functions and losses, without a
// ceres::Problem. Why: the refinement takes one Gauss-Newton step per iteration (paper §4.3, the
// authors' code), and Ceres pays its per-solve set-up for each one: the program and its Jacobian's
// block structure, J^T J's sparsity and its ordering, all rebuilt for a single step. Here the
// normal equations J^T J d = -J^T r are assembled block by block, straight into the compressed
// columns CHOLMOD factors, and solved by CHOLMOD's supernodal Cholesky. Measured at 900 frames
// (31,000 residual blocks with the structural model), the refinement takes about a fifth less time,
// with and without the structure; what remains is mostly CHOLMOD's factorization.
//
// The step is the one Ceres' Levenberg-Marquardt takes from an infinite trust region: parameter
// blocks on their manifolds (the Jacobian taken through each manifold's PlusJacobian, the step
// applied by its Plus), residuals under a loss corrected as Ceres does (Triggs et al.: the residual
// and Jacobian scaled by sqrt(rho'), with the curvature term where rho'' > 0), and the step kept
// only if the cost falls by at least `min_relative_decrease` of what the linear model predicts;
// otherwise it is retried with Levenberg-Marquardt's damping (max_damped_steps), and where none
// passes the variables stay as they were. The blocks are linearised in parallel into one buffer,
// each into its own slot, and each variable's columns of J^T J and J^T r are summed in parallel
// (the columns are disjoint), every entry over its blocks in their order, so the result does not
// depend on the number of threads. The pattern and the symbolic analysis, which need no values, are
// built beside the first linearisation. Given a coarse space (GaussNewtonOptions::coarse), the
// step is solved by preconditioned conjugate gradients instead (optim/coarse_pcg.h), for
// systems whose Cholesky factor fills in.

#include <ceres/cost_function.h>
#include <ceres/loss_function.h>
#include <ceres/manifold.h>

#include <cstddef>
#include <string>
#include <unordered_map>
#include <vector>

#include "f2c/optim/block_matrix.h"
#include "f2c/optim/coarse_pcg.h"

namespace f2c {

struct GaussNewtonResidual {
  const ceres::CostFunction* cost = nullptr;
  const ceres::LossFunction* loss = nullptr;  // null: least squares
  std::vector<double*> blocks;
};

// A coarse space for the step by conjugate gradients (optim/coarse_pcg.h), keyed by the
// variables' addresses: each covered variable's step as combinations of the coarse blocks', and
// its smoother group. Free variables it does not name are coarse blocks of their own.
struct CoarseSpace {
  std::vector<int> block_sizes;
  std::unordered_map<const double*, std::vector<CoarseBasis>> basis;
  std::unordered_map<const double*, int> group;
};

struct GaussNewtonOptions {
  int max_iterations = 1;
  // Stop once a step changes the cost by less than this fraction of it (Ceres' meaning).
  double function_tolerance = 1e-6;
  // A step is kept if (cost - new cost) / (the model's predicted decrease) exceeds this
  // (Ceres' default).
  double min_relative_decrease = 1e-3;
  // A rejected step is retried this many times, damped as Levenberg-Marquardt damps it (H + lambda
  // diag(H), lambda = initial_damping, then times damping_increase), before the variables are left
  // where they were. Why: the undamped step can run far along a direction little holds (a gauge
  // held only by a weak E_I; a plane that barely moves its residuals), where the linear model no
  // longer holds and the cost rises; a damped step still makes progress in the directions that are
  // well held. 0: no retry. Measured: no step of the refinement's walks or real sequences is
  // rejected, so they run as before; refine_test's exact room with w_I 1e-9 and frame 0 free, whose
  // every step after the first was rejected, converges.
  int max_damped_steps = 4;
  double initial_damping = 1e-3;
  double damping_increase = 10;
  // CHOLMOD's fill-reducing ordering: AMD, or CHOLMOD's nested dissection (METIS) on the graph of
  // the blocks, each block's columns kept together. Measured, analysis and factorization together:
  // the same at 900 frames, and nested dissection 2% ahead at 2,001 (less fill from the loops for a
  // longer analysis); for the planes-only presolve, whose system is nearly block-diagonal, AMD.
  using Ordering = FillOrdering;
  Ordering ordering = Ordering::kNestedDissection;
  // Where set, the step by conjugate gradients preconditioned with this coarse space instead
  // of Cholesky; a solve that ends above pcg_accept (relative residual) is redone by Cholesky.
  const CoarseSpace* coarse = nullptr;
  TwoLevelPcgOptions pcg;
  double pcg_accept = 1e-3;
  // The residual blocks are linearised a chunk of at most this many doubles at a time (a
  // chunk holds at least one block), each summed into the normal equations before the next:
  // the same sums in the same order as one buffer for all, in memory that does not grow
  // with the scan.
  size_t linearisation_chunk = size_t{1} << 21;
};

struct GaussNewtonSummary {
  double initial_cost = 0;  // 1/2 sum of robustified squares, as Ceres counts it
  double final_cost = 0;
  int iterations = 0;  // steps tried
  int accepted = 0;    // steps kept
  int damped = 0;      // damped retries of rejected steps (each one more factorization)
  // False where the normal equations were not positive definite (a direction nothing
  // constrains): nothing moved, and the caller may solve another way.
  bool factorized = true;
  // Whether CHOLMOD chose a supernodal factor (dense blocks, BLAS) over a simplicial one.
  bool supernodal = false;
  int factorizations = 0;        // Cholesky factorizations
  int linear_iterations = 0;     // conjugate gradients' steps, over every solve
  double relative_residual = 0;  // the largest |H step + g| / |g| the conjugate gradients left
  std::string termination;
};

class GaussNewtonProblem {
 public:
  // A parameter block of `size` doubles at `x`; `manifold` null: Euclidean. Constant blocks
  // enter the residuals but do not move.
  void AddVariable(double* x, int size, const ceres::Manifold* manifold, bool constant);
  bool HasVariable(const double* x) const { return index_.count(x) > 0; }

  // Up to options.max_iterations steps over `residuals`, whose blocks must all be variables.
  GaussNewtonSummary Solve(const std::vector<GaussNewtonResidual>& residuals, const GaussNewtonOptions& options) const;

 private:
  struct Variable {
    double* x;
    int size;
    const ceres::Manifold* manifold;
    bool constant;
  };
  std::vector<Variable> variables_;
  std::unordered_map<const double*, int> index_;
};

}  // namespace f2c
