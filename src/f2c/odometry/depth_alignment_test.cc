#include "f2c/odometry/depth_alignment.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "f2c/testing/synthetic_scene.h"

namespace f2c {
namespace {

using testing::Render;
using testing::RenderedFrame;
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

// A camera 0.5 m from the room's back wall sees only the wall; one 0.7 m from a vertical
// corner sees two walls; one as near to the ceiling as well sees three planes.
TEST(AnalyseDepthConstraints, CountsTheMotionsTheGeometryLeavesFree) {
  SyntheticScene scene;
  scene.textured = false;
  const auto k = TestIntrinsics();
  auto degenerate = [&](const Rigid3d& pose) {
    return AnalyseDepthConstraints(Render(scene, k, pose).depth, k, 8).Degenerate(IcpOptions().prior_information);
  };
  EXPECT_EQ(degenerate(Pose(M_PI, {0.0, 0.0, -2.0})), 3);         // slide in the plane, turn about its normal
  EXPECT_EQ(degenerate(Pose(0.75 * M_PI, {2.0, 0.0, -2.0})), 1);  // slide along the edge
  EXPECT_EQ(degenerate(Pose(0.75 * M_PI, {2.0, 1.3, -2.0})), 0);
}

Rigid3d Exp(const Eigen::Vector3d& w, const Eigen::Vector3d& v) {
  Rigid3d t = Rigid3d::Identity();
  t.linear() = Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix();
  t.translation() = v;
  return t;
}

// Facing a plain wall (normal along the camera's z): ICP wrong only where the wall leaves it
// free (slide in x, y and turn about z), the prior wrong only where the wall constrains it
// (tilt and distance). Fused, each keeps its good part: the truth comes back to within the
// share of the prior's error the wall's tilt constraint (eigenvalue 0.06-0.12 against the
// prior's 0.01) leaves.
TEST(ConstrainToGeometry, KeepsIcpWhereTheGeometryConstrainsItAndThePriorElsewhere) {
  SyntheticScene scene;
  scene.textured = false;
  const auto k = TestIntrinsics();
  const DepthConstraints wall = AnalyseDepthConstraints(Render(scene, k, Pose(M_PI, {0.0, 0.0, -2.0})).depth, k, 8);
  const Rigid3d truth = Exp({0.01, 0.02, 0.005}, {0.02, -0.01, 0.01});
  const Rigid3d icp = Exp({0, 0, 0.02}, {0.03, -0.02, 0}) * truth;
  const Rigid3d prior = Exp({0.01, -0.015, 0}, {0, 0, 0.02}) * truth;
  const double threshold = IcpOptions().prior_information;
  const Rigid3d combined = ConstrainToGeometry(icp, prior, wall, threshold);
  EXPECT_LT((combined.translation() - truth.translation()).norm(), 0.004);
  EXPECT_LT(RotationAngle(combined.linear().transpose() * truth.linear()) * 180 / M_PI, 0.2);
  // Either alone is off by a centimetre or more, or a degree.
  EXPECT_GT((icp.translation() - truth.translation()).norm(), 0.03);
  EXPECT_GT(RotationAngle(prior.linear().transpose() * truth.linear()) * 180 / M_PI, 1.0);
  // No prior information: ICP stands.
  EXPECT_EQ(ConstrainToGeometry(icp, prior, wall, 0.0).matrix(), icp.matrix());
}

cv::Mat Gray(const cv::Mat& color) {
  cv::Mat gray;
  cv::cvtColor(color, gray, cv::COLOR_BGR2GRAY);
  return gray;
}

// Facing the back wall from 1.5 m: a textured one constrains every motion once its image is
// counted; a plain one still leaves the slides and the turn about the normal free.
TEST(AnalyseViewConstraints, CountsTheMotionsTheImageGradientsConstrain) {
  const auto k = TestIntrinsics();
  const Rigid3d pose = Pose(M_PI, {0.0, 0.0, -1.0});
  const double threshold = IcpOptions().prior_information, min_gradient = IcpOptions().min_gradient;
  SyntheticScene textured;
  const RenderedFrame view = Render(textured, k, pose);
  const ViewConstraints textured_wall = AnalyseViewConstraints(view.depth, Gray(view.color), k, 8, min_gradient);
  const DepthConstraints depth = textured_wall.depth;
  EXPECT_EQ(depth.Degenerate(threshold), 3);
  EXPECT_EQ(depth.eigenvalues, AnalyseDepthConstraints(view.depth, k, 8).eigenvalues);
  // Along the three motions the depth leaves free, the texture constrains all three.
  const DepthConstraints image = textured_wall.image.Along(depth.eigenvectors.leftCols(3));
  EXPECT_EQ(image.Degenerate(threshold), 3);  // only the three across the span: no information
  EXPECT_GT(image.eigenvalues(3), 2 * threshold);
  SyntheticScene plain;
  plain.textured = false;
  const RenderedFrame flat = Render(plain, k, pose);
  const ViewConstraints flat_wall = AnalyseViewConstraints(flat.depth, Gray(flat.color), k, 8, min_gradient);
  EXPECT_EQ(flat_wall.image.Degenerate(threshold), 6);
}

// Hand-made constraints along the coordinate axes of (w L, v): the depth's eigenvalues and the
// image's information per axis.
ViewConstraints AxisConstraints(const Eigen::Matrix<double, 6, 1>& depth, const Eigen::Matrix<double, 6, 1>& image) {
  ViewConstraints view;
  for (DepthConstraints* c : {&view.depth, &view.image}) {
    c->information = (c == &view.depth ? depth : image).asDiagonal();
    c->mean_depth = 2.0;
    c->samples = 100;
  }
  // Ascending, as AnalyseViewConstraints gives them (the depth's are already in order below).
  view.depth.eigenvalues = depth;
  view.depth.eigenvectors.setIdentity();
  return view;
}

// Free to the depth (below the prior's 0.01): the slides, chosen. A direction the depth barely
// constrains (0.02) but the image does (0.3, more than the depth's and the prior's 0.03):
// chosen too. The tilts and the distance, which the depth measures better: left to ICP.
TEST(PhotometricDirections, TakesWhatTheDepthLeavesFreeAndWhatTheImageMeasuresBetter) {
  Eigen::Matrix<double, 6, 1> depth, image;
  depth << 0.0, 0.005, 0.02, 0.06, 0.1, 1.0;
  image << 0.5, 0.5, 0.3, 0.01, 0.05, 0.0;
  const Eigen::Matrix<double, 6, Eigen::Dynamic> b = PhotometricDirections(AxisConstraints(depth, image), 0.01);
  ASSERT_EQ(b.cols(), 3);
  EXPECT_EQ(b, (Eigen::Matrix<double, 6, 6>::Identity().leftCols(3)));
  image(2) = 0.015;  // now the depth and the prior (0.03) measure it better
  EXPECT_EQ(PhotometricDirections(AxisConstraints(depth, image), 0.01).cols(), 2);
  // An image that sees a tilt only together with a slide (one row along (slide + tilt) / sqrt 2,
  // information 1, as a fronto-parallel wall's texture confounds them): 0.5 along the tilt alone,
  // but with the slide free it adds 0.01 to the tilt's 0.07. Not chosen.
  ViewConstraints confounded = AxisConstraints(depth, Eigen::Matrix<double, 6, 1>::Zero());
  Eigen::Matrix<double, 6, 1> u = Eigen::Matrix<double, 6, 1>::Zero();
  u(0) = u(3) = 1 / std::sqrt(2.0);
  confounded.image.information = u * u.transpose();
  EXPECT_EQ(PhotometricDirections(confounded, 0.01), (Eigen::Matrix<double, 6, 6>::Identity().leftCols(2)));
}

// The fused answer's information in (w radians, v metres): D (H_depth + p I + P H_image P) D
// / (p sigma^2), D = diag(L, L, L, 1, 1, 1), P the projector on the refined directions. Where
// neither the depth nor the image measured, the prior alone: a translation variance of
// sigma^2 and a rotation variance of (sigma / L)^2.
TEST(MeasuredInformation, TheFusionsInformationScaledByThePrior) {
  Eigen::Matrix<double, 6, 1> depth, image;
  depth << 0.0, 0.0, 0.02, 0.06, 0.1, 1.0;
  image << 0.99, 0.0, 0.08, 0.0, 0.0, 0.5;
  ViewConstraints view = AxisConstraints(depth, image);
  view.depth.information(0, 3) = view.depth.information(3, 0) = 0.004;  // a tilt tied to a slide
  const double p = 0.01, sigma = 0.005, scale = 1 / (p * sigma * sigma), l = 2.0;
  const Eigen::Matrix<double, 6, Eigen::Dynamic> b = Eigen::Matrix<double, 6, 6>::Identity().leftCols(3);
  const Eigen::Matrix<double, 6, 6> h = MeasuredInformation(view, b, p, sigma);
  Eigen::Matrix<double, 6, 1> diagonal;
  diagonal << (0.99 + p) * l * l, p * l * l, (0.02 + 0.08 + p) * l * l, 0.06 + p, 0.1 + p, 1.0 + p;
  EXPECT_LT((h.diagonal() / scale - diagonal).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_NEAR(h(0, 3) / scale, 0.004 * l, 1e-12);  // rotation rows times L, translation rows not
  EXPECT_NEAR(h(3, 0), h(0, 3), 1e-9);
  EXPECT_NEAR(1 / h(1, 1), (sigma / l) * (sigma / l), 1e-15);  // the turn neither measured
  // Without the photometric step the image adds nothing, its strong sixth row included.
  const Eigen::Matrix<double, 6, 6> depth_only = MeasuredInformation(view, Eigen::Matrix<double, 6, 0>(), p, sigma);
  EXPECT_NEAR(depth_only(0, 0) / scale, p * l * l, 1e-12);
  EXPECT_NEAR(depth_only(5, 5) / scale, 1.0 + p, 1e-12);
  EXPECT_NEAR(h(5, 5), depth_only(5, 5), 1e-6);  // the refined directions are the first three only
}

// A prior three times as uncertain as the fusion assumed (a run of fallbacks before it): the
// prior's term drops to I / (3 sigma)^2 in (w, v) units, the measurements' terms keep the
// fusion's scale 1 / (p sigma^2).
TEST(MeasuredInformation, AnOlderPriorWeighsLessAndTheMeasurementsAsBefore) {
  Eigen::Matrix<double, 6, 1> depth, image;
  depth << 0.0, 0.0, 0.02, 0.06, 0.1, 1.0;
  image << 0.99, 0.0, 0.08, 0.0, 0.0, 0.5;
  const ViewConstraints view = AxisConstraints(depth, image);
  const double p = 0.01, sigma = 0.005, l = 2.0, scale = 1 / (p * sigma * sigma);
  const Eigen::Matrix<double, 6, Eigen::Dynamic> b = Eigen::Matrix<double, 6, 6>::Identity().leftCols(3);
  const Eigen::Matrix<double, 6, 6> aged = MeasuredInformation(view, b, p, sigma, 3);
  Eigen::Matrix<double, 6, 1> diagonal;
  diagonal << (0.99 + p / 9) * l * l, p / 9 * l * l, (0.02 + 0.08 + p / 9) * l * l, 0.06 + p / 9, 0.1 + p / 9,
      1.0 + p / 9;
  EXPECT_LT((aged.diagonal() / scale - diagonal).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_NEAR(1 / aged(1, 1), (3 * sigma / l) * (3 * sigma / l), 1e-15);  // the turn: the prior alone
}

// Along each chosen axis the photometric step's move s is kept in the share lambda_image /
// (lambda_image + lambda_depth + prior): all of it where the depth is silent and the image
// strong, a part where both measure, none where the image is blind.
TEST(FusePhotometric, WeighsThePhotometricStepAgainstTheDepthAndThePrior) {
  Eigen::Matrix<double, 6, 1> depth, image;
  depth << 0.0, 0.0, 0.02, 0.06, 0.1, 1.0;
  image << 0.99, 0.0, 0.08, 0.0, 0.0, 0.0;
  const ViewConstraints view = AxisConstraints(depth, image);
  const double p = 0.01;
  const Eigen::Matrix<double, 6, Eigen::Dynamic> b = Eigen::Matrix<double, 6, 6>::Identity().leftCols(3);
  const Rigid3d fused = Exp({0.01, -0.02, 0.03}, {0.1, 0.0, 0.2});
  Eigen::Matrix<double, 6, 1> s;
  s << 0.004, -0.006, 0.01, 0.0, 0.0, 0.0;  // (w L, v), L = 2
  const Rigid3d refined = ExpScaled(s, view.depth.mean_depth) * fused;
  int degenerate = -1;
  const Rigid3d out = FusePhotometric(refined, fused, view, b, p, &degenerate);
  Eigen::Matrix<double, 6, 1> kept;
  kept << 0.99 * 0.004, 0.0, 0.08 / (0.08 + 0.02 + p) * 0.01, 0.0, 0.0, 0.0;
  const Rigid3d expected = ExpScaled(kept, view.depth.mean_depth) * fused;
  EXPECT_LT((out.matrix() - expected.matrix()).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_EQ(degenerate, 1);  // the second axis: neither measures it
  // Where the depth is silent along every chosen direction it is ConstrainToGeometry with the
  // image's information.
  const ViewConstraints silent =
      AxisConstraints((Eigen::Matrix<double, 6, 1>() << 0, 0, 0, 0.06, 0.1, 1).finished(), image);
  const Rigid3d a = FusePhotometric(refined, fused, silent, b, p);
  const Rigid3d c = ConstrainToGeometry(refined, fused, silent.image.Along(b), p);
  EXPECT_LT((a.matrix() - c.matrix()).cwiseAbs().maxCoeff(), 1e-12);
}

}  // namespace
}  // namespace f2c
