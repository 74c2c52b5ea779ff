#include "f2c/matching/ransac.h"

#include <gtest/gtest.h>

#include <random>

namespace f2c {
namespace {

struct Problem {
  std::vector<Eigen::Vector3d> a, b;
  Rigid3d b_from_a;
};

// n points in a 4 m box; the first `outliers` of them get a random b instead of T a.
Problem MakeProblem(int n, int outliers, double noise, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> box(-2.0, 2.0);
  std::normal_distribution<double> gauss(0.0, noise);
  Problem p;
  p.b_from_a = Rigid3d::Identity();
  p.b_from_a.linear() = Eigen::AngleAxisd(0.2, Eigen::Vector3d(0.3, 1, -0.2).normalized()).toRotationMatrix();
  p.b_from_a.translation() = Eigen::Vector3d(0.1, -0.05, 0.08);
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d a(box(rng), box(rng), box(rng) + 3);
    Eigen::Vector3d b = p.b_from_a * a + Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng));
    if (i < outliers) b = Eigen::Vector3d(box(rng), box(rng), box(rng) + 3);
    p.a.push_back(a);
    p.b.push_back(b);
  }
  return p;
}

TEST(EstimateRigidRansac, RecoversTransformDespiteFortyPercentOutliers) {
  const Problem p = MakeProblem(200, 80, 0.003, 1);
  const RansacResult r = EstimateRigidRansac(p.a, p.b, RansacOptions(), 7);
  EXPECT_GE(r.inliers.size(), 118u);
  EXPECT_LE(r.inliers.size(), 125u);  // a few random outliers may fall within 5 cm
  EXPECT_LT((r.b_from_a.translation() - p.b_from_a.translation()).norm(), 0.005);
  EXPECT_LT(RotationAngle(r.b_from_a.linear().transpose() * p.b_from_a.linear()), 0.002);
  for (int i : r.inliers) EXPECT_TRUE(i >= 80 || (r.b_from_a * p.a[i] - p.b[i]).norm() < 0.05);
}

TEST(EstimateRigidRansac, ExactDataGivesExactTransform) {
  const Problem p = MakeProblem(30, 0, 0.0, 2);
  const RansacResult r = EstimateRigidRansac(p.a, p.b, RansacOptions(), 0);
  EXPECT_EQ(r.inliers.size(), 30u);
  EXPECT_LT((r.b_from_a.matrix() - p.b_from_a.matrix()).norm(), 1e-9);
  EXPECT_LT(r.inlier_rmse, 1e-9);
}

TEST(EstimateRigidRansac, SameSeedSameAnswer) {
  const Problem p = MakeProblem(100, 50, 0.01, 3);
  const RansacResult r1 = EstimateRigidRansac(p.a, p.b, RansacOptions(), 42);
  const RansacResult r2 = EstimateRigidRansac(p.a, p.b, RansacOptions(), 42);
  EXPECT_EQ(r1.inliers, r2.inliers);
  EXPECT_EQ(r1.b_from_a.matrix(), r2.b_from_a.matrix());
}

TEST(EstimateRigidRansac, TooFewMatchesGiveNoInliers) {
  const Problem p = MakeProblem(2, 0, 0.0, 4);
  const RansacResult r = EstimateRigidRansac(p.a, p.b, RansacOptions(), 0);
  EXPECT_TRUE(r.inliers.empty());
  EXPECT_TRUE(r.b_from_a.matrix().isIdentity());
}

TEST(FitRigidWeighted, ZeroWeightIgnoresAnOutlier) {
  Problem p = MakeProblem(10, 0, 0.0, 5);
  p.b[0] += Eigen::Vector3d(1, 1, 1);
  std::vector<int> all(10);
  std::vector<double> w(10, 1.0);
  for (int i = 0; i < 10; ++i) all[i] = i;
  w[0] = 0.0;
  const Rigid3d t = FitRigidWeighted(p.a, p.b, all, w);
  EXPECT_LT((t.matrix() - p.b_from_a.matrix()).norm(), 1e-9);
  w[0] = 1.0;
  EXPECT_GT((FitRigidWeighted(p.a, p.b, all, w).matrix() - p.b_from_a.matrix()).norm(), 1e-3);
}

}  // namespace
}  // namespace f2c
