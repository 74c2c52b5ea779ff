#include "f2c/features/point_grid.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "f2c/testing/synthetic_scene.h"

namespace f2c {
namespace {

using testing::kDeg;

double AngleBetween(const Eigen::Vector3f& a, const Eigen::Vector3d& b) {
  return std::acos(std::clamp(std::abs(a.cast<double>().normalized().dot(b.normalized())), 0.0, 1.0));
}

TEST(BuildPointGrid, NormalsOfATiltedPlaneAreExactAndItsCurvatureVanishes) {
  const CameraIntrinsics k = testing::TestIntrinsics();
  const Eigen::Vector3d n = Eigen::Vector3d(0.3, -0.5, -1.0).normalized();  // towards the camera
  const PointGrid g = BuildPointGrid(testing::PlaneDepth(k, n, -1.6), k, PointGridOptions());
  EXPECT_EQ(g.width, 160);
  EXPECT_EQ(g.height, 120);
  int checked = 0;
  for (int i = 0; i < g.width * g.height; ++i) {
    if (!g.Valid(i)) continue;
    ASSERT_TRUE(g.HasNormal(i));
    EXPECT_LT(AngleBetween(g.normals[i], n), 0.05 * kDeg);
    EXPECT_LT(g.normals[i].dot(g.points[i]), 0) << "towards the camera";
    EXPECT_LT(g.curvature[i], 1e-5);
    ++checked;
  }
  EXPECT_GT(checked, 10000);
  // The grid samples pixel centres exactly: cell (10, 20) is pixel (42, 82).
  const Eigen::Vector3f p = g.points[g.Index(10, 20)];
  EXPECT_NEAR(p.x() / p.z(), (42 - k.cx) / k.fx, 1e-6);
  EXPECT_NEAR(p.y() / p.z(), (82 - k.cy) / k.fy, 1e-6);
}

TEST(BuildPointGrid, CellsAtACreaseAreCurvedAndCellsAwayFromItAreNot) {
  // A floor (y = 1 m below the camera) meeting a wall 2 m ahead: a 90 degree valley.
  const CameraIntrinsics k = testing::TestIntrinsics();
  cv::Mat depth(k.height, k.width, CV_32F);
  for (int v = 0; v < k.height; ++v) {
    for (int u = 0; u < k.width; ++u) {
      const double ry = (v - k.cy) / k.fy;
      const double floor_z = ry > 0 ? 1.0 / ry : 1e9;
      depth.at<float>(v, u) = static_cast<float>(std::min(2.0, floor_z));
    }
  }
  const PointGrid g = BuildPointGrid(depth, k, PointGridOptions());
  const double crease_v = k.cy + k.fy * 0.5;  // the floor meets the wall at y = 1, z = 2
  for (int y = 0; y < g.height; ++y) {
    const double dv = g.PixelV(y) - crease_v;
    const int i = g.Index(80, y);
    if (std::abs(dv) > 12) {  // beyond the 8 px normal window
      EXPECT_LT(g.curvature[i], 1e-5) << y;
      EXPECT_LT(AngleBetween(g.normals[i], dv < 0 ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d::UnitY()), 0.05 * kDeg);
    } else if (std::abs(dv) < 3) {
      EXPECT_GT(g.curvature[i], 0.02f) << y;  // above ProxyOptions::max_curvature: no proxy
    }
  }
}

TEST(BuildPointGrid, MissingOrOutOfRangeDepthIsInvalid) {
  const CameraIntrinsics k = testing::TestIntrinsics();
  cv::Mat depth(k.height, k.width, CV_32F, cv::Scalar(2.0f));
  depth.at<float>(2, 2) = std::numeric_limits<float>::quiet_NaN();  // cell (0, 0)
  depth.at<float>(2, 6) = std::numeric_limits<float>::infinity();   // cell (1, 0)
  depth.at<float>(2, 10) = 7.0f;                                    // beyond 5 m: cell (2, 0)
  depth.at<float>(2, 14) = 0.1f;                                    // nearer than 0.3 m: cell (3, 0)
  depth.at<float>(2, 18) = -1.0f;                                   // cell (4, 0)
  const PointGrid g = BuildPointGrid(depth, k, PointGridOptions());
  for (int x = 0; x < 5; ++x) EXPECT_FALSE(g.Valid(g.Index(x, 0))) << x;
  EXPECT_TRUE(g.Valid(g.Index(5, 0)));
  EXPECT_EQ(g.ValidCount(), g.width * g.height - 5);
}

TEST(BuildPointGrid, TheBilateralFilterSteadiesNormalsOfNoisyDepth) {
  const CameraIntrinsics k = testing::TestIntrinsics();
  const Eigen::Vector3d n(0, 0, -1);
  cv::Mat depth(k.height, k.width, CV_32F, cv::Scalar(2.5f));
  std::mt19937 rng(3);
  std::normal_distribution<float> noise(0.0f, 0.01f);
  for (int v = 0; v < k.height; ++v) {
    for (int u = 0; u < k.width; ++u) depth.at<float>(v, u) += noise(rng);
  }
  auto mean_error = [&](bool bilateral) {
    PointGridOptions o;
    o.bilateral = bilateral;
    const PointGrid g = BuildPointGrid(depth, k, o);
    double sum = 0;
    int count = 0;
    for (int i = 0; i < g.width * g.height; ++i) {
      if (g.HasNormal(i)) sum += AngleBetween(g.normals[i], n), ++count;
    }
    return sum / count;
  };
  const double raw = mean_error(false), filtered = mean_error(true);
  EXPECT_LT(filtered, 0.5 * raw) << raw / kDeg << " vs " << filtered / kDeg << " degrees";
}

}  // namespace
}  // namespace f2c
