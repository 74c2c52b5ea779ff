#include "f2c/features/proxies.h"

#include <gtest/gtest.h>

#include "f2c/testing/synthetic_scene.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <cmath>
#include <random>

namespace f2c {
namespace {

using testing::kDeg;

// A wall seen obliquely: the plane n . x = d in camera coordinates, n turned 60 deg about the
// camera's vertical axis from facing it, 4 m away along the optical axis. The grid samples
// a 48 x 64 pixel patch (12 x 16 cells of 4 px) around the principal point, so the patch is
// narrow across the tilt and the least-squares bias is large.
struct ObliqueWall {
  Eigen::Vector3d normal = Eigen::Vector3d(std::sin(60 * kDeg), 0, -std::cos(60 * kDeg));  // towards the camera
  double offset = -4 * std::cos(60 * kDeg);                                                // normal . x
};

// Cells on the wall, their depth moved along the ray by Gaussian noise of sigma(z) (the
// options' sensor model; no noise when `seed` < 0). Every cell is flat with the true normal,
// so the proxy's members are exactly the cells and only its refit is under test.
PointGrid WallGrid(const ObliqueWall& wall, const ProxyOptions& o, int seed) {
  const double f = 525, cx = 319.5, cy = 239.5;
  PointGrid g;
  g.step = 4;
  g.width = 12;
  g.height = 16;
  std::mt19937 rng(seed < 0 ? 0 : seed);
  std::normal_distribution<double> gauss(0, 1);
  for (int y = 0; y < g.height; ++y) {
    for (int x = 0; x < g.width; ++x) {
      const Eigen::Vector3d ray((296 + x * 4 - cx) / f, (208 + y * 4 - cy) / f, 1);
      double z = wall.offset / wall.normal.dot(ray);
      const double dz = z - 0.4;
      if (seed >= 0) z += (o.sensor_sigma_a + o.sensor_sigma_b * dz * dz) * gauss(rng);
      g.points.push_back((z * ray).cast<float>());
      g.normals.push_back(wall.normal.cast<float>());
      g.curvature.push_back(0);
      g.residual.push_back(0);
    }
  }
  return g;
}

// A noisy sensor (3x the Kinect model), and merge bounds wide enough for its noise.
ProxyOptions NoisySensor() {
  ProxyOptions o;
  o.sensor_sigma_a *= 3;
  o.sensor_sigma_b *= 3;
  o.max_rms_a = 1;
  o.max_distance = 1;
  o.trim_iterations = 0;
  return o;
}

// A normal turned from the wall's about the camera's vertical axis (radians).
double Tilt(const Eigen::Vector3f& normal, const ObliqueWall& wall) {
  const Eigen::Vector3d across = Eigen::Vector3d::UnitY().cross(wall.normal);
  return std::atan2(normal.cast<double>().dot(across), normal.cast<double>().dot(wall.normal));
}

// The plane of the members' spread without the noise: covariance - noise's smallest
// eigenvector, towards the camera.
Eigen::Vector3f NoiseFreeNormal(const PlanarProxy& p) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3f> eig(p.covariance - p.noise);
  Eigen::Vector3f n = eig.eigenvectors().col(0);
  return n.dot(p.normal) < 0 ? -n : n;
}

TEST(ExtractProxies, TheNoiseEstimateRemovesTheTiltOfDepthNoiseAlongTheRays) {
  const ObliqueWall wall;
  const ProxyOptions o = NoisySensor();
  double least_squares = 0, noise_free = 0;
  const int seeds = 20;
  for (int seed = 0; seed < seeds; ++seed) {
    const ProxySegmentation s = ExtractProxies(WallGrid(wall, o, seed), o);
    ASSERT_EQ(s.proxies.size(), 1u);
    ASSERT_EQ(s.proxies[0].inliers, 12 * 16);
    least_squares += Tilt(s.proxies[0].normal, wall) / seeds;
    noise_free += Tilt(NoiseFreeNormal(s.proxies[0]), wall) / seeds;
  }
  // sigma(z) ~ 0.08 m at 4 m against a patch 0.7 m wide across the tilt: least squares
  // turns the plane towards the rays by degrees (3.1 measured); without the noise only the
  // seeds' scatter is left (about 0.4 deg / sqrt(20); 0.09 measured).
  EXPECT_GT(std::abs(least_squares), 2 * kDeg);
  EXPECT_LT(std::abs(noise_free), 0.25 * kDeg);
}

TEST(ExtractProxies, TheNoiseEstimateIsTheScattersNoiseAndNothingElse) {
  const ObliqueWall wall;
  const ProxyOptions o = NoisySensor();
  const PlanarProxy p = ExtractProxies(WallGrid(wall, o, 7), o).proxies.at(0);
  // mu N is positive definite, and the spread left is positive semi-definite and singular
  // along its normal (E_P's minimum is that plane).
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3f> noise(p.noise), spread(p.covariance - p.noise);
  EXPECT_GT(noise.eigenvalues()(0), 0);
  EXPECT_GT(spread.eigenvalues()(0), -1e-6f * p.covariance.trace());
  EXPECT_LT(spread.eigenvalues()(0), 1e-6f * p.covariance.trace());
  // Along the normal, nearly all of the scatter is noise; across the wall, little of it.
  const Eigen::Vector3f n = NoiseFreeNormal(p);
  EXPECT_NEAR(n.dot(p.noise * n), n.dot(p.covariance * n), 1e-6f);
  // The estimate's scale is the noise the grid was made with: sigma(z) along the rays (at
  // the centroid's depth, within the spread of depths over the patch and the seed's luck).
  const Eigen::Vector3f ray = p.centroid / p.centroid.z();
  const double dz = p.centroid.z() - 0.4, sigma = o.sensor_sigma_a + o.sensor_sigma_b * dz * dz;
  EXPECT_NEAR(ray.normalized().dot(p.noise * ray.normalized()) / (sigma * sigma * ray.squaredNorm()), 1.0, 0.25);

  // Exact depth: no noise to remove, whatever the sensor model.
  const PlanarProxy exact = ExtractProxies(WallGrid(wall, o, -1), o).proxies.at(0);
  EXPECT_LT(std::abs(Tilt(exact.normal, wall)), 1e-5);
  EXPECT_NEAR(exact.offset, wall.offset, 1e-5);
  EXPECT_LT(exact.noise.norm(), 1e-9f);

  // A noise-free sensor model estimates none.
  ProxyOptions noise_free = o;
  noise_free.sensor_sigma_a = noise_free.sensor_sigma_b = 0;
  EXPECT_TRUE(ExtractProxies(WallGrid(wall, o, 7), noise_free).proxies.at(0).noise.isZero());
}

}  // namespace
}  // namespace f2c
