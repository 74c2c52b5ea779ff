#include "f2c/optim/cost_functions.h"

#include <ceres/gradient_checker.h>
#include <ceres/manifold.h>
#include <gtest/gtest.h>

#include <memory>
#include <random>
#include <vector>

#include "f2c/optim/test_helpers.h"
#include "f2c/optim/pair_cost.h"
#include "f2c/optim/pose.h"

namespace f2c {
namespace {

class CostFunctions : public ::testing::Test {
 protected:
  void SetUp() override {
    std::mt19937 rng(7);
    a_ = RandomPose(rng);
    b_ = RandomPose(rng);
  }
  Eigen::Vector3d InCamera(const Pose& pose, const Eigen::Vector3d& x_world) const {
    return pose.rotation.conjugate() * (x_world - pose.translation);
  }
  std::vector<double*> Blocks() {
    return {a_.rotation_data(), a_.translation_data(), b_.rotation_data(), b_.translation_data()};
  }
  std::vector<const ceres::Manifold*> Manifolds() { return {&quaternion_, nullptr, &quaternion_, nullptr}; }

  Pose a_, b_;
  ceres::EigenQuaternionManifold quaternion_;
};

TEST_F(CostFunctions, PointToPlaneVanishesForAnyPointOfThePlane) {
  // Plane n . x = 0.7 in the world; frames see different points of it.
  const Eigen::Vector3d n_world = Eigen::Vector3d(1, 2, -2).normalized();
  const Eigen::Vector3d x_a = 0.7 * n_world + Eigen::Vector3d(2, -1, 0).normalized() * 0.4;
  const Eigen::Vector3d x_b = 0.7 * n_world + n_world.cross(Eigen::Vector3d::UnitZ()).normalized() * -1.3;
  std::unique_ptr<ceres::CostFunction> cost(
      PointToPlaneCost::Create(InCamera(a_, x_a), a_.rotation.conjugate() * n_world, InCamera(b_, x_b)));
  EXPECT_NEAR(Residuals(*cost, Blocks())[0], 0.0, 1e-12);
  // Moving frame b 3 cm along the normal moves its point off the plane by 3 cm.
  b_.translation += 0.03 * n_world;
  EXPECT_NEAR(Residuals(*cost, Blocks())[0], 0.03, 1e-12);
  ExpectJacobiansMatch(*cost, Blocks(), Manifolds());
}

TEST_F(CostFunctions, PointToPlaneHandComputed) {
  a_ = Pose();
  b_ = Pose();
  b_.translation = Eigen::Vector3d(0, 0, 0.1);
  std::unique_ptr<ceres::CostFunction> cost(PointToPlaneCost::Create({0, 0, 1}, {0, 0, 1}, {0.3, 0.2, 1.05}));
  // p_b in the world is (0.3, 0.2, 1.15): 0.15 m above the plane z = 1.
  EXPECT_NEAR(Residuals(*cost, Blocks())[0], 0.15, 1e-12);
}

TEST_F(CostFunctions, PointToLineVanishesOnTheLineAndMeasuresTheDistance) {
  const Eigen::Vector3d direction = Eigen::Vector3d(0.2, -1, 0.4).normalized();
  const Eigen::Vector3d x_a(0.3, 0.1, 2.0);
  const Eigen::Vector3d x_b = x_a + 0.8 * direction;
  std::unique_ptr<ceres::CostFunction> cost(
      PointToLineCost::Create(InCamera(a_, x_a), a_.rotation.conjugate() * direction, InCamera(b_, x_b)));
  for (double r : Residuals(*cost, Blocks())) EXPECT_NEAR(r, 0.0, 1e-12);
  // 2 cm perpendicular to the line.
  const Eigen::Vector3d off = direction.cross(Eigen::Vector3d::UnitX()).normalized();
  b_.translation += 0.02 * off;
  const std::vector<double> r = Residuals(*cost, Blocks());
  EXPECT_NEAR(Eigen::Vector3d(r[0], r[1], r[2]).norm(), 0.02, 1e-12);
  ExpectJacobiansMatch(*cost, Blocks(), Manifolds());
}

TEST_F(CostFunctions, PointToLineHandComputed) {
  a_ = Pose();
  b_ = Pose();
  std::unique_ptr<ceres::CostFunction> cost(PointToLineCost::Create({0, 0, 1}, {1, 0, 0}, {0.3, 0.02, 1.05}));
  // (0.3, 0.02, 0.05) x (1, 0, 0) = (0, 0.05, -0.02).
  const std::vector<double> r = Residuals(*cost, Blocks());
  EXPECT_NEAR(r[0], 0.0, 1e-12);
  EXPECT_NEAR(r[1], 0.05, 1e-12);
  EXPECT_NEAR(r[2], -0.02, 1e-12);
}

TEST_F(CostFunctions, RelativePoseVanishesAtTheMeasurement) {
  const Rigid3d a_from_b = a_.ToRigid().inverse() * b_.ToRigid();
  std::unique_ptr<ceres::CostFunction> cost(
      RelativePoseCost::Create(Eigen::Quaterniond(a_from_b.linear()), a_from_b.translation(), 3.0, 5.0));
  for (double r : Residuals(*cost, Blocks())) EXPECT_NEAR(r, 0.0, 1e-12);
  // The same relative motion anywhere in the world: still zero.
  const Rigid3d moved = Pose{Eigen::Quaterniond(Eigen::AngleAxisd(1.0, Eigen::Vector3d::UnitY())), {4, 5, 6}}.ToRigid();
  a_ = Pose::FromRigid(moved * a_.ToRigid());
  b_ = Pose::FromRigid(moved * b_.ToRigid());
  for (double r : Residuals(*cost, Blocks())) EXPECT_NEAR(r, 0.0, 1e-12);
  ExpectJacobiansMatch(*cost, Blocks(), Manifolds());
}

TEST_F(CostFunctions, RelativePoseHandComputed) {
  a_ = Pose();
  b_ = Pose();
  b_.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitZ()));
  b_.translation = Eigen::Vector3d(1, 0, 0);
  // Measured: no rotation, 0.9 m along x. Errors: 0.1 m along x, 0.1 rad about z.
  std::unique_ptr<ceres::CostFunction> cost(
      RelativePoseCost::Create(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.9, 0, 0), 2.0, 3.0));
  const std::vector<double> r = Residuals(*cost, Blocks());
  EXPECT_NEAR(r[0], 2.0 * 0.1, 1e-12);
  EXPECT_NEAR(r[1], 0.0, 1e-12);
  EXPECT_NEAR(r[3], 0.0, 1e-12);
  EXPECT_NEAR(r[5], 3.0 * 2.0 * std::sin(0.05), 1e-12);
}

// With a full square root of the information, r = M e: the errors of the test above mixed
// by M's rows, and the Jacobians still those of the residual.
TEST_F(CostFunctions, RelativePoseWhitenedByAFullMatrix) {
  a_ = Pose();
  b_ = Pose();
  b_.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitZ()));
  b_.translation = Eigen::Vector3d(1, 0, 0);
  Eigen::Matrix<double, 6, 6> m = Eigen::Matrix<double, 6, 6>::Zero();
  m(0, 0) = 2, m(0, 5) = 0.5, m(1, 1) = 1, m(5, 5) = 4, m(2, 0) = -1;
  std::unique_ptr<ceres::CostFunction> cost(
      RelativePoseCost::Create(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.9, 0, 0), m));
  const double turn = 2.0 * std::sin(0.05);  // e[5]; e[0] = 0.1 m
  const std::vector<double> r = Residuals(*cost, Blocks());
  EXPECT_NEAR(r[0], 2 * 0.1 + 0.5 * turn, 1e-12);
  EXPECT_NEAR(r[1], 0.0, 1e-12);
  EXPECT_NEAR(r[2], -0.1, 1e-12);
  EXPECT_NEAR(r[5], 4 * turn, 1e-12);
  b_.translation = Eigen::Vector3d(0.7, 0.2, -0.1);
  b_.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 2, 3).normalized()));
  ExpectJacobiansMatch(*cost, Blocks(), Manifolds());
}

TEST_F(CostFunctions, PoseChangeVanishesAtThePreviousPoseAndMeasuresTheChange) {
  std::unique_ptr<ceres::CostFunction> cost(PoseChangeCost::Create(a_.rotation, a_.translation, 1.0, 2.0));
  std::vector<double*> blocks = {a_.rotation_data(), a_.translation_data()};
  for (double r : Residuals(*cost, blocks)) EXPECT_NEAR(r, 0.0, 1e-12);
  a_.translation += Eigen::Vector3d(0, 0.04, 0);
  a_.rotation = a_.rotation * Eigen::Quaterniond(Eigen::AngleAxisd(0.02, Eigen::Vector3d::UnitX()));
  const std::vector<double> r = Residuals(*cost, blocks);
  EXPECT_NEAR(r[1], 0.04, 1e-12);
  EXPECT_NEAR(r[3], 2.0 * 2.0 * std::sin(0.01), 1e-12);
  ceres::EigenQuaternionManifold quaternion;
  ExpectJacobiansMatch(*cost, blocks, {&quaternion, nullptr});
}

// E_V: a screw motion (the same body-frame turn and the same world step each interval)
// costs nothing, wherever it is and however fast; a frame turned or moved off it does.
TEST_F(CostFunctions, SteadyMotionVanishesForAConstantVelocity) {
  const Eigen::Quaterniond turn(Eigen::AngleAxisd(0.05, Eigen::Vector3d(0.3, -1, 0.2).normalized()));
  const Eigen::Vector3d step(0.02, -0.01, 0.03);
  Pose c = a_;
  b_ = a_;
  b_.rotation = a_.rotation * turn;
  b_.translation = a_.translation + step;
  c.rotation = b_.rotation * turn;
  c.translation = b_.translation + step;
  std::vector<double*> blocks = {a_.rotation_data(),    a_.translation_data(), b_.rotation_data(),
                                 b_.translation_data(), c.rotation_data(),     c.translation_data()};
  std::unique_ptr<ceres::CostFunction> cost(SteadyMotionCost::Create(1.0, 1.0, 2.0, 3.0));
  for (double r : Residuals(*cost, blocks)) EXPECT_NEAR(r, 0.0, 1e-12);
  // The second interval twice as long (a dropped frame): twice the turn and the step, scaled
  // by 1/2, is the same velocity.
  c.rotation = b_.rotation * turn * turn;
  c.translation = b_.translation + 2 * step;
  std::unique_ptr<ceres::CostFunction> gap(SteadyMotionCost::Create(1.0, 0.5, 2.0, 3.0));
  for (double r : Residuals(*gap, blocks)) EXPECT_NEAR(r, 0.0, 1e-12);
  // Read as one interval, the same poses are a jolt.
  const std::vector<double> jolt = Residuals(*cost, blocks);
  EXPECT_NEAR(jolt[0], 2.0 * 0.02, 1e-12);  // one more step of 0.02 m along x, at s_t = 2
  const std::vector<const ceres::Manifold*> manifolds = {&quaternion_, nullptr,      &quaternion_,
                                                         nullptr,      &quaternion_, nullptr};
  ExpectJacobiansMatch(*cost, blocks, manifolds);
  ExpectJacobiansMatch(*gap, blocks, manifolds);
}

TEST_F(CostFunctions, SteadyMotionHandComputed) {
  // a and b at rest at the origin; c turned 0.1 rad about z and moved 0.05 m along x.
  a_ = Pose();
  b_ = Pose();
  Pose c;
  c.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitZ()));
  c.translation = Eigen::Vector3d(0.05, 0, 0);
  std::vector<double*> blocks = {a_.rotation_data(),    a_.translation_data(), b_.rotation_data(),
                                 b_.translation_data(), c.rotation_data(),     c.translation_data()};
  std::unique_ptr<ceres::CostFunction> cost(SteadyMotionCost::Create(1.0, 0.5, 2.0, 3.0));
  const std::vector<double> r = Residuals(*cost, blocks);
  EXPECT_NEAR(r[0], 2.0 * 0.5 * 0.05, 1e-12);
  EXPECT_NEAR(r[1], 0.0, 1e-12);
  EXPECT_NEAR(r[3], 0.0, 1e-12);
  EXPECT_NEAR(r[5], 3.0 * 0.5 * 0.1, 1e-12);
}

// The hand-written E_C kernels (EvaluateConstraint, here through a one-constraint PairCost with
// no loss) compute the AutoDiff functors' residuals and Jacobians exactly, at unit and
// non-unit quaternions alike, and pass the same central-difference checks.
TEST_F(CostFunctions, AnalyticCostsEqualTheirAutoDiffFunctors) {
  std::mt19937 rng(11);
  std::normal_distribution<double> g(0, 1);
  for (int trial = 0; trial < 20; ++trial) {
    a_ = RandomPose(rng);
    b_ = RandomPose(rng);
    if (trial % 2) a_.rotation.coeffs() *= 1.3;  // off the sphere
    const Eigen::Vector3d p_a(g(rng), g(rng), 2 + g(rng)), p_b(g(rng), g(rng), 2 + g(rng));
    const Eigen::Vector3d dir = Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
    for (int line = 0; line < 2; ++line) {
      std::unique_ptr<ceres::CostFunction> reference(line ? PointToLineCost::Create(p_a, dir, p_b)
                                                          : PointToPlaneCost::Create(p_a, dir, p_b));
      PairConstraint c;
      c.kind = line ? ConstraintKind::kPointToLine : ConstraintKind::kPointToPlane;
      c.target_point = p_a;
      c.target_direction = dir;
      c.point = p_b;
      std::unique_ptr<ceres::CostFunction> analytic(new PairCost({c}, RobustLoss::kNone, 1.0, Blocks().data()));
      const int m = reference->num_residuals();
      ASSERT_EQ(analytic->num_residuals(), m);
      std::vector<double> r1(m), r2(m), j1(m * 14), j2(m * 14);
      double* jac1[4] = {j1.data(), j1.data() + 4 * m, j1.data() + 7 * m, j1.data() + 11 * m};
      double* jac2[4] = {j2.data(), j2.data() + 4 * m, j2.data() + 7 * m, j2.data() + 11 * m};
      std::vector<double*> blocks = Blocks();
      ASSERT_TRUE(reference->Evaluate(blocks.data(), r1.data(), jac1));
      ASSERT_TRUE(analytic->Evaluate(blocks.data(), r2.data(), jac2));
      for (int i = 0; i < m; ++i) EXPECT_NEAR(r1[i], r2[i], 1e-12);
      for (int i = 0; i < m * 14; ++i) EXPECT_NEAR(j1[i], j2[i], 1e-11) << "line " << line << " entry " << i;
      if (trial == 0) ExpectJacobiansMatch(*analytic, blocks, Manifolds());
    }
  }
}

}  // namespace
}  // namespace f2c
