#pragma once
// Every constraint of one term between one pair of frames as a single Ceres residual block.
// With one block per correspondence, Ceres' per-block work (building the problem, the
// Jacobian's structure, J^T J's sparsity) cost more than the arithmetic: 40,000 blocks took
// about 0.2 s per solve. Batched per pair there are a few thousand.
//
// Robust losses are applied inside, per constraint, by iteratively reweighted least squares:
// constraint i with residual r_i (unweighted, metres) costs 1/2 w_i rho(|r_i|^2); the block
// returns r'_i = sqrt(w_i rho'(s_i)) r_i with s_i = |r_i|^2 at the poses it was built with (the
// iteration's linearisation point), so one Gauss-Newton step is the IRLS step of ICP. The
// weights stay fixed while Ceres iterates; the refinement rebuilds the blocks every
// iteration. RobustCost() gives the true robust cost for summaries.

#include <ceres/cost_function.h>

#include <string>
#include <vector>

#include "f2c/optim/cost_functions.h"
#include "f2c/util/fields.h"

namespace f2c {

enum class RobustLoss { kNone, kHuber, kCauchy };
F2C_ENUM_NAMES(RobustLoss,
               {{RobustLoss::kNone, "none"}, {RobustLoss::kHuber, "huber"}, {RobustLoss::kCauchy, "cauchy"}})

// rho(s) and rho'(s) of a loss with scale c (residual units): none s; Huber s up to c^2, then
// 2 c sqrt(s) - c^2; Cauchy c^2 log(1 + s / c^2).
void EvaluateLoss(RobustLoss loss, double scale, double s, double* rho, double* rho_prime);

struct PairConstraint {
  ConstraintKind kind = ConstraintKind::kPointToPlane;
  double weight = 1;                                       // w_i: the residual is scaled by sqrt(w_i) before the loss
  Eigen::Vector3d target_point = Eigen::Vector3d::Zero();  // frame a
  Eigen::Vector3d target_direction = Eigen::Vector3d::Zero();  // frame a (planes, lines)
  Eigen::Vector3d point = Eigen::Vector3d::Zero();             // frame b
};

// Parameter blocks q_a (4), t_a (3), q_b (4), t_b (3); `parameters` are their values now, at
// which the IRLS weights are taken.
class PairCost final : public ceres::CostFunction {
 public:
  PairCost(std::vector<PairConstraint> constraints, RobustLoss loss, double scale, double const* const* parameters);
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;
  // sum_i 1/2 w_i rho(|r_i|^2) at `parameters`.
  double RobustCost(double const* const* parameters) const;

 private:
  std::vector<PairConstraint> constraints_;
  std::vector<int> offsets_;          // first residual row of each constraint
  std::vector<double> sqrt_weights_;  // sqrt(w_i rho'(s_i)) at construction
  RobustLoss loss_;
  double scale_;
};

}  // namespace f2c
