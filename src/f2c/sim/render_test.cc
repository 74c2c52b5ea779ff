#include "f2c/sim/render.h"

#include <gtest/gtest.h>

#include <cmath>

namespace f2c::sim {
namespace {

const CameraIntrinsics kK{525.0, 525.0, 319.5, 239.5, 640, 480};

// Camera at (2.5, 2, 1.5) in the two-rooms scene, looking along -x at the wall x = 0
// (pixel rows grow downwards, so the principal point sees height 1.5 m, above furniture).
Rigid3d LookingWest() {
  Rigid3d pose = Rigid3d::Identity();
  Eigen::Matrix3d r;
  r.col(2) = Eigen::Vector3d(-1, 0, 0);  // forward
  r.col(0) = Eigen::Vector3d(0, 1, 0);   // right = forward x up
  r.col(1) = Eigen::Vector3d(0, 0, -1);  // down
  pose.linear() = r;
  pose.translation() = Eigen::Vector3d(2.5, 2.0, 1.5);
  return pose;
}

TEST(Renderer, ExactDepthOfAKnownWall) {
  const Scene scene = BuildScene("two-rooms", 0);
  const Renderer renderer(scene);
  const RenderedView view = renderer.Render(kK, LookingWest(), SensorOptions::Exact(), 0);
  // Pixel (319.5, 239.5) is between four pixels; (320, 240) looks 0.5 px off-axis: the wall
  // x = 0 is 2.5 m ahead at any pixel, since depth is measured along the optical axis.
  EXPECT_NEAR(view.depth.at<float>(240, 320), 2.5f, 1e-5);
  EXPECT_NEAR(view.depth.at<float>(100, 320), 2.5f, 1e-5);  // higher up the same wall
}

TEST(Renderer, NoisyDepthWithinTheNoiseModel) {
  const Scene scene = BuildScene("two-rooms", 0);
  const Renderer renderer(scene);
  const SensorOptions sensor;
  const RenderedView view = renderer.Render(kK, LookingWest(), sensor, 7);
  // sigma(2.5) = 0.0012 + 0.0019 * 2.1^2 = 9.6 mm; a 1/8 px disparity step at 2.5 m is
  // z^2 / (f b) / 8 = 19.8 mm, so rounding adds up to 9.9 mm and step^2 / 12 of variance.
  const double sigma = sensor.sigma_a + sensor.sigma_b * 2.1 * 2.1;
  const double step = 2.5 * 2.5 / (kK.fx * sensor.baseline) * sensor.disparity_step;
  const double spread = std::sqrt(sigma * sigma + step * step / 12);
  double sum = 0, sum2 = 0;
  int n = 0;
  for (int v = 200; v < 280; ++v) {
    for (int u = 280; u < 360; ++u) {
      const float z = view.depth.at<float>(v, u);
      ASSERT_GT(z, 0);
      EXPECT_NEAR(z, 2.5, 4.5 * sigma + step / 2);
      sum += z - 2.5;
      sum2 += (z - 2.5) * (z - 2.5);
      ++n;
    }
  }
  EXPECT_NEAR(sum / n, 0.0, 0.002);                                                // unbiased
  EXPECT_NEAR(std::sqrt(sum2 / n - (sum / n) * (sum / n)), spread, 0.2 * spread);  // the modelled spread
}

TEST(Renderer, NormalsFromDepthMatchTheWall) {
  const Scene scene = BuildScene("two-rooms", 0);
  const Renderer renderer(scene);
  const RenderedView view = renderer.Render(kK, LookingWest(), SensorOptions::Exact(), 0);
  auto point = [&](int u, int v) { return kK.Unproject(u, v, view.depth.at<float>(v, u)); };
  const Eigen::Vector3d n = (point(330, 240) - point(310, 240)).cross(point(320, 250) - point(320, 230)).normalized();
  // The wall faces the camera: its normal in camera coordinates is -z.
  EXPECT_NEAR(std::abs(n.z()), 1.0, 1e-5);
  // The floor seen below: normal along the camera's -y (up), from depth at the bottom rows.
  Rigid3d down_pose = LookingWest();
  down_pose.linear() = down_pose.linear() * Eigen::AngleAxisd(-0.6, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const RenderedView floor = renderer.Render(kK, down_pose, SensorOptions::Exact(), 0);
  auto fp = [&](int u, int v) { return kK.Unproject(u, v, floor.depth.at<float>(v, u)); };
  const Eigen::Vector3d nf = (fp(330, 460) - fp(310, 460)).cross(fp(320, 470) - fp(320, 450)).normalized();
  const Eigen::Vector3d up_in_camera = down_pose.linear().transpose() * Eigen::Vector3d::UnitZ();
  EXPECT_NEAR(std::abs(nf.dot(up_in_camera)), 1.0, 1e-4);
}

TEST(Renderer, SameSeedSameBytesOtherSeedOtherNoise) {
  const Scene scene = BuildScene("apartment", 3);
  const Renderer renderer(scene);
  Rigid3d pose = LookingWest();
  pose.translation() = Eigen::Vector3d(6, 5, 1.5);
  const RenderedView a = renderer.Render(kK, pose, SensorOptions(), 11);
  const RenderedView b = renderer.Render(kK, pose, SensorOptions(), 11);
  const RenderedView c = renderer.Render(kK, pose, SensorOptions(), 12);
  EXPECT_EQ(cv::norm(a.depth, b.depth, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(a.color, b.color, cv::NORM_INF), 0.0);
  EXPECT_GT(cv::norm(a.depth, c.depth, cv::NORM_INF), 0.0);
}

TEST(Renderer, NoDepthBeyondRangeOrAtGrazingAngles) {
  const Scene scene = BuildScene("corridor", 0);
  const Renderer renderer(scene);
  Rigid3d pose = LookingWest();
  pose.linear().col(2) = Eigen::Vector3d(1, 0, 0);  // looking down the 20 m corridor
  pose.linear().col(0) = Eigen::Vector3d(0, -1, 0);
  pose.translation() = Eigen::Vector3d(0.5, 1.0, 1.5);
  const RenderedView exact = renderer.Render(kK, pose, SensorOptions::Exact(), 0);
  const RenderedView sensed = renderer.Render(kK, pose, SensorOptions(), 0);
  EXPECT_GT(exact.depth.at<float>(240, 320), 15.0f);  // the far end exists...
  EXPECT_EQ(sensed.depth.at<float>(240, 320), 0.0f);  // ...but is beyond 5 m
  double max_depth = 0;
  cv::minMaxLoc(sensed.depth, nullptr, &max_depth);
  EXPECT_LE(max_depth, 5.0);
}

}  // namespace
}  // namespace f2c::sim
