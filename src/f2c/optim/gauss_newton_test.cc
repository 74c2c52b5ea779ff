#include "f2c/optim/gauss_newton.h"

#include <ceres/ceres.h>
#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <memory>
#include <random>
#include <utility>
#include <vector>

#include "f2c/optim/cost_functions.h"
#include "f2c/optim/pose.h"
#include "f2c/optim/structure_costs.h"
#include "f2c/optim/test_helpers.h"

namespace f2c {
namespace {

// r = x - target (3 residuals): pins a translation.
struct Pin {
  Eigen::Vector3d target;
  template <typename T>
  bool operator()(const T* x, T* r) const {
    for (int i = 0; i < 3; ++i) r[i] = x[i] - T(target[i]);
    return true;
  }
};

// r = atan(x): Gauss-Newton from x = 2 overshoots to about -3.5, where the cost is higher.
struct Arctan {
  template <typename T>
  bool operator()(const T* x, T* r) const {
    r[0] = atan(x[0]);
    return true;
  }
};

// r = a x (1 residual on a 2-vector): the direction (-a_1, a_0) is free.
struct Dot {
  template <typename T>
  bool operator()(const T* x, T* r) const {
    r[0] = x[0] + T(2) * x[1] - T(1);
    return true;
  }
};

// One step of Ceres' Levenberg-Marquardt from an infinite trust region (dense QR) on
// `poses`, the first held, and `planes` (4 doubles each, on `plane_manifold`).
ceres::Solver::Summary OneCeresStep(PoseVector* poses, const std::vector<GaussNewtonResidual>& residuals,
                                    const std::vector<double*>& planes = {},
                                    const ceres::Manifold* plane_manifold = nullptr) {
  ceres::EigenQuaternionManifold quaternion;
  ceres::Problem::Options o;
  o.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  o.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  o.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(o);
  for (Pose& pose : *poses) {
    problem.AddParameterBlock(pose.rotation_data(), 4, &quaternion);
    problem.AddParameterBlock(pose.translation_data(), 3);
  }
  for (double* plane : planes) problem.AddParameterBlock(plane, 4, const_cast<ceres::Manifold*>(plane_manifold));
  problem.SetParameterBlockConstant((*poses)[0].rotation_data());
  problem.SetParameterBlockConstant((*poses)[0].translation_data());
  for (const GaussNewtonResidual& r : residuals) {
    problem.AddResidualBlock(const_cast<ceres::CostFunction*>(r.cost), const_cast<ceres::LossFunction*>(r.loss),
                             r.blocks);
  }
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = 1;
  options.initial_trust_region_radius = 1e16;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  return summary;
}

// A small pose problem: relative-pose and steady-motion-free constraints between noisy
// poses, plus a plane tied to one frame (E_P) and pinned translations, some under losses
// whose second derivative is negative (Cauchy), zero (Huber) and positive (Tolerant), so that
// every branch of the loss correction is used.
struct SmallProblem {
  PoseVector poses;
  Eigen::Vector4d plane;
  ceres::EigenQuaternionManifold quaternion;
  PlaneManifold plane_manifold;
  std::vector<std::unique_ptr<ceres::CostFunction>> costs;
  std::vector<std::unique_ptr<ceres::LossFunction>> losses;
  std::vector<GaussNewtonResidual> residuals;

  explicit SmallProblem(unsigned seed) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> g(0.0, 1.0);
    for (int i = 0; i < 4; ++i) poses.push_back(RandomPose(rng));
    losses.emplace_back(new ceres::CauchyLoss(0.3));
    losses.emplace_back(new ceres::HuberLoss(0.2));
    losses.emplace_back(new ceres::TolerantLoss(0.5, 0.4));
    for (int i = 0; i + 1 < 4; ++i) {
      // The relative transforms the poses would have if they were a little different.
      const Eigen::Quaterniond q = (poses[i].rotation.conjugate() * poses[i + 1].rotation *
                                    Eigen::Quaterniond(Eigen::AngleAxisd(0.05 * g(rng), Eigen::Vector3d::UnitX())))
                                       .normalized();
      const Eigen::Vector3d t = poses[i].rotation.conjugate() * (poses[i + 1].translation - poses[i].translation) +
                                0.1 * Eigen::Vector3d(g(rng), g(rng), g(rng));
      costs.emplace_back(RelativePoseCost::Create(q, t, 1.0, 1.0));
      residuals.push_back({costs.back().get(),
                           i == 1 ? losses[0].get() : nullptr,
                           {poses[i].rotation_data(), poses[i].translation_data(), poses[i + 1].rotation_data(),
                            poses[i + 1].translation_data()}});
    }
    for (int i = 0; i < 4; ++i) {
      costs.emplace_back(new ceres::AutoDiffCostFunction<Pin, 3, 3>(
          new Pin{poses[i].translation + 0.3 * Eigen::Vector3d(g(rng), g(rng), g(rng))}));
      residuals.push_back({costs.back().get(), losses[i % 3].get(), {poses[i].translation_data()}});
    }
    const Eigen::Vector3d n = Eigen::Vector3d(0.2, 0.3, 0.9).normalized();
    plane << n, 0.4;
    Eigen::Matrix3d spread = Eigen::Matrix3d::Identity() * 0.2;
    costs.emplace_back(ProxyFitCost::Create(Eigen::Vector3d(0.1, -0.2, 1.5), spread));
    residuals.push_back(
        {costs.back().get(), nullptr, {poses[2].rotation_data(), poses[2].translation_data(), plane.data()}});
    costs.emplace_back(PlaneChangeCost::Create(Eigen::Vector3d(0.25, 0.3, 0.88).normalized(), 0.35, 1.0, 1.0));
    residuals.push_back({costs.back().get(), nullptr, {plane.data()}});
  }

  void AddTo(GaussNewtonProblem* problem) {
    for (size_t i = 0; i < poses.size(); ++i) {
      problem->AddVariable(poses[i].rotation_data(), 4, &quaternion, i == 0);
      problem->AddVariable(poses[i].translation_data(), 3, nullptr, i == 0);
    }
    problem->AddVariable(plane.data(), 4, &plane_manifold, false);
  }

  // One step of Ceres' Levenberg-Marquardt from an infinite trust region.
  ceres::Solver::Summary SolveWithCeres() { return OneCeresStep(&poses, residuals, {plane.data()}, &plane_manifold); }
};

TEST(GaussNewton, OneStepIsCeresLevenbergMarquardtStepFromAnInfiniteTrustRegion) {
  for (unsigned seed : {1u, 2u, 3u}) {
    SmallProblem ceres_side(seed), start(seed);
    const ceres::Solver::Summary c = ceres_side.SolveWithCeres();
    // Ceres counts its start as iteration 0.
    ASSERT_EQ(c.iterations.size(), 2u);
    ASSERT_TRUE(c.iterations.back().step_is_successful) << c.FullReport();
    for (auto ordering : {GaussNewtonOptions::Ordering::kAmd, GaussNewtonOptions::Ordering::kNestedDissection}) {
      SmallProblem ours(seed);
      GaussNewtonProblem problem;
      ours.AddTo(&problem);
      GaussNewtonOptions options;
      options.ordering = ordering;
      const GaussNewtonSummary s = problem.Solve(ours.residuals, options);
      ASSERT_TRUE(s.factorized) << s.termination;
      EXPECT_EQ(s.accepted, 1) << s.termination;
      for (size_t i = 0; i < ours.poses.size(); ++i) {
        EXPECT_LT((ours.poses[i].rotation.coeffs() - ceres_side.poses[i].rotation.coeffs()).norm(), 1e-9) << seed;
        EXPECT_LT((ours.poses[i].translation - ceres_side.poses[i].translation).norm(), 1e-9) << seed;
        EXPECT_NEAR(ours.poses[i].rotation.norm(), 1, 1e-12);  // on its manifold
      }
      EXPECT_LT((ours.plane - ceres_side.plane).norm(), 1e-9);
      EXPECT_NEAR(ours.plane.head<3>().norm(), 1, 1e-12);
      EXPECT_GT((ours.poses[3].translation - start.poses[3].translation).norm(), 1e-3);  // it moved
      // The held frame did not.
      EXPECT_EQ(ours.poses[0].translation, start.poses[0].translation);
      EXPECT_EQ(ours.poses[0].rotation.coeffs(), start.poses[0].rotation.coeffs());
    }
  }
}

TEST(GaussNewton, CostsAreCeresRobustifiedHalfSquares) {
  SmallProblem ours(4), ceres_side(4);
  GaussNewtonProblem problem;
  ours.AddTo(&problem);
  GaussNewtonOptions options;
  options.max_iterations = 1;
  const GaussNewtonSummary s = problem.Solve(ours.residuals, options);
  const ceres::Solver::Summary c = ceres_side.SolveWithCeres();
  EXPECT_NEAR(s.initial_cost, c.initial_cost, 1e-12 * c.initial_cost);
  EXPECT_NEAR(s.final_cost, c.final_cost, 1e-9 * c.initial_cost);
  EXPECT_LT(s.final_cost, s.initial_cost);
}

TEST(GaussNewton, AStepThatRaisesTheCostIsUndone) {
  double x = 2;
  std::unique_ptr<ceres::CostFunction> cost(new ceres::AutoDiffCostFunction<Arctan, 1, 1>(new Arctan));
  GaussNewtonProblem problem;
  problem.AddVariable(&x, 1, nullptr, false);
  GaussNewtonOptions undamped;
  undamped.max_damped_steps = 0;
  const GaussNewtonSummary s = problem.Solve({{cost.get(), nullptr, {&x}}}, undamped);
  EXPECT_EQ(s.iterations, 1);
  EXPECT_EQ(s.accepted, 0);
  EXPECT_EQ(s.damped, 0);
  EXPECT_EQ(s.termination, "step rejected");
  EXPECT_EQ(x, 2);
  EXPECT_NEAR(s.final_cost, 0.5 * std::atan(2.0) * std::atan(2.0), 1e-15);
  // From 0.5 the step lands near 0: kept, and more steps converge to the root.
  x = 0.5;
  GaussNewtonOptions more;
  more.max_iterations = 10;
  more.max_damped_steps = 0;
  const GaussNewtonSummary t = problem.Solve({{cost.get(), nullptr, {&x}}}, more);
  EXPECT_GE(t.accepted, 2);
  EXPECT_NEAR(x, 0, 1e-9);
}

// The same overshoot, retried with Levenberg-Marquardt's damping: the step -r / J = -5 atan(2)
// becomes -5 atan(2) / (1 + lambda); lambda 0.001, 0.01 and 0.1 still land beyond -2.9, where
// the cost is higher, and lambda 1 halves the step, to -0.77: kept.
TEST(GaussNewton, ARejectedStepIsRetriedDamped) {
  double x = 2;
  std::unique_ptr<ceres::CostFunction> cost(new ceres::AutoDiffCostFunction<Arctan, 1, 1>(new Arctan));
  GaussNewtonProblem problem;
  problem.AddVariable(&x, 1, nullptr, false);
  const GaussNewtonSummary s = problem.Solve({{cost.get(), nullptr, {&x}}}, GaussNewtonOptions{});
  EXPECT_EQ(s.iterations, 1);
  EXPECT_EQ(s.accepted, 1);
  EXPECT_EQ(s.damped, 4);
  EXPECT_EQ(s.termination, "iteration limit");
  EXPECT_NEAR(x, 2 - 0.5 * 5 * std::atan(2.0), 1e-12);
  EXPECT_NEAR(s.final_cost, 0.5 * std::atan(x) * std::atan(x), 1e-15);
  EXPECT_LT(s.final_cost, s.initial_cost);
  // Three retries stop short of lambda 1: nothing moves.
  x = 2;
  GaussNewtonOptions three;
  three.max_damped_steps = 3;
  const GaussNewtonSummary t = problem.Solve({{cost.get(), nullptr, {&x}}}, three);
  EXPECT_EQ(t.accepted, 0);
  EXPECT_EQ(t.damped, 3);
  EXPECT_EQ(t.termination, "step rejected");
  EXPECT_EQ(x, 2);
}

TEST(GaussNewton, AFreeDirectionIsReportedAndNothingMoves) {
  Eigen::Vector2d x(0.3, 0.7);
  std::unique_ptr<ceres::CostFunction> cost(new ceres::AutoDiffCostFunction<Dot, 1, 2>(new Dot));
  GaussNewtonProblem problem;
  problem.AddVariable(x.data(), 2, nullptr, false);
  const GaussNewtonSummary s = problem.Solve({{cost.get(), nullptr, {x.data()}}}, GaussNewtonOptions{});
  EXPECT_FALSE(s.factorized);
  EXPECT_EQ(s.termination, "the normal equations are not positive definite");
  EXPECT_EQ(x, Eigen::Vector2d(0.3, 0.7));
}

// A chain of `n` noisy poses: relative-pose constraints to the next two frames (every third
// under a Cauchy loss) and a pin on each translation; big enough that the linearisation and
// the summation into the normal equations are split between threads.
struct ChainProblem {
  PoseVector poses;
  ceres::EigenQuaternionManifold quaternion;
  std::vector<std::unique_ptr<ceres::CostFunction>> costs;
  ceres::CauchyLoss loss{0.05};
  std::vector<GaussNewtonResidual> residuals;

  explicit ChainProblem(int n) {
    std::mt19937 rng(7);
    std::normal_distribution<double> g(0.0, 1.0);
    for (int i = 0; i < n; ++i) poses.push_back(RandomPose(rng));
    for (int i = 0; i < n; ++i) {
      for (int k = 1; k <= 2 && i + k < n; ++k) {
        const Pose& a = poses[i];
        const Pose& b = poses[i + k];
        const Eigen::Quaterniond q = (a.rotation.conjugate() * b.rotation *
                                      Eigen::Quaterniond(Eigen::AngleAxisd(0.02 * g(rng), Eigen::Vector3d::UnitY())))
                                         .normalized();
        const Eigen::Vector3d t =
            a.rotation.conjugate() * (b.translation - a.translation) + 0.05 * Eigen::Vector3d(g(rng), g(rng), g(rng));
        costs.emplace_back(RelativePoseCost::Create(q, t, 1.0, 1.0));
        residuals.push_back({costs.back().get(),
                             (i + k) % 3 == 0 ? &loss : nullptr,
                             {poses[i].rotation_data(), poses[i].translation_data(), poses[i + k].rotation_data(),
                              poses[i + k].translation_data()}});
      }
      costs.emplace_back(new ceres::AutoDiffCostFunction<Pin, 3, 3>(
          new Pin{poses[i].translation + 0.1 * Eigen::Vector3d(g(rng), g(rng), g(rng))}));
      residuals.push_back({costs.back().get(), nullptr, {poses[i].translation_data()}});
    }
  }

  GaussNewtonSummary Solve(int threads, size_t chunk = GaussNewtonOptions().linearisation_chunk) {
    GaussNewtonProblem problem;
    for (Pose& p : poses) {
      problem.AddVariable(p.rotation_data(), 4, &quaternion, false);
      problem.AddVariable(p.translation_data(), 3, nullptr, false);
    }
    GaussNewtonOptions options;
    options.max_iterations = 3;
    options.linearisation_chunk = chunk;
    GaussNewtonSummary summary;
    tbb::task_arena arena(threads);
    arena.execute([&] { summary = problem.Solve(residuals, options); });
    return summary;
  }
};

// Two solves of the same chain took the same three steps, bit for bit (every entry of the
// normal equations sums the same numbers in the same order), and moved the poses.
void ExpectSameSteps(const ChainProblem& x, const GaussNewtonSummary& a, const ChainProblem& y,
                     const GaussNewtonSummary& b) {
  const ChainProblem start(400);
  ASSERT_EQ(a.accepted, 3) << a.termination;
  EXPECT_EQ(b.accepted, 3) << b.termination;
  EXPECT_EQ(a.final_cost, b.final_cost);
  EXPECT_LT(a.final_cost, 0.5 * a.initial_cost);
  double moved = 0;
  for (size_t i = 0; i < x.poses.size(); ++i) {
    EXPECT_EQ(x.poses[i].rotation.coeffs(), y.poses[i].rotation.coeffs()) << i;
    EXPECT_EQ(x.poses[i].translation, y.poses[i].translation) << i;
    moved = std::max(moved, (x.poses[i].translation - start.poses[i].translation).norm());
  }
  EXPECT_GT(moved, 1e-3);
}

TEST(GaussNewton, TheStepDoesNotDependOnTheThreads) {
  ChainProblem one(400), four(400);
  const GaussNewtonSummary a = one.Solve(1);
  const GaussNewtonSummary b = four.Solve(4);
  ExpectSameSteps(one, a, four, b);
}

// Linearised one block at a time (each block its own chunk, summed into H before the next
// is linearised) or all at once: the same steps, bit for bit.
TEST(GaussNewton, TheStepDoesNotDependOnTheLinearisationChunk) {
  ChainProblem whole(400), blockwise(400);
  const GaussNewtonSummary a = whole.Solve(2);
  const GaussNewtonSummary b = blockwise.Solve(2, /*chunk=*/1);
  ExpectSameSteps(whole, a, blockwise, b);
}

// Every frame tied to every other: a dense factor, which CHOLMOD factors supernodally (the
// walks' joint steps are; the small problem above takes the simplicial path). The step is
// still Ceres' one Levenberg-Marquardt step from an infinite trust region (dense QR).
TEST(GaussNewton, ASupernodalFactorGivesCeresStep) {
  const int n = 40;
  std::mt19937 rng(11);
  std::normal_distribution<double> g(0.0, 1.0);
  PoseVector poses, start;
  for (int i = 0; i < n; ++i) poses.push_back(RandomPose(rng));
  ceres::EigenQuaternionManifold quaternion;
  std::vector<std::unique_ptr<ceres::CostFunction>> costs;
  ceres::CauchyLoss loss(0.05);
  std::vector<std::pair<int, int>> frames;  // each cost's two frames
  for (int a = 0; a < n; ++a) {
    for (int b = a + 1; b < n; ++b) {
      const Eigen::Quaterniond q = (poses[a].rotation.conjugate() * poses[b].rotation *
                                    Eigen::Quaterniond(Eigen::AngleAxisd(0.02 * g(rng), Eigen::Vector3d::UnitZ())))
                                       .normalized();
      const Eigen::Vector3d t = poses[a].rotation.conjugate() * (poses[b].translation - poses[a].translation) +
                                0.05 * Eigen::Vector3d(g(rng), g(rng), g(rng));
      costs.emplace_back(RelativePoseCost::Create(q, t, 1.0, 1.0));
      frames.push_back({a, b});
    }
  }
  auto residuals_on = [&](PoseVector* p) {
    std::vector<GaussNewtonResidual> residuals;
    for (size_t k = 0; k < costs.size(); ++k) {
      const auto [a, b] = frames[k];
      residuals.push_back(
          {costs[k].get(),
           (a + b) % 5 == 0 ? &loss : nullptr,
           {(*p)[a].rotation_data(), (*p)[a].translation_data(), (*p)[b].rotation_data(), (*p)[b].translation_data()}});
    }
    return residuals;
  };
  start = poses;
  PoseVector ceres_poses = poses;
  const ceres::Solver::Summary summary = OneCeresStep(&ceres_poses, residuals_on(&ceres_poses));
  ASSERT_EQ(summary.iterations.size(), 2u);
  ASSERT_TRUE(summary.iterations.back().step_is_successful) << summary.FullReport();
  for (auto ordering : {GaussNewtonOptions::Ordering::kAmd, GaussNewtonOptions::Ordering::kNestedDissection}) {
    poses = start;
    GaussNewtonProblem problem;
    for (int i = 0; i < n; ++i) {
      problem.AddVariable(poses[i].rotation_data(), 4, &quaternion, i == 0);
      problem.AddVariable(poses[i].translation_data(), 3, nullptr, i == 0);
    }
    GaussNewtonOptions options;
    options.ordering = ordering;
    const GaussNewtonSummary s = problem.Solve(residuals_on(&poses), options);
    ASSERT_TRUE(s.factorized) << s.termination;
    EXPECT_TRUE(s.supernodal);
    EXPECT_EQ(s.accepted, 1) << s.termination;
    double moved = 0;
    for (int i = 0; i < n; ++i) {
      EXPECT_LT((poses[i].rotation.coeffs() - ceres_poses[i].rotation.coeffs()).norm(), 1e-9) << i;
      EXPECT_LT((poses[i].translation - ceres_poses[i].translation).norm(), 1e-9) << i;
      moved = std::max(moved, (poses[i].translation - start[i].translation).norm());
    }
    EXPECT_GT(moved, 1e-3);
  }
  // The small problem's factor is simplicial.
  SmallProblem small(1);
  GaussNewtonProblem problem;
  small.AddTo(&problem);
  EXPECT_FALSE(problem.Solve(small.residuals, GaussNewtonOptions{}).supernodal);
}

}  // namespace
}  // namespace f2c
