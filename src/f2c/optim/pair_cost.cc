#include "f2c/optim/pair_cost.h"

#include <fmt/format.h>

#include <cmath>

#include "f2c/util/error.h"

namespace f2c {

void EvaluateLoss(RobustLoss loss, double c, double s, double* rho, double* rho_prime) {
  const double c2 = c * c;
  switch (loss) {
    case RobustLoss::kNone:
      *rho = s;
      *rho_prime = 1;
      return;
    case RobustLoss::kHuber:
      if (s <= c2) {
        *rho = s;
        *rho_prime = 1;
      } else {
        const double r = std::sqrt(s);
        *rho = 2 * c * r - c2;
        *rho_prime = c / r;
      }
      return;
    case RobustLoss::kCauchy:
      *rho = c2 * std::log1p(s / c2);
      *rho_prime = 1 / (1 + s / c2);
      return;
  }
}

PairCost::PairCost(std::vector<PairConstraint> constraints, RobustLoss loss, double scale,
                   double const* const* parameters)
    : constraints_(std::move(constraints)), loss_(loss), scale_(scale) {
  int rows = 0;
  const PosePair poses(parameters);
  ConstraintRows r;
  for (const PairConstraint& c : constraints_) {
    offsets_.push_back(rows);
    rows += c.kind == ConstraintKind::kPointToPlane ? 1 : 3;
    EvaluateConstraint(c.kind, poses, c.target_point, c.target_direction, c.point, false, &r);
    double rho = 0, rho_prime = 0;
    EvaluateLoss(loss_, scale_, r.residual.head(r.rows).squaredNorm(), &rho, &rho_prime);
    sqrt_weights_.push_back(std::sqrt(c.weight * rho_prime));
  }
  set_num_residuals(rows);
  *mutable_parameter_block_sizes() = {4, 3, 4, 3};
}

bool PairCost::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  const PosePair poses(parameters);
  const bool want = jacobians != nullptr;
  const int offsets[4] = {0, 4, 7, 11}, sizes[4] = {4, 3, 4, 3};
  ConstraintRows rows;
  for (size_t i = 0; i < constraints_.size(); ++i) {
    const PairConstraint& c = constraints_[i];
    EvaluateConstraint(c.kind, poses, c.target_point, c.target_direction, c.point, want, &rows);
    const double w = sqrt_weights_[i];
    const int row0 = offsets_[i];
    for (int k = 0; k < rows.rows; ++k) residuals[row0 + k] = w * rows.residual[k];
    if (!want) continue;
    for (int b = 0; b < 4; ++b) {
      if (jacobians[b] == nullptr) continue;
      for (int k = 0; k < rows.rows; ++k) {
        double* out = jacobians[b] + (row0 + k) * sizes[b];
        for (int j = 0; j < sizes[b]; ++j) out[j] = w * rows.jacobian(k, offsets[b] + j);
      }
    }
  }
  return true;
}

double PairCost::RobustCost(double const* const* parameters) const {
  const PosePair poses(parameters);
  ConstraintRows rows;
  double cost = 0;
  for (const PairConstraint& c : constraints_) {
    EvaluateConstraint(c.kind, poses, c.target_point, c.target_direction, c.point, false, &rows);
    double rho = 0, rho_prime = 0;
    EvaluateLoss(loss_, scale_, rows.residual.head(rows.rows).squaredNorm(), &rho, &rho_prime);
    cost += 0.5 * c.weight * rho;
  }
  return cost;
}

}  // namespace f2c
