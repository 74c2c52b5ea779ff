#include "f2c/eval/trajectory_error.h"

#include <gtest/gtest.h>

#include <cmath>

#include "f2c/util/error.h"

namespace f2c {
namespace {

Rigid3d At(double x, double y, double z, double yaw = 0) {
  Rigid3d t = Rigid3d::Identity();
  t.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  t.translation() = Eigen::Vector3d(x, y, z);
  return t;
}

TEST(ComputeStatistics, HandComputed) {
  // errors 1, 2, 3, 4: mean 2.5, rmse sqrt(30/4), median 2.5, population std sqrt(1.25).
  const ErrorStatistics s = ComputeStatistics({4, 1, 3, 2});
  EXPECT_DOUBLE_EQ(s.mean, 2.5);
  EXPECT_DOUBLE_EQ(s.rmse, std::sqrt(7.5));
  EXPECT_DOUBLE_EQ(s.median, 2.5);
  EXPECT_DOUBLE_EQ(s.std, std::sqrt(1.25));
  EXPECT_DOUBLE_EQ(s.min, 1);
  EXPECT_DOUBLE_EQ(s.max, 4);
}

// Ground truth at (+-1,0,0), (0,+-1,0); the estimate moves the x points out by 0.1 each. The
// cross-covariance is symmetric positive, so the best alignment is the identity and the
// errors are 0.1, 0.1, 0, 0: rmse sqrt(0.02/4), mean 0.05, median 0.05, std 0.05. Moving the
// whole estimate rigidly must not change any of it.
TEST(ComputeAte, HandComputedAndInvariantToARigidMotionOfTheEstimate) {
  Trajectory gt, est;
  const double xs[4][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
  const double dx[4] = {0.1, -0.1, 0, 0};
  Rigid3d motion = At(5, -2, 3, 1.2);
  for (int i = 0; i < 4; ++i) {
    gt.Add(i, At(xs[i][0], xs[i][1], 0));
    est.Add(i + 0.005, motion * At(xs[i][0] + dx[i], xs[i][1], 0));
  }
  const AteResult ate = ComputeAte(est, gt);
  EXPECT_EQ(ate.translation.count, 4);
  EXPECT_NEAR(ate.translation.rmse, std::sqrt(0.02 / 4), 1e-9);
  EXPECT_NEAR(ate.translation.mean, 0.05, 1e-9);
  EXPECT_NEAR(ate.translation.median, 0.05, 1e-9);
  EXPECT_NEAR(ate.translation.std, 0.05, 1e-9);
  EXPECT_NEAR(ate.translation.max, 0.1, 1e-9);
  EXPECT_NEAR(ate.translation.min, 0.0, 1e-9);
}

TEST(ComputeAte, PosesOutsideTheTimeWindowAreNotAssociated) {
  Trajectory gt, est;
  for (int i = 0; i < 5; ++i) gt.Add(i, At(i, 0, 0));
  for (int i = 0; i < 5; ++i) est.Add(i + (i == 4 ? 0.5 : 0.0), At(i, 0, 0));
  EXPECT_EQ(ComputeAte(est, gt).translation.count, 4);
}

TEST(ComputeAte, TooFewAssociationsIsAnInputError) {
  Trajectory gt, est;
  for (int i = 0; i < 5; ++i) gt.Add(i, At(i, 0, 0));
  for (int i = 0; i < 5; ++i) est.Add(100 + i, At(i, 0, 0));
  try {
    ComputeAte(est, gt);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(),
                 "estimate: only 0 of 5 poses have a ground-truth pose within 0.02 s; "
                 "time stamps from another sequence?");
  }
}

// Two poses, both associated: too few to align, which says so rather than blaming the time
// stamps.
TEST(ComputeAte, FewerThanThreePosesIsAnInputError) {
  Trajectory gt, est;
  for (int i = 0; i < 5; ++i) gt.Add(i, At(i, 0, 0));
  for (int i = 0; i < 2; ++i) est.Add(i, At(i, 0, 0));
  try {
    ComputeAte(est, gt);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "estimate: 2 poses: a rigid alignment needs at least 3");
  }
}

// Ground truth moves 1 m per second along x; the estimate 1.1 m per second and yaws 10 degrees
// per second. Each 1-second relative motion then errs by exactly 0.1 m... in the estimate's
// frame: E = gt_rel^-1 est_rel, gt_rel = (I, (1,0,0)), est_rel = (Rz(10deg), (1.1,0,0)) in
// the first frame's coordinates when the start yaw is 0; translation of E = (0.1, 0, 0).
TEST(ComputeRpe, PerSecondHandComputed) {
  Trajectory gt, est;
  for (int i = 0; i <= 4; ++i) {
    gt.Add(i, At(i, 0, 0));
    est.Add(i, At(1.1 * i, 0, 0));
  }
  const RpeResult rpe = ComputeRpe(est, gt, 1.0, true);
  // Pairs (0,1), (1,2), (2,3); (3,4) ends at the last pose and is dropped as in evaluate_rpe.py.
  EXPECT_EQ(rpe.translation.count, 3);
  EXPECT_NEAR(rpe.translation.rmse, 0.1, 1e-9);
  EXPECT_NEAR(rpe.rotation.max, 0.0, 1e-9);

  Trajectory rotating;
  for (int i = 0; i <= 4; ++i) rotating.Add(i, At(i, 0, 0, i * 10.0 * M_PI / 180.0));
  const RpeResult rot = ComputeRpe(rotating, gt, 1.0, true);
  EXPECT_NEAR(rot.rotation.mean, 10.0, 1e-9);
  EXPECT_NEAR(rot.rotation.min, 10.0, 1e-9);
}

TEST(ComputeRpe, PerFrameUsesFrameSteps) {
  Trajectory gt, est;
  for (int i = 0; i < 10; ++i) {
    gt.Add(i * 0.1, At(i * 0.1, 0, 0));
    est.Add(i * 0.1, At(i * 0.12, 0, 0));
  }
  const RpeResult rpe = ComputeRpe(est, gt, 2, false);
  EXPECT_EQ(rpe.translation.count, 7);  // i = 0..6: j = i + 2 < 9
  EXPECT_NEAR(rpe.translation.mean, 0.04, 1e-9);
}

TEST(Evaluate, PerfectEstimateHasZeroError) {
  Trajectory gt;
  for (int i = 0; i < 50; ++i) gt.Add(i / 30.0, At(std::sin(i * 0.1), i * 0.01, 0.2, i * 0.02));
  const EvaluationResult r = Evaluate(gt, gt);
  EXPECT_NEAR(r.ate.translation.rmse, 0, 1e-9);
  EXPECT_NEAR(r.rpe_per_frame.rotation.max, 0, 1e-6);
  EXPECT_GT(r.rpe_per_second.translation.count, 0);
}

// Ground truth turns about z at 3 deg/s; the estimate turns 0.1 deg/s more (drift) and is
// moved rigidly, which must not matter. Poses at t = 0..10 s: pairs >= 5 s apart have
// |i - j| = 5..10, 6 + 5 + 4 + 3 + 2 + 1 = 21 of them, with errors 0.1 |i - j| deg.
TEST(ComputeRotationDrift, HandComputedAndInvariantToARigidMotionOfTheEstimate) {
  Trajectory gt, est;
  const Rigid3d motion = At(1, 2, 3, 0.7);
  for (int i = 0; i <= 10; ++i) {
    gt.Add(i, At(i * 0.3, 0, 0, i * 3.0 * M_PI / 180));
    est.Add(i, motion * At(i * 0.3, 0.01 * i, 0, i * 3.1 * M_PI / 180));
  }
  const RotationDrift d = ComputeRotationDrift(est, gt);
  ASSERT_EQ(d.rotation.count, 21);
  EXPECT_EQ(d.poses, 11);
  double sum2 = 0;
  for (int k = 5; k <= 10; ++k) sum2 += (11 - k) * std::pow(0.1 * k, 2);
  EXPECT_NEAR(d.rotation.max, 1.0, 1e-9);
  EXPECT_NEAR(d.rotation.min, 0.5, 1e-9);
  EXPECT_NEAR(d.rotation.rmse, std::sqrt(sum2 / 21), 1e-9);
  // Sorted, the 21 angles are 0.5 (6 times), 0.6 (5), 0.7 (4), 0.8 (3), 0.9 (2), 1.0: the 99th
  // percentile lies 0.8 of the way from the 20th (0.9) to the 21st (1.0).
  EXPECT_NEAR(d.p99, 0.98, 1e-9);
  EXPECT_EQ(d.threshold_deg, 0.5);
  EvaluationOptions options;
  options.drift_threshold_deg = 0.75;
  const RotationDrift over = ComputeRotationDrift(est, gt, options);
  EXPECT_NEAR(over.share_over, 6.0 / 21, 1e-12);  // 0.8, 0.9 and 1.0
  options.drift_threshold_deg = 1.5;
  EXPECT_EQ(ComputeRotationDrift(est, gt, options).share_over, 0);
}

TEST(ComputeRotationDrift, OnlyPairsFarEnoughApartCountAndPosesAreSubsampledEvenly) {
  Trajectory gt, est;
  for (int i = 0; i < 100; ++i) {
    gt.Add(i * 0.1, At(0, 0, 0));
    est.Add(i * 0.1, At(0, 0, 0, i < 50 ? 0 : 2 * M_PI / 180));  // a 2 deg jump after 5 s
  }
  EvaluationOptions options;
  options.drift_min_seconds = 20;  // longer than the scan: no pairs
  EXPECT_EQ(ComputeRotationDrift(est, gt, options).rotation.count, 0);
  options.drift_min_seconds = 5;
  options.drift_max_poses = 10;  // poses 0, 11, 22, ..., 99 (t = 0, 1.1, ..., 9.9 s)
  const RotationDrift d = ComputeRotationDrift(est, gt, options);
  EXPECT_EQ(d.poses, 10);
  // Pairs at least 5 s apart: (0,5..9) (1,6..9) (2,7..9) (3,8..9) (4,9): 15; of them, those
  // across the jump (first before 5 s, second after) err by 2 deg, all of them here.
  EXPECT_EQ(d.rotation.count, 15);
  EXPECT_NEAR(d.rotation.max, 2, 1e-9);
  EXPECT_NEAR(d.rotation.min, 2, 1e-9);
}

// 20 s at 30 Hz, turning 0.5 deg per frame; the estimate is moved rigidly and each frame is
// rolled 0.3 deg one way or the other, alternately: the worst pair 0.6 deg, but no drift.
// Windows of 1.01 s hold 31 frames inside the scan (net one frame's roll: 0.3 / 31 deg), and
// near the ends fewer: the first window of an odd count is frames 0..16 (net 0.3 / 17 deg, the
// sign of the even frames); inside, windows about even frames lean the other way.
TEST(ComputeSmoothedRotationDrift, AveragesAlternatingJitterAway) {
  Trajectory gt, est;
  const Rigid3d motion = At(1, 2, 3, 0.7);
  for (int k = 0; k <= 600; ++k) {
    const Rigid3d truth = At(0.01 * k, 0, 0, k * 0.5 * M_PI / 180);
    Rigid3d jittered = truth;
    jittered.linear() =
        Eigen::AngleAxisd((k % 2 == 0 ? 0.3 : -0.3) * M_PI / 180, Eigen::Vector3d::UnitX()) * truth.linear();
    gt.Add(k / 30.0, truth);
    est.Add(k / 30.0, motion * jittered);
  }
  EvaluationOptions options;
  options.drift_smoothing_seconds = 1.01;
  EXPECT_NEAR(ComputeRotationDrift(est, gt, options).rotation.max, 0.6, 1e-9);
  const RotationDrift smoothed = ComputeSmoothedRotationDrift(est, gt, options);
  EXPECT_EQ(smoothed.poses, 601);
  EXPECT_EQ(smoothed.smoothing_seconds, 1.01);
  EXPECT_NEAR(smoothed.rotation.max, 0.3 / 17 + 0.3 / 31, 1e-5);
}

// The estimate turns 0.1 deg/s more than the truth for 20 s: drift the averaging keeps. The
// first window holds frames 0..15 (mean 0.25 s: 0.025 deg), the last 585..600 (19.75 s).
TEST(ComputeSmoothedRotationDrift, KeepsSlowDrift) {
  Trajectory gt, est;
  for (int k = 0; k <= 600; ++k) {
    const double t = k / 30.0;
    gt.Add(t, At(0.01 * k, 0, 0, k * 0.5 * M_PI / 180));
    est.Add(t, At(0.01 * k, 0, 0, (k * 0.5 + 0.1 * t) * M_PI / 180));
  }
  EvaluationOptions options;
  options.drift_smoothing_seconds = 1.01;
  EXPECT_NEAR(ComputeRotationDrift(est, gt, options).rotation.max, 2.0, 1e-9);
  EXPECT_NEAR(ComputeSmoothedRotationDrift(est, gt, options).rotation.max, 1.95, 1e-6);
  // 0 turns it off in Evaluate.
  options.drift_smoothing_seconds = 0;
  const EvaluationResult r = Evaluate(est, gt, options);
  EXPECT_EQ(r.drift_smoothed.rotation.count, 0);
  EXPECT_GT(r.drift.rotation.count, 0);
}

}  // namespace
}  // namespace f2c
