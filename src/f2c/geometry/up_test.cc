#include "f2c/geometry/up.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

namespace f2c {
namespace {

// A room's normals: floor and table tops (up, with a few degrees of noise), walls in two
// directions (horizontal), all seen from either side.
std::vector<Eigen::Vector3f> RoomNormals(const Eigen::Vector3d& up, int horizontal, int walls) {
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0, 0.03);
  const Eigen::Vector3d a = up.unitOrthogonal(), b = up.cross(a);
  std::vector<Eigen::Vector3f> n;
  for (int i = 0; i < horizontal; ++i) {
    const Eigen::Vector3d v = (up + noise(rng) * a + noise(rng) * b).normalized();
    n.push_back(((i % 3 == 0) ? -v : v).cast<float>());  // the ceiling faces down
  }
  for (int i = 0; i < walls; ++i) {
    const Eigen::Vector3d w = (i % 2 ? a : b) + noise(rng) * up;
    n.push_back(w.normalized().cast<float>());
  }
  n.push_back(Eigen::Vector3f::Zero());  // no normal: ignored
  return n;
}

TEST(UpFromNormals, FindsTheFloorsNormalFromATiltedPrior) {
  const Eigen::Vector3d up = Eigen::Vector3d(0.1, -0.2, 1).normalized();
  const Eigen::Vector3d prior = Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitX()) * up;  // 29 degrees off
  const Eigen::Vector3d found = UpFromNormals(RoomNormals(up, 500, 3000), prior);
  EXPECT_LT(std::acos(std::min(1.0, found.dot(up))) * 180 / M_PI, 0.5);
}

TEST(UpFromNormals, KeepsThePriorWhenNoSurfaceIsHorizontalEnough) {
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d prior(0, 2, 1);  // 63 degrees off: the floors lie outside the 45-degree cone
  EXPECT_TRUE(UpFromNormals(RoomNormals(up, 500, 0), prior).isApprox(prior.normalized(), 1e-12));
  // Inside the cone but too few to count (19 agree).
  EXPECT_TRUE(UpFromNormals(RoomNormals(up, 19, 0), Eigen::Vector3d(0, 0.3, 1))
                  .isApprox(Eigen::Vector3d(0, 0.3, 1).normalized(), 1e-12));
  EXPECT_GT(UpFromNormals(RoomNormals(up, 20, 0), Eigen::Vector3d(0, 0.3, 1)).z(), 0.999);
  EXPECT_TRUE(UpFromNormals({}, prior).isApprox(prior.normalized(), 1e-12));
}

}  // namespace
}  // namespace f2c
