#include "f2c/optim/structure_costs.h"

#include <Eigen/Eigenvalues>

#include "f2c/optim/constraints.h"

namespace f2c {

Eigen::Matrix3d SqrtCovariance(const Eigen::Matrix3d& covariance) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(0.5 * (covariance + covariance.transpose()));
  const Eigen::Vector3d root = eig.eigenvalues().cwiseMax(0.0).cwiseSqrt();
  // S = diag(sqrt(lambda)) V^T: S^T S = V diag(lambda) V^T.
  return root.asDiagonal() * eig.eigenvectors().transpose();
}

const char* RelationTypeName(RelationType type) {
  switch (type) {
    case RelationType::kParallel:
      return "parallel";
    case RelationType::kAntiparallel:
      return "antiparallel";
    case RelationType::kOrthogonal:
      return "orthogonal";
  }
  return "?";
}

}  // namespace f2c
