// SolvePoses with E_L and E_V alone: how their weights are shared, whitened links, steady
// motion against a wrong pair, and E_L's loss on weakly tracked links (problem.h). The
// scenes with correspondences and planes are in problem_test.cc.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <vector>

#include "f2c/geometry/rigid.h"
#include "f2c/optim/problem.h"

namespace f2c {
namespace {

TEST(SolvePoses, TermWeightsAreTotalsSharedAmongResiduals) {
  // One local constraint 10 cm off: its cost is w_L / 2 * 0.1^2 whatever its relative weight.
  PoseVector poses(2);
  poses[1].translation = Eigen::Vector3d(1.1, 0, 0);
  std::vector<RelativePoseConstraint> local = {{0, 1, Eigen::Quaterniond::Identity(), Eigen::Vector3d(1, 0, 0), 7.0}};
  SolverOptions options;
  options.weight_local = 300;
  const SolveSummary s = SolvePoses({{}, local, {}, {}, {}}, options, &poses);
  EXPECT_NEAR(s.cost_before.at(Term::kL), 0.5 * 300 * 0.01, 1e-9);
  // E_I starts at zero and ends small; E_L almost vanishes.
  EXPECT_NEAR(s.cost_before.at(Term::kI), 0.0, 1e-15);
  EXPECT_LT(s.cost_after.at(Term::kL), 1e-4);

  // Through a Cauchy loss of scale c the reported cost is the robust one:
  // w_L / 2 * c^2 log(1 + 0.1^2 / c^2).
  poses = PoseVector(2);
  poses[1].translation = Eigen::Vector3d(1.1, 0, 0);
  options.local_loss_scale = 0.05;
  const SolveSummary robust = SolvePoses({{}, local, {}, {}, {}}, options, &poses);
  EXPECT_NEAR(robust.cost_before.at(Term::kL), 0.5 * 300 * 0.0025 * std::log(1 + 0.01 / 0.0025), 1e-9);
}

// Two whitened constraints on one pair of frames, each measuring what the other does not:
// one the translation (its turn about z barely), the other the turn (its translation
// barely). The solve takes each direction from the one that measured it, where one weight
// per constraint would split the difference (1.1 m and 0.025 rad).
TEST(SolvePoses, WhitenedLocalConstraintsTakeEachDirectionFromTheOneThatMeasuredIt) {
  PoseVector poses(2);
  poses[1].translation = Eigen::Vector3d(1.1, 0, 0);
  poses[1].rotation = Eigen::Quaterniond(Eigen::AngleAxisd(0.025, Eigen::Vector3d::UnitZ()));
  RelativePoseConstraint moves{0, 1, Eigen::Quaterniond::Identity(), Eigen::Vector3d(1, 0, 0), 1.0};
  moves.sqrt_information.diagonal() << 10, 10, 10, 10, 10, 0.01;
  RelativePoseConstraint turns{0, 1, Eigen::Quaterniond(Eigen::AngleAxisd(0.05, Eigen::Vector3d::UnitZ())),
                               Eigen::Vector3d(1.2, 0, 0), 1.0};
  turns.sqrt_information.diagonal() << 0.01, 0.01, 0.01, 10, 10, 10;
  SolverOptions options;
  options.fix_first_pose = true;
  EXPECT_TRUE(SolvePoses({{}, {moves, turns}, {}, {}, {}}, options, &poses).usable);
  EXPECT_NEAR(poses[1].translation.x(), 1.0, 1e-3);
  EXPECT_NEAR(Eigen::AngleAxisd(poses[1].rotation).angle(), 0.05, 1e-3);
}

// E_V against one wrong odometry pair, which E_L repeats in both of the frame's links (as T0's
// consecutive differences do when one tracked pair is wrong): without E_V nothing disputes
// it and the frame stays 3 degrees off; with E_V at E_L's total it comes most of the way
// back, its neighbours giving a little. Expected: the same balance as a linear least-squares
// problem in each frame's angle off the truth x_i (x_0 = 0, the gauge): E_L's eight links
// sqrt(100 / 8) (x_{a+1} - x_a - m_a) with m_3 = 3, m_4 = -3, and E_V's seven triples
// sqrt(100 / 7) (x_{b+1} - 2 x_b + x_{b-1}). At the truth E_V costs nothing.
TEST(SolvePoses, SteadyMotionTurnsBackAFrameThatOneWrongPairTurned) {
  const int n = 9;
  const Eigen::Quaterniond turn(Eigen::AngleAxisd(0.02, Eigen::Vector3d(0.2, 1, 0.1).normalized()));
  PoseVector truth(n);
  for (int i = 1; i < n; ++i) {
    truth[i].rotation = truth[i - 1].rotation * turn;
    truth[i].translation = truth[i - 1].translation + Eigen::Vector3d(0.01, 0.002, -0.004);
  }
  const int bad = 4;
  PoseVector measured = truth;  // what the odometry says
  measured[bad].rotation = truth[bad].rotation * Eigen::AngleAxisd(3.0 * M_PI / 180, Eigen::Vector3d::UnitZ());
  auto links = [](const PoseVector& poses) {
    std::vector<RelativePoseConstraint> local;
    for (int a = 0; a + 1 < n; ++a) {
      const Rigid3d a_from_b = poses[a].ToRigid().inverse() * poses[a + 1].ToRigid();
      local.push_back({a, a + 1, Eigen::Quaterniond(a_from_b.linear()), a_from_b.translation(), 1.0});
    }
    return local;
  };
  std::vector<SteadyMotionConstraint> steady;
  for (int b = 1; b + 1 < n; ++b) steady.push_back({b - 1, b, b + 1, 1.0, 1.0});

  PoseVector poses = truth;
  SolveSummary s = SolvePoses({{}, links(truth), {}, {}, steady}, {}, &poses);
  EXPECT_LT(s.cost_before.at(Term::kV), 1e-20);

  SolverOptions options;
  options.solve = SolveMode::kConverge;
  options.weight_inertia = 1e-9;
  options.measured_velocity_loss_scale = 0;  // least squares: the linear balance below
  options.weight_velocity = 0;
  poses = measured;
  SolvePoses({{}, links(measured), {}, {}, steady}, options, &poses);
  EXPECT_NEAR(poses[bad].rotation.angularDistance(truth[bad].rotation) * 180 / M_PI, 3.0, 1e-3);

  options.weight_velocity = 100;  // the default, as E_L's
  poses = measured;
  s = SolvePoses({{}, links(measured), {}, {}, steady}, options, &poses);
  EXPECT_GT(s.cost_before.at(Term::kV), s.cost_after.at(Term::kV));
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(2 * n - 3, n - 1);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(2 * n - 3);
  auto column = [](int frame) { return frame - 1; };  // x_0 is held at 0
  for (int k = 0; k + 1 < n; ++k) {
    const double w = std::sqrt(100.0 / 8);
    a(k, column(k + 1)) = w;
    if (k > 0) a(k, column(k)) = -w;
    rhs(k) = w * (k == bad - 1 ? 3.0 : k == bad ? -3.0 : 0.0);
  }
  for (int b = 1; b + 1 < n; ++b) {
    const double w = std::sqrt(100.0 / 7);
    const int row = n - 1 + b - 1;
    a(row, column(b + 1)) = w;
    a(row, column(b)) = -2 * w;
    if (b - 1 > 0) a(row, column(b - 1)) = w;
  }
  const Eigen::VectorXd expected = a.colPivHouseholderQr().solve(rhs);
  EXPECT_NEAR(expected(column(bad)), 1.27, 0.01);
  for (int i = 1; i < n; ++i) {
    EXPECT_NEAR(poses[i].rotation.angularDistance(truth[i].rotation) * 180 / M_PI, std::abs(expected(column(i))), 0.01)
        << "frame " << i;
  }
}

// One wrong odometry pair among links that agree: frames 0-4, each held to the next and to
// the one after it, all at the truth but the pair 1 -> 2, which is 3 deg and 3 cm off (a
// tracked pair whose 20 keypoints sat on one object; the others had 200). In least squares
// the other links share its error and frame 2 turns; through E_L's loss for weak measured
// pairs (--measured-local-loss-scale, the refinement's --polish-local-loss-scale; fewer
// inliers than --measured-local-loss-max-inliers) the links that agree outvote it. The loss
// leaves alone a pair with many inliers and one that left directions to the motion prior
// (measured false): nothing else would hold those directions.
TEST(SolvePoses, MeasuredLocalLossLetsAWeakWrongPairGo) {
  const int n = 5;
  const Eigen::Quaterniond turn(Eigen::AngleAxisd(0.03, Eigen::Vector3d(0.1, 1, 0.2).normalized()));
  PoseVector truth(n);
  for (int i = 1; i < n; ++i) {
    truth[i].rotation = truth[i - 1].rotation * turn;
    truth[i].translation = truth[i - 1].translation + Eigen::Vector3d(0.02, 0.003, -0.005);
  }
  auto make = [&](bool wrong_measured, int wrong_inliers, double wrong_deg) {
    std::vector<RelativePoseConstraint> local;
    for (int a = 0; a < n; ++a) {
      for (int b = a + 1; b <= a + 2 && b < n; ++b) {
        Rigid3d a_from_b = truth[a].ToRigid().inverse() * truth[b].ToRigid();
        RelativePoseConstraint l{a, b, Eigen::Quaterniond(a_from_b.linear()), a_from_b.translation(), 1.0};
        l.weakest_inliers = 200;
        if (a == 1 && b == 2) {
          l.rotation_a_from_b =
              l.rotation_a_from_b * Eigen::AngleAxisd(wrong_deg * M_PI / 180, Eigen::Vector3d::UnitZ());
          l.translation_a_from_b += Eigen::Vector3d(0.01 * wrong_deg, 0, 0);
          l.measured = wrong_measured;
          l.weakest_inliers = wrong_inliers;
        }
        local.push_back(l);
      }
    }
    return local;
  };
  auto error_deg = [&](const PoseVector& poses) {
    // Frame 2 against frame 1: the relative turn the wrong pair asks for.
    return (poses[1].rotation.conjugate() * poses[2].rotation)
               .angularDistance(truth[1].rotation.conjugate() * truth[2].rotation) *
           180 / M_PI;
  };
  SolverOptions least_squares;
  least_squares.solve = SolveMode::kConverge;
  least_squares.weight_inertia = 1e-9;
  SolverOptions robust = least_squares;
  robust.measured_local_loss_scale = 0.01;
  ASSERT_EQ(robust.measured_local_loss_max_inliers, 50);

  auto solve = [&](const std::vector<RelativePoseConstraint>& local, const SolverOptions& options) {
    PoseVector poses = truth;
    EXPECT_TRUE(SolvePoses({{}, local, {}, {}, {}}, options, &poses).usable);
    return error_deg(poses);
  };
  const double ls = solve(make(true, 20, 3.0), least_squares);
  const double weak = solve(make(true, 20, 3.0), robust);
  const double strong = solve(make(true, 200, 3.0), robust);
  const double unmeasured = solve(make(false, 20, 3.0), robust);
  std::printf(
      "frames 1 -> 2 turned (deg): least squares %.3f; loss: weak pair %.3f, strong pair %.3f, unmeasured %.3f\n", ls,
      weak, strong, unmeasured);
  // Least squares: the pair's 3 deg split between it and the links that disagree with it.
  EXPECT_GT(ls, 0.5);
  EXPECT_LT(ls, 2.5);
  EXPECT_LT(weak, 0.25 * ls);
  EXPECT_NEAR(strong, ls, 1e-6);      // every link has 200 inliers: least squares, exactly
  EXPECT_NEAR(unmeasured, ls, 1e-6);  // the weak link is not measured, the others are strong
  // With no wrong pair the loss leaves the truth alone: started 0.2 deg off, frame 2 comes back.
  PoseVector poses = truth;
  poses[2].rotation = poses[2].rotation * Eigen::AngleAxisd(0.2 * M_PI / 180, Eigen::Vector3d::UnitX());
  ASSERT_TRUE(SolvePoses({{}, make(true, 20, 0.0), {}, {}, {}}, robust, &poses).usable);
  EXPECT_LT(error_deg(poses), 0.01);
}

// The truth itself jolts: frames 0-4 turn 2 deg per frame about one axis and frames 5-9
// turn back at 2 deg per frame (a hand-held camera swung the other way), and the odometry
// measured every pair exactly. E_V asks for steady motion, so in least squares it bends
// the frames about the turn off the truth against E_L. Through E_V's loss on triples the
// odometry measured (--measured-velocity-loss-scale: the jolt's residual, 0.07 rad at the
// 1 m lever arm, is 3.5 times the 2 cm scale) the measured motion stands; triples over a
// pair left to the motion prior keep least squares (nothing else holds those directions).
// Measured: the worst frame 1.92 deg off the truth in least squares, 0.38 through the loss.
TEST(SolvePoses, MeasuredVelocityLossLetsAMeasuredJoltStand) {
  const int n = 10;
  const Eigen::Vector3d axis = Eigen::Vector3d(0.1, 1, 0.2).normalized();
  PoseVector truth(n);
  for (int i = 1; i < n; ++i) {
    const double angle = (i <= 4 ? 2.0 : -2.0) * M_PI / 180;
    truth[i].rotation = truth[i - 1].rotation * Eigen::AngleAxisd(angle, axis);
    truth[i].translation = truth[i - 1].translation + Eigen::Vector3d(0.01, 0.002, -0.004);
  }
  std::vector<RelativePoseConstraint> local;
  for (int a = 0; a + 1 < n; ++a) {
    const Rigid3d a_from_b = truth[a].ToRigid().inverse() * truth[a + 1].ToRigid();
    local.push_back({a, a + 1, Eigen::Quaterniond(a_from_b.linear()), a_from_b.translation(), 1.0});
  }
  auto steady = [](bool measured) {
    std::vector<SteadyMotionConstraint> v;
    for (int b = 1; b + 1 < n; ++b) v.push_back({b - 1, b, b + 1, 1.0, 1.0, 1.0, measured});
    return v;
  };
  // The largest turn of any frame relative to frame 0, against the truth's.
  auto error_deg = [&](const PoseVector& poses) {
    double worst = 0;
    for (int i = 1; i < n; ++i) {
      worst = std::max(worst, (poses[0].rotation.conjugate() * poses[i].rotation)
                                  .angularDistance(truth[0].rotation.conjugate() * truth[i].rotation));
    }
    return worst * 180 / M_PI;
  };
  SolverOptions least_squares;
  least_squares.solve = SolveMode::kConverge;
  least_squares.weight_inertia = 1e-9;
  least_squares.measured_velocity_loss_scale = 0;
  SolverOptions robust = least_squares;
  robust.measured_velocity_loss_scale = 0.02;
  auto solve = [&](bool measured, const SolverOptions& options) {
    PoseVector poses = truth;
    EXPECT_TRUE(SolvePoses({{}, local, {}, {}, steady(measured)}, options, &poses).usable);
    return error_deg(poses);
  };
  const double ls = solve(true, least_squares);
  const double loss = solve(true, robust);
  const double unmeasured = solve(false, robust);
  std::printf("worst turn off the truth (deg): least squares %.4f, loss %.4f, unmeasured triples %.4f\n", ls, loss,
              unmeasured);
  EXPECT_GT(ls, 0.1);
  EXPECT_LT(loss, 0.25 * ls);
  EXPECT_NEAR(unmeasured, ls, 1e-6);
}

}  // namespace
}  // namespace f2c
