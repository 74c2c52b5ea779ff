#include "f2c/optim/pair_cost.h"

#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include <memory>
#include <random>

#include "f2c/optim/pose.h"

namespace f2c {
namespace {

struct Fixture {
  Pose a, b;
  std::vector<PairConstraint> constraints;
  std::vector<double*> Blocks() {
    return {a.rotation_data(), a.translation_data(), b.rotation_data(), b.translation_data()};
  }
};

// Poses and constraints of every kind with residuals from millimetres to decimetres, so a
// Cauchy loss of 2 cm sees both sides of its scale.
Fixture MakeFixture() {
  std::mt19937 rng(4);
  std::normal_distribution<double> g(0, 1);
  Fixture f;
  f.a.rotation = Eigen::Quaterniond(1, 0.1, -0.2, 0.05).normalized();
  f.a.translation = {0.3, -0.1, 0.2};
  f.b.rotation = Eigen::Quaterniond(1, -0.05, 0.1, 0.2).normalized();
  f.b.translation = {0.1, 0.2, -0.3};
  for (int i = 0; i < 12; ++i) {
    PairConstraint c;
    c.kind = static_cast<ConstraintKind>(i % 3);
    c.weight = 0.5 + 0.1 * i;
    c.target_point = Eigen::Vector3d(g(rng), g(rng), 2 + g(rng));
    c.target_direction = Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
    // The point frame b sees, offset from the target by 1 mm .. 20 cm.
    const Eigen::Vector3d world = f.a.ToRigid() * c.target_point +
                                  0.001 * std::pow(1.6, i) * Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
    c.point = f.b.ToRigid().inverse() * world;
    f.constraints.push_back(c);
  }
  return f;
}

ceres::CostFunction* Single(const PairConstraint& c) {
  switch (c.kind) {
    case ConstraintKind::kPointToPlane:
      return PointToPlaneCost::Create(c.target_point, c.target_direction, c.point);
    case ConstraintKind::kPointToLine:
      return PointToLineCost::Create(c.target_point, c.target_direction, c.point);
    case ConstraintKind::kPointToPoint:
      return PointToPointCost::Create(c.target_point, c.point);
  }
  return nullptr;
}

// The reference: one AutoDiff block per constraint with Ceres' ScaledLoss(Cauchy(0.02), w).
void ReferenceCostAndGradient(Fixture& f, double* cost, std::vector<double>* gradient) {
  ceres::Problem::Options po;
  po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(po);
  for (const PairConstraint& c : f.constraints) {
    problem.AddResidualBlock(
        Single(c), new ceres::ScaledLoss(new ceres::CauchyLoss(0.02), c.weight, ceres::TAKE_OWNERSHIP), f.Blocks());
  }
  ceres::Problem::EvaluateOptions eo;
  eo.parameter_blocks = f.Blocks();
  problem.Evaluate(eo, cost, nullptr, gradient, nullptr);
}

TEST(PairCost, RobustCostAndGradientEqualCeresLossesAtTheLinearisationPoint) {
  Fixture f = MakeFixture();
  double reference_cost;
  std::vector<double> reference_gradient;
  ReferenceCostAndGradient(f, &reference_cost, &reference_gradient);

  PairCost cost(f.constraints, RobustLoss::kCauchy, 0.02, f.Blocks().data());
  EXPECT_NEAR(cost.RobustCost(f.Blocks().data()), reference_cost, 1e-12 * reference_cost);
  // IRLS: J'^T r' = sum w rho'(s) J^T r, the robust gradient.
  ceres::Problem::Options po;
  ceres::Problem problem(po);
  problem.AddResidualBlock(new PairCost(f.constraints, RobustLoss::kCauchy, 0.02, f.Blocks().data()), nullptr,
                           f.Blocks());
  ceres::Problem::EvaluateOptions eo;
  eo.parameter_blocks = f.Blocks();
  double irls_cost;
  std::vector<double> gradient;
  problem.Evaluate(eo, &irls_cost, nullptr, &gradient, nullptr);
  ASSERT_EQ(gradient.size(), reference_gradient.size());
  for (size_t i = 0; i < gradient.size(); ++i) EXPECT_NEAR(gradient[i], reference_gradient[i], 1e-9) << i;
}

TEST(PairCost, JacobianEqualsCentralDifferences) {
  Fixture f = MakeFixture();
  PairCost cost(f.constraints, RobustLoss::kHuber, 0.02, f.Blocks().data());
  const int m = cost.num_residuals();
  ASSERT_EQ(m, 4 * 1 + 4 * 3 + 4 * 3);
  std::vector<double> j[4] = {std::vector<double>(m * 4), std::vector<double>(m * 3), std::vector<double>(m * 4),
                              std::vector<double>(m * 3)};
  double* jacobians[4] = {j[0].data(), j[1].data(), j[2].data(), j[3].data()};
  std::vector<double> r(m), plus(m), minus(m);
  std::vector<double*> blocks = f.Blocks();
  ASSERT_TRUE(cost.Evaluate(blocks.data(), r.data(), jacobians));
  const int sizes[4] = {4, 3, 4, 3};
  const double h = 1e-6;
  for (int b = 0; b < 4; ++b) {
    for (int k = 0; k < sizes[b]; ++k) {
      const double saved = blocks[b][k];
      blocks[b][k] = saved + h;
      cost.Evaluate(blocks.data(), plus.data(), nullptr);
      blocks[b][k] = saved - h;
      cost.Evaluate(blocks.data(), minus.data(), nullptr);
      blocks[b][k] = saved;
      for (int i = 0; i < m; ++i) EXPECT_NEAR(j[b][i * sizes[b] + k], (plus[i] - minus[i]) / (2 * h), 1e-7);
    }
  }
}

// The point-to-point kernel (E_M) against its AutoDiff functor.
TEST(PairCost, PointToPointKernelEqualsAutoDiff) {
  Fixture f = MakeFixture();
  const PairConstraint& c = f.constraints[2];
  ASSERT_EQ(c.kind, ConstraintKind::kPointToPoint);
  std::unique_ptr<ceres::CostFunction> reference(Single(c));
  double r[3], j0[12], j1[9], j2[12], j3[9];
  double* jac[4] = {j0, j1, j2, j3};
  std::vector<double*> blocks = f.Blocks();
  reference->Evaluate(blocks.data(), r, jac);
  ConstraintRows rows;
  EvaluateConstraint(c.kind, PosePair(blocks.data()), c.target_point, c.target_direction, c.point, true, &rows);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(rows.residual[i], r[i], 1e-12);
    for (int k = 0; k < 4; ++k) EXPECT_NEAR(rows.jacobian(i, k), j0[i * 4 + k], 1e-12);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(rows.jacobian(i, 4 + k), j1[i * 3 + k], 1e-12);
    for (int k = 0; k < 4; ++k) EXPECT_NEAR(rows.jacobian(i, 7 + k), j2[i * 4 + k], 1e-12);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(rows.jacobian(i, 11 + k), j3[i * 3 + k], 1e-12);
  }
}

TEST(EvaluateLoss, ValuesAndSlopes) {
  double rho, d;
  EvaluateLoss(RobustLoss::kCauchy, 0.1, 0.02, &rho, &d);
  EXPECT_NEAR(rho, 0.01 * std::log(3.0), 1e-15);
  EXPECT_NEAR(d, 1.0 / 3.0, 1e-15);
  EvaluateLoss(RobustLoss::kHuber, 0.1, 0.04, &rho, &d);  // |r| = 0.2 > 0.1
  EXPECT_NEAR(rho, 2 * 0.1 * 0.2 - 0.01, 1e-15);
  EXPECT_NEAR(d, 0.5, 1e-15);
  EvaluateLoss(RobustLoss::kNone, 0.1, 0.04, &rho, &d);
  EXPECT_EQ(rho, 0.04);
  EXPECT_EQ(d, 1.0);
}

}  // namespace
}  // namespace f2c
