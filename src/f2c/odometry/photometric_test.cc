#include "f2c/odometry/photometric.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "f2c/odometry/depth_alignment.h"
#include "f2c/testing/synthetic_scene.h"

namespace f2c {
namespace {

Rigid3d Twist(const Eigen::Vector3d& w, const Eigen::Vector3d& v) {
  Rigid3d t = Rigid3d::Identity();
  if (w.norm() > 0) t.linear() = Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix();
  t.translation() = v;
  return t;
}

cv::Mat ToGray(const cv::Mat& color) {
  cv::Mat gray;
  cv::cvtColor(color, gray, cv::COLOR_BGR2GRAY);
  return gray;
}

double Degrees(const Rigid3d& a, const Rigid3d& b) {
  return RotationAngle(a.linear().transpose() * b.linear()) * 180 / M_PI;
}

// A camera 1.5 m from the room's textured back wall, and a second view of it: the depth leaves
// the slides in the wall and the turn about its normal free.
struct WallPair {
  CameraIntrinsics k = testing::TestIntrinsics();
  Rigid3d truth = Twist({0.004, -0.006, 0.015}, {0.03, -0.02, 0.01});  // reference_from_frame
  testing::RenderedFrame reference, frame;
  Eigen::Matrix<double, 6, Eigen::Dynamic> free;
  double lever = 1;

  explicit WallPair(bool textured = true) {
    testing::SyntheticScene scene;
    scene.textured = textured;
    // Turned to face the back wall (-z), 1.5 m from it.
    const Rigid3d world_from_reference = Twist({0.0, M_PI, 0.0}, {0.0, 0.0, -1.0});
    reference = testing::Render(scene, k, world_from_reference);
    frame = testing::Render(scene, k, world_from_reference * truth);
    const DepthConstraints depth = AnalyseDepthConstraints(reference.depth, k, 8);
    free = depth.eigenvectors.leftCols(depth.Degenerate(IcpOptions().prior_information));
    lever = depth.mean_depth;
  }
  // The truth moved along `direction` ((w L, v) units, on the left).
  Rigid3d Moved(const Eigen::Matrix<double, 6, 1>& direction) const {
    return Twist(direction.head<3>() / lever, direction.tail<3>()) * truth;
  }
};

TEST(AlignPhotometric, RecoversTheMotionsThePlainWallsDepthLeavesFree) {
  const WallPair wall;
  ASSERT_EQ(wall.free.cols(), 3);
  // Off by 1-2 cm in each free direction (a turn about the normal of about a degree).
  const Rigid3d start = wall.Moved(wall.free * Eigen::Vector3d(0.02, -0.015, 0.01));
  ASSERT_GT((start.translation() - wall.truth.translation()).norm(), 0.01);
  Rigid3d estimate = start;
  const PhotometricResult r =
      AlignPhotometric(ToGray(wall.reference.color), wall.reference.depth, ToGray(wall.frame.color), wall.k, wall.free,
                       wall.lever, PhotometricOptions(), &estimate);
  ASSERT_TRUE(r.ok);
  EXPECT_LT(r.rmse_after, 0.5 * r.rmse_before);
  EXPECT_LT((estimate.translation() - wall.truth.translation()).norm(), 0.001);
  EXPECT_LT(Degrees(estimate, wall.truth), 0.02);
}

TEST(AlignPhotometric, LeavesTheOtherDirectionsAlone) {
  const WallPair wall;
  // 5 mm off along the wall's distance, the most constrained direction, only: the free
  // directions are right already, so nothing moves.
  const DepthConstraints depth = AnalyseDepthConstraints(wall.reference.depth, wall.k, 8);
  const Rigid3d start = wall.Moved(0.005 * depth.eigenvectors.col(5));
  Rigid3d estimate = start;
  AlignPhotometric(ToGray(wall.reference.color), wall.reference.depth, ToGray(wall.frame.color), wall.k, wall.free,
                   wall.lever, PhotometricOptions(), &estimate);
  EXPECT_LT((estimate.translation() - start.translation()).norm(), 0.001);
  EXPECT_LT(Degrees(estimate, start), 0.02);
}

TEST(AlignPhotometric, IgnoresABrightnessChange) {
  const WallPair wall;
  const Rigid3d start = wall.Moved(wall.free * Eigen::Vector3d(0.01, 0.01, -0.01));
  cv::Mat brighter;
  ToGray(wall.frame.color).convertTo(brighter, CV_8U, 1.0, 25.0);
  Rigid3d estimate = start;
  ASSERT_TRUE(AlignPhotometric(ToGray(wall.reference.color), wall.reference.depth, brighter, wall.k, wall.free,
                               wall.lever, PhotometricOptions(), &estimate)
                  .ok);
  EXPECT_LT((estimate.translation() - wall.truth.translation()).norm(), 0.001);
  EXPECT_LT(Degrees(estimate, wall.truth), 0.02);
}

TEST(AlignPhotometric, MovesNothingOnAPlainWall) {
  const WallPair wall(/*textured=*/false);
  const Rigid3d start = wall.Moved(wall.free * Eigen::Vector3d(0.02, -0.015, 0.01));
  Rigid3d estimate = start;
  AlignPhotometric(ToGray(wall.reference.color), wall.reference.depth, ToGray(wall.frame.color), wall.k, wall.free,
                   wall.lever, PhotometricOptions(), &estimate);
  EXPECT_LT((estimate.translation() - start.translation()).norm(), 1e-6);
  EXPECT_LT(Degrees(estimate, start), 1e-6);
}

TEST(PhotometricOptions, RefusesLevelsThatDoNotPair) {
  PhotometricOptions o;
  o.strides = {8};
  EXPECT_EQ(testing::InputErrorMessage([&] { o.Check(); }),
            "blur_sigmas: needs one value per level, as strides (1), got 2");
}

}  // namespace
}  // namespace f2c
