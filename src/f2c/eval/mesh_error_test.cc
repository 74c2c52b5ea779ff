#include "f2c/eval/mesh_error.h"

#include <gtest/gtest.h>

#include <random>

namespace f2c {
namespace {

// Independent reference: the projection onto the plane when it falls inside, else the
// nearest of the three edges.
double SegmentDistance(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const double t = std::clamp((p - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
  return (p - (a + t * (b - a))).norm();
}

double Reference(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                 const Eigen::Vector3d& c) {
  const Eigen::Vector3d n = (b - a).cross(c - a).normalized();
  const Eigen::Vector3d q = p - n.dot(p - a) * n;
  const bool inside =
      (b - a).cross(q - a).dot(n) >= 0 && (c - b).cross(q - b).dot(n) >= 0 && (a - c).cross(q - c).dot(n) >= 0;
  if (inside) return std::abs(n.dot(p - a));
  return std::min({SegmentDistance(p, a, b), SegmentDistance(p, b, c), SegmentDistance(p, c, a)});
}

TEST(PointTriangleDistance, MatchesProjectionOrNearestEdge) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  auto random = [&] { return Eigen::Vector3d(u(rng), u(rng), u(rng)); };
  for (int i = 0; i < 2000; ++i) {
    Eigen::Vector3d a = random(), b = random(), c = random();
    if ((b - a).cross(c - a).norm() < 1e-3) continue;
    if ((b - a).cross(c - a).dot(Eigen::Vector3d::UnitZ()) < 0) std::swap(b, c);
    const Eigen::Vector3d p = 2 * random();
    EXPECT_NEAR(PointTriangleDistance(p, a, b, c), Reference(p, a, b, c), 1e-12) << i;
  }
}

// A 1 m square floor (two triangles) as the truth.
PlyPoints Floor() {
  PlyPoints t;
  t.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  t.faces = {{0, 1, 2}, {0, 2, 3}};
  return t;
}

// Mesh vertices every 5 mm over x in [0, x_max], all y, at height z.
PlyPoints Sheet(double x_max, double z) {
  PlyPoints m;
  for (double x = 0.0025; x < x_max; x += 0.005) {
    for (double y = 0.0025; y < 1; y += 0.005) m.positions.emplace_back(x, y, z);
  }
  return m;
}

TEST(EvaluateMesh, AccuracyIsTheDistanceAndCompletenessTheCoveredShare) {
  const MeshError half = EvaluateMesh(Sheet(0.5, 0.005), Floor());
  EXPECT_NEAR(half.accuracy.mean, 0.005, 1e-6);
  EXPECT_NEAR(half.p90, 0.005, 1e-6);
  EXPECT_EQ(half.far_fraction, 0.0);
  // Samples within 2 cm of x <= 0.5: 52% of the floor.
  EXPECT_NEAR(half.completeness, 0.52, 0.02);
  EXPECT_GT(half.surface_samples, 2000);

  // A doubled floor 3 cm up: worse accuracy, and it covers nothing.
  const MeshError lifted = EvaluateMesh(Sheet(1.0, 0.03), Floor());
  EXPECT_NEAR(lifted.accuracy.median, 0.03, 1e-6);
  EXPECT_EQ(lifted.completeness, 0.0);
  // Far away: capped and counted.
  const MeshError far = EvaluateMesh(Sheet(1.0, 1.0), Floor());
  EXPECT_EQ(far.far_fraction, 1.0);
  EXPECT_DOUBLE_EQ(far.accuracy.max, MeshErrorOptions().max_distance);
}

}  // namespace
}  // namespace f2c
