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

// Points 1.5-4 m in front of two cameras 20 cm and 5 degrees apart, each seen with the depth
// noise of a Kinect along its ray (sigma_z = 1.2 mm + 1.9 mm z^2) and a tenth of a pixel
// across it.
struct RayNoiseProblem {
  std::vector<Eigen::Vector3d> a, b;
  Rigid3d b_from_a;
};
RayNoiseProblem MakeRayNoiseProblem(int n, bool noisy, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> x(-1.5, 1.5), z(1.5, 4.0);
  std::normal_distribution<double> unit(0.0, 1.0);
  RayNoiseProblem p;
  p.b_from_a.linear() = Eigen::AngleAxisd(0.087, Eigen::Vector3d(0.2, 1, 0.1).normalized()).toRotationMatrix();
  p.b_from_a.translation() = Eigen::Vector3d(0.2, 0.02, -0.05);
  auto observe = [&](const Eigen::Vector3d& q) {
    if (!noisy) return q;
    const double sigma_z = 0.0012 + 0.0019 * q.z() * q.z();
    const Eigen::Vector3d ray = q.normalized();
    Eigen::Vector3d across(unit(rng), unit(rng), unit(rng));
    across -= across.dot(ray) * ray;
    return Eigen::Vector3d(q * (1 + sigma_z * unit(rng) / q.z()) + 0.0002 * q.norm() * across);
  };
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d q(x(rng), x(rng), z(rng));
    p.a.push_back(observe(q));
    p.b.push_back(observe(p.b_from_a * q));
  }
  return p;
}

TEST(RefineRigidAnisotropic, ExactPointsGiveTheTruthFromAFarStart) {
  const RayNoiseProblem p = MakeRayNoiseProblem(40, false, 7);
  std::vector<int> all(40);
  for (int i = 0; i < 40; ++i) all[i] = i;
  RansacOptions options;
  options.anisotropic_iterations = 10;
  const Rigid3d start = Rigid3d::Identity();  // 5 degrees and 20 cm off
  const Rigid3d t = RefineRigidAnisotropic(p.a, p.b, all, start, options);
  EXPECT_LT((t.matrix() - p.b_from_a.matrix()).norm(), 1e-6);
}

// Under noise along the rays, the ray-aware fit beats the isotropic least-squares fit.
TEST(RefineRigidAnisotropic, UnderRayNoiseBeatsTheIsotropicFit) {
  RansacOptions options;
  options.anisotropic_iterations = 5;
  double isotropic = 0, aware = 0;
  for (int trial = 0; trial < 20; ++trial) {
    const RayNoiseProblem p = MakeRayNoiseProblem(60, true, 100 + trial);
    std::vector<int> all(60);
    for (int i = 0; i < 60; ++i) all[i] = i;
    const Rigid3d plain = FitRigid(p.a, p.b, all);
    const Rigid3d refined = RefineRigidAnisotropic(p.a, p.b, all, plain, options);
    isotropic += (plain.translation() - p.b_from_a.translation()).squaredNorm();
    aware += (refined.translation() - p.b_from_a.translation()).squaredNorm();
  }
  EXPECT_LT(aware, 0.5 * isotropic) << "RMS " << std::sqrt(aware / 20) << " m against " << std::sqrt(isotropic / 20);
}

// The fit's information is its inverse covariance: over repeated draws of the same scene's
// ray noise, the ray-aware fit's error d (a left perturbation of the truth) has
// E[d^T H d] = 6 (chi-square with six degrees of freedom) and each direction's variance is
// H^-1's.
TEST(RigidFitInformation, IsTheRayAwareFitsInverseCovariance) {
  RansacOptions options;
  options.anisotropic_iterations = 5;
  options.bearing_sigma = 0.0002;  // MakeRayNoiseProblem's noise across the rays
  const RayNoiseProblem exact = MakeRayNoiseProblem(40, false, 3);
  std::vector<int> all(40);
  for (int i = 0; i < 40; ++i) all[i] = i;
  const Eigen::Matrix<double, 6, 6> h = RigidFitInformation(exact.a, exact.b, all, exact.b_from_a, options);
  const Eigen::Matrix<double, 6, 6> covariance = h.inverse();
  std::mt19937_64 rng(11);
  std::normal_distribution<double> unit(0.0, 1.0);
  auto observe = [&](const Eigen::Vector3d& q) {  // MakeRayNoiseProblem's noise
    const double sigma_z = 0.0012 + 0.0019 * q.z() * q.z();
    const Eigen::Vector3d ray = q.normalized();
    Eigen::Vector3d across(unit(rng), unit(rng), unit(rng));
    across -= across.dot(ray) * ray;
    return Eigen::Vector3d(q * (1 + sigma_z * unit(rng) / q.z()) + 0.0002 * q.norm() * across);
  };
  const int trials = 2000;
  double chi2 = 0;
  Eigen::Matrix<double, 6, 6> scatter = Eigen::Matrix<double, 6, 6>::Zero();
  for (int trial = 0; trial < trials; ++trial) {
    RayNoiseProblem p = exact;
    for (int i = 0; i < 40; ++i) {
      p.a[i] = observe(exact.a[i]);
      p.b[i] = observe(exact.b[i]);
    }
    const Rigid3d fit = RefineRigidAnisotropic(p.a, p.b, all, FitRigid(p.a, p.b, all), options);
    const Rigid3d error = fit * exact.b_from_a.inverse();  // exp(w, v)
    Eigen::Matrix<double, 6, 1> d;
    d.head<3>() = Eigen::AngleAxisd(error.linear()).angle() * Eigen::AngleAxisd(error.linear()).axis();
    d.tail<3>() = error.translation();
    chi2 += d.dot(h * d) / trials;
    scatter += d * d.transpose() / trials;
  }
  EXPECT_NEAR(chi2, 6.0, 0.5);
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(scatter(i, i) / covariance(i, i), 1.0, 0.15) << "direction " << i;
}

}  // namespace
}  // namespace f2c
