#include "f2c/odometry/depth_alignment.h"

#include <gtest/gtest.h>

#include "f2c/testing/synthetic_scene.h"

namespace f2c {
namespace {

using testing::Render;
using testing::SyntheticScene;
using testing::TestIntrinsics;

Rigid3d Pose(double yaw, const Eigen::Vector3d& t) {
  Rigid3d pose = Rigid3d::Identity();
  pose.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitY()).toRotationMatrix();
  pose.translation() = t;
  return pose;
}

TEST(AlignDepthIcp, RecoversSmallMotionOnUntexturedScene) {
  SyntheticScene scene;
  scene.textured = false;
  const auto k = TestIntrinsics();
  const Rigid3d world_from_a = Pose(0.0, {0.1, 0.0, -0.5});
  const Rigid3d world_from_b = Pose(0.04, {0.14, 0.01, -0.47});
  const cv::Mat depth_a = Render(scene, k, world_from_a).depth;
  const cv::Mat depth_b = Render(scene, k, world_from_b).depth;
  const Rigid3d truth = world_from_a.inverse() * world_from_b;  // a_from_b
  Rigid3d estimate = Rigid3d::Identity();
  ASSERT_TRUE(AlignDepthIcp(depth_b, depth_a, k, Rigid3d::Identity(), IcpOptions(), &estimate));
  EXPECT_LT((estimate.translation() - truth.translation()).norm(), 0.005);
  EXPECT_LT(RotationAngle(estimate.linear().transpose() * truth.linear()), 0.003);
}

TEST(MeasureDepthOverlap, OneAtTheTruthAndLowerWhenWrong) {
  SyntheticScene scene;
  const auto k = TestIntrinsics();
  const Rigid3d world_from_a = Pose(0.0, {0.0, 0.0, -0.5});
  const Rigid3d world_from_b = Pose(0.05, {0.05, 0.0, -0.45});
  const cv::Mat depth_a = Render(scene, k, world_from_a).depth;
  const cv::Mat depth_b = Render(scene, k, world_from_b).depth;
  const Rigid3d truth = world_from_a.inverse() * world_from_b;
  const DepthOverlap good = MeasureDepthOverlap(depth_b, depth_a, k, truth);
  EXPECT_GT(good.fitness, 0.99);
  EXPECT_LT(good.rmse, 0.002);
  const DepthOverlap bad = MeasureDepthOverlap(depth_b, depth_a, k, Pose(0.0, {0, 0, 0.2}) * truth);
  EXPECT_LT(bad.fitness, 0.2);
}

}  // namespace
}  // namespace f2c
