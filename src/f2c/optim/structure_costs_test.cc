#include "f2c/optim/structure_costs.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "f2c/optim/test_helpers.h"
#include "f2c/optim/pose.h"

namespace f2c {
namespace {

// Members of a proxy in camera coordinates: points of the world plane {n . x = d} (plus
// `off` along n), seen from `pose`; their centroid and population covariance.
struct Members {
  std::vector<Eigen::Vector3d> points;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
};

Members MembersOf(const Pose& pose, const Eigen::Vector3d& n, double d, std::mt19937& rng, double noise) {
  std::normal_distribution<double> g(0.0, 1.0);
  const Eigen::Vector3d u = n.unitOrthogonal(), v = n.cross(u);
  Members m;
  for (int i = 0; i < 40; ++i) {
    const Eigen::Vector3d world = d * n + 0.7 * g(rng) * u + 0.4 * g(rng) * v + noise * g(rng) * n;
    m.points.push_back(pose.rotation.conjugate() * (world - pose.translation));
  }
  for (const auto& p : m.points) m.centroid += p / m.points.size();
  for (const auto& p : m.points) m.covariance += (p - m.centroid) * (p - m.centroid).transpose() / m.points.size();
  return m;
}

class StructureCosts : public ::testing::Test {
 protected:
  ceres::EigenQuaternionManifold quaternion_;
  PlaneManifold plane_;
  std::mt19937 rng_{11};
};

TEST_F(StructureCosts, SqrtCovarianceSquaresToTheCovariance) {
  Eigen::Matrix3d a = Eigen::Matrix3d::Random();
  const Eigen::Matrix3d sigma = a * a.transpose();
  const Eigen::Matrix3d s = SqrtCovariance(sigma);
  EXPECT_LT((s.transpose() * s - sigma).norm(), 1e-12);
}

TEST_F(StructureCosts, ProxyFitVanishesOnThePlaneAndIsTheMeanSquaredDistanceOffIt) {
  Pose pose = RandomPose(rng_);
  Eigen::Vector3d n = Eigen::Vector3d(0.3, -0.5, 0.8).normalized();
  double d = 1.7;
  const Members exact = MembersOf(pose, n, d, rng_, 0.0);
  std::unique_ptr<ceres::CostFunction> cost(ProxyFitCost::Create(exact.centroid, SqrtCovariance(exact.covariance)));
  Eigen::Vector4d plane(n.x(), n.y(), n.z(), d);
  std::vector<double*> blocks = {pose.rotation_data(), pose.translation_data(), plane.data()};
  // Zero up to rounding: 4e-9 m with clang at -O1 (the square root of the covariance).
  for (double r : Residuals(*cost, blocks)) EXPECT_NEAR(r, 0, 1e-8);

  // Noisy members against a plane moved by 3 cm: |r|^2 is their mean squared distance,
  // summed point by point here.
  const Members noisy = MembersOf(pose, n, d, rng_, 0.01);
  cost.reset(ProxyFitCost::Create(noisy.centroid, SqrtCovariance(noisy.covariance)));
  const double moved = d + 0.03;
  plane[3] = moved;
  double expected = 0;
  for (const auto& x : noisy.points) expected += std::pow(n.dot(pose.rotation * x + pose.translation) - moved, 2);
  expected /= noisy.points.size();
  double got = 0;
  for (double r : Residuals(*cost, blocks)) got += r * r;
  EXPECT_NEAR(got, expected, 1e-12);
  EXPECT_GT(got, 0.02 * 0.02);
  ExpectJacobiansMatch(*cost, blocks, {&quaternion_, nullptr, &plane_});
}

TEST_F(StructureCosts, CoplanarityVanishesForTheSamePlaneAndIsHandComputedOtherwise) {
  Eigen::Vector4d parent(0, 0, 1, 0), child(0, 0, 1, 0);  // (n, d)
  std::unique_ptr<ceres::CostFunction> cost(CoplanarityCost::Create(Eigen::Vector3d(1, 2, 0.3), 2.0));
  std::vector<double*> blocks = {child.data(), parent.data()};
  for (double r : Residuals(*cost, blocks)) EXPECT_NEAR(r, 0, 1e-12);  // the anchor need not lie on it

  // The child 0.1 m above: its foot of the anchor is (1, 2, 0.1), 0.1 m off the parent.
  child[3] = 0.1;
  std::vector<double> r = Residuals(*cost, blocks);
  EXPECT_NEAR(r[0], 0.1, 1e-12);
  EXPECT_NEAR(r[1], 0, 1e-12);
  // Tilted by a about y through the origin: foot p = a - (n . a) n, r[0] = p_z, and the
  // normals differ by (sin a, 0, cos a - 1) at the lever arm 2.
  const double angle = 0.2;
  const Eigen::Vector3d child_n(std::sin(angle), 0, std::cos(angle));
  child << child_n, 0;
  const Eigen::Vector3d anchor(1, 2, 0.3);
  const Eigen::Vector3d foot = anchor - child_n.dot(anchor) * child_n;
  r = Residuals(*cost, blocks);
  EXPECT_NEAR(r[0], foot.z(), 1e-12);
  EXPECT_NEAR(r[1], 2 * std::sin(angle), 1e-12);
  EXPECT_NEAR(r[2], 0, 1e-12);
  EXPECT_NEAR(r[3], 2 * (std::cos(angle) - 1), 1e-12);
  std::unique_ptr<ceres::CostFunction> scaled(CoplanarityCost::Create(anchor, 2.0, 3.0));
  EXPECT_NEAR(Residuals(*scaled, blocks)[1], 3 * r[1], 1e-12);
  child[3] = 0.05;
  ExpectJacobiansMatch(*cost, blocks, {&plane_, &plane_});
}

TEST_F(StructureCosts, RelationsVanishWhenMetAndAreHandComputedOtherwise) {
  Eigen::Vector4d a(1, 0, 0, 0.5), b(1, 0, 0, -2);  // the offsets do not enter
  std::unique_ptr<ceres::CostFunction> parallel(ParallelCost::Create(1.0));
  std::unique_ptr<ceres::CostFunction> antiparallel(ParallelCost::Create(-1.0, 2.0));
  std::unique_ptr<ceres::CostFunction> orthogonal(OrthogonalCost::Create(3.0));
  std::vector<double*> blocks = {a.data(), b.data()};
  for (double r : Residuals(*parallel, blocks)) EXPECT_NEAR(r, 0, 1e-15);
  b.head<3>() = -a.head<3>();
  for (double r : Residuals(*antiparallel, blocks)) EXPECT_NEAR(r, 0, 1e-15);
  b.head<3>() = Eigen::Vector3d(0, 0, 1);
  EXPECT_NEAR(Residuals(*orthogonal, blocks)[0], 0, 1e-15);

  const double theta = 80 * M_PI / 180;
  b.head<3>() = Eigen::Vector3d(std::cos(theta), std::sin(theta), 0);
  EXPECT_NEAR(Residuals(*orthogonal, blocks)[0], 3 * std::cos(theta), 1e-15);
  std::vector<double> r = Residuals(*parallel, blocks);
  EXPECT_NEAR(r[0], 1 - std::cos(theta), 1e-15);
  EXPECT_NEAR(r[1], -std::sin(theta), 1e-15);
  r = Residuals(*antiparallel, blocks);
  EXPECT_NEAR(r[0], 2 * (1 + std::cos(theta)), 1e-15);
  for (auto* cost : {parallel.get(), antiparallel.get(), orthogonal.get()}) {
    ExpectJacobiansMatch(*cost, blocks, {&plane_, &plane_});
  }
}

TEST_F(StructureCosts, PlaneChangeVanishesAtThePreviousPlaneAndMeasuresTheChange) {
  const Eigen::Vector3d n0 = Eigen::Vector3d(1, 2, 2) / 3;
  Eigen::Vector4d plane(n0.x(), n0.y(), n0.z(), 0.5);
  std::unique_ptr<ceres::CostFunction> cost(PlaneChangeCost::Create(n0, 0.5, 2.0, 3.0));
  std::vector<double*> blocks = {plane.data()};
  for (double r : Residuals(*cost, blocks)) EXPECT_NEAR(r, 0, 1e-15);
  plane << 0, 0, 1, 0.6;
  const std::vector<double> r = Residuals(*cost, blocks);
  EXPECT_NEAR(r[2], 2 * (1 - 2.0 / 3), 1e-15);
  EXPECT_NEAR(r[3], 3 * 0.1, 1e-12);
  ExpectJacobiansMatch(*cost, blocks, {&plane_});
}

// With reference points the same planes give the same residuals: an offset e from x_0 is
// d = n . x_0 + e from the origin.
TEST_F(StructureCosts, ReferencePointsOnlyMoveWhereOffsetsAreMeasuredFrom) {
  std::mt19937 rng(5);
  Pose pose = RandomPose(rng);
  Eigen::Vector3d n = Eigen::Vector3d(0.2, 0.9, -0.3).normalized(),
                  n_p = Eigen::Vector3d(0.25, 0.88, -0.3).normalized();
  double d = 1.3, d_p = 1.25;
  const Members members = MembersOf(pose, n, d, rng, 0.01);
  const Eigen::Vector3d x0(0.5, -1, 2), x0_p(3, 1, -1), anchor(1, 1, 1);
  Eigen::Vector4d plane_d(n.x(), n.y(), n.z(), d), plane_e(n.x(), n.y(), n.z(), d - n.dot(x0));
  Eigen::Vector4d parent_d(n_p.x(), n_p.y(), n_p.z(), d_p), parent_e(n_p.x(), n_p.y(), n_p.z(), d_p - n_p.dot(x0_p));
  const Eigen::Matrix3d sqrt_cov = SqrtCovariance(members.covariance);
  std::unique_ptr<ceres::CostFunction> fit(ProxyFitCost::Create(members.centroid, sqrt_cov));
  std::unique_ptr<ceres::CostFunction> fit_ref(ProxyFitCost::Create(members.centroid, sqrt_cov, x0));
  const std::vector<double> a = Residuals(*fit, {pose.rotation_data(), pose.translation_data(), plane_d.data()});
  const std::vector<double> b = Residuals(*fit_ref, {pose.rotation_data(), pose.translation_data(), plane_e.data()});
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(a[i], b[i], 1e-12);
  std::unique_ptr<ceres::CostFunction> cop(CoplanarityCost::Create(anchor, 1.5, 2.0));
  std::unique_ptr<ceres::CostFunction> cop_ref(CoplanarityCost::Create(anchor, 1.5, 2.0, x0, x0_p));
  const std::vector<double> c = Residuals(*cop, {plane_d.data(), parent_d.data()});
  const std::vector<double> f = Residuals(*cop_ref, {plane_e.data(), parent_e.data()});
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(c[i], f[i], 1e-12);
  EXPECT_GT(std::abs(c[0]), 0.01);
  ExpectJacobiansMatch(*fit_ref, {pose.rotation_data(), pose.translation_data(), plane_e.data()},
                       {&quaternion_, nullptr, &plane_});
  ExpectJacobiansMatch(*cop_ref, {plane_e.data(), parent_e.data()}, {&plane_, &plane_});
}

}  // namespace
}  // namespace f2c
