#include "f2c/optim/coarse_pcg.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "f2c/optim/pose_problem.h"

namespace f2c {
namespace {

// A chain of `n` variables of 3 columns each, every one coupled to the next two and, every
// fifth, to a far one (a loop), plus a random diagonal: symmetric positive definite.
struct ChainSystem {
  std::vector<int> start, tangent;
  std::unique_ptr<BlockSymmetricMatrix> h;

  ChainSystem(int n, std::mt19937& rng) {
    std::normal_distribution<double> g(0, 1);
    std::vector<std::vector<int>> coupled;
    for (int v = 0; v < n; ++v) {
      start.push_back(3 * v);
      tangent.push_back(3);
      coupled.push_back({v});
    }
    std::vector<std::pair<int, int>> edges;
    for (int v = 0; v + 1 < n; ++v) edges.push_back({v, v + 1});
    for (int v = 0; v + 2 < n; ++v) edges.push_back({v, v + 2});
    for (int v = 0; v + 17 < n; v += 5) edges.push_back({v, v + 17});
    for (auto [a, b] : edges) coupled.push_back({a, b});
    h = std::make_unique<BlockSymmetricMatrix>(coupled, start, tangent);
    // Each edge a residual J = [A, -A] (A random, well conditioned): H += J^T J, a sum of
    // squares that leaves the whole chain moving together free; a small diagonal holds it.
    for (auto [a, b] : edges) {
      Eigen::Matrix3d m = Eigen::Matrix3d::Identity() + 0.3 * Eigen::Matrix3d::NullaryExpr([&] { return g(rng); });
      const Eigen::Matrix3d mtm = m.transpose() * m;
      const Eigen::Matrix3d off = -mtm;
      h->Add(a, a, h->Offset(a, a), mtm.data());
      h->Add(b, b, h->Offset(b, b), mtm.data());
      h->Add(a, b, h->Offset(a, b), off.data());
    }
    for (int v = 0; v < n; ++v) {
      const Eigen::Matrix3d d = 1e-4 * Eigen::Matrix3d::Identity();
      h->Add(v, v, h->Offset(v, v), d.data());
    }
  }
};

// Controls every `spacing` variables, each variable blended between its two (3 columns each,
// the identity); smoother groups of `group_size` consecutive variables.
TwoLevelPcg ChainPreconditioner(int n, int spacing, int group_size = 8) {
  std::vector<std::vector<CoarseBasis>> basis(n);
  std::vector<int> group(n);
  const int controls = (n - 1 + spacing - 1) / spacing + 1;
  for (int v = 0; v < n; ++v) {
    const int k = std::min(v / spacing, controls - 2);
    const int last = std::min((k + 1) * spacing, n - 1);
    const double t = static_cast<double>(v - k * spacing) / (last - k * spacing);
    if (t < 1) basis[v].push_back({k, (1 - t) * Eigen::MatrixXd::Identity(3, 3)});
    if (t > 0) basis[v].push_back({k + 1, t * Eigen::MatrixXd::Identity(3, 3)});
    group[v] = v / group_size;
  }
  return TwoLevelPcg(basis, std::vector<int>(controls, 3), group);
}

TEST(TwoLevelPcg, SolvesToTheCholeskySolution) {
  std::mt19937 rng(5);
  ChainSystem system(400, rng);
  std::normal_distribution<double> g(0, 1);
  const Eigen::VectorXd b = Eigen::VectorXd::NullaryExpr(system.h->size(), [&] { return g(rng); });
  Eigen::VectorXd direct;
  SparseCholesky cholesky(FillOrdering::kNestedDissection);
  ASSERT_TRUE(cholesky.Solve(system.h.get(), b, &direct));

  TwoLevelPcg pcg = ChainPreconditioner(400, 8);
  ASSERT_TRUE(pcg.Setup(*system.h));
  TwoLevelPcgOptions options;
  options.tolerance = 1e-10;
  Eigen::VectorXd x;
  const TwoLevelPcgSummary s = pcg.Solve(*system.h, b, options, &x);
  EXPECT_TRUE(s.converged);
  EXPECT_LT((x - direct).norm(), 1e-6 * direct.norm());
  EXPECT_LT((system.h->Multiply(x) - b).norm(), 1e-9 * b.norm());
}

// The coarse space is what makes it fast: with two controls for the whole chain (a coarse
// space of straight lines only) the same groups need several times the iterations on this
// long chain.
TEST(TwoLevelPcg, TheCoarseSpaceCutsTheIterations) {
  std::mt19937 rng(6);
  ChainSystem system(400, rng);
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(system.h->size());
  TwoLevelPcgOptions options;
  options.tolerance = 1e-8;
  options.max_iterations = 5000;
  Eigen::VectorXd x;
  TwoLevelPcg fine = ChainPreconditioner(400, 8);
  ASSERT_TRUE(fine.Setup(*system.h));
  const TwoLevelPcgSummary with_controls = fine.Solve(*system.h, b, options, &x);
  TwoLevelPcg coarse = ChainPreconditioner(400, 399);
  ASSERT_TRUE(coarse.Setup(*system.h));
  const TwoLevelPcgSummary one_control = coarse.Solve(*system.h, b, options, &x);
  ASSERT_TRUE(with_controls.converged);
  ASSERT_TRUE(one_control.converged);
  EXPECT_LT(3 * with_controls.iterations, one_control.iterations)
      << with_controls.iterations << " vs " << one_control.iterations;
}

// Every control moving the same rigid motion about the world's origin (each control's own
// translation v_k = v + omega x c_k, as its rotation turns about its position c_k) moves the
// whole trajectory rigidly: relative poses unchanged to second order. A motion of one control
// alone bends it (the test can fail).
TEST(PoseCoarseSpace, EqualControlMotionsMoveTheTrajectoryRigidly) {
  std::mt19937 rng(7);
  std::normal_distribution<double> g(0, 1);
  PoseVector poses(23);
  for (size_t i = 0; i < poses.size(); ++i) {
    poses[i].rotation = Eigen::Quaterniond(Eigen::AngleAxisd(0.1 * i, Eigen::Vector3d(g(rng), g(rng), 1).normalized()));
    poses[i].translation = Eigen::Vector3d(0.2 * i, std::sin(0.3 * i), 1.5 + 0.1 * g(rng));
  }
  PoseProblem problem;
  for (Pose& p : poses) problem.AddPose(&p);
  const CoarseSpace space = problem.PoseCoarseSpace(5);
  ASSERT_EQ(space.block_sizes.size(), 6u);  // 0, 5, 10, 15, 20 and 22
  const double eps = 1e-4;
  const Eigen::Vector3d omega = eps * Eigen::Vector3d(0.3, -0.8, 0.5), v = eps * Eigen::Vector3d(1, 2, -1);
  auto moved = [&](bool rigid) {
    PoseVector out = poses;
    const std::vector<int> controls = {0, 5, 10, 15, 20, 22};
    for (size_t i = 0; i < poses.size(); ++i) {
      Pose& p = out[i];
      Eigen::Vector3d dr = Eigen::Vector3d::Zero(), dt = Eigen::Vector3d::Zero();
      for (const CoarseBasis& c : space.basis.at(poses[i].rotation_data())) {
        Eigen::Matrix<double, 6, 1> y = Eigen::Matrix<double, 6, 1>::Zero();
        if (rigid || c.block == 2) y << omega, v + omega.cross(poses[controls[c.block]].translation);
        dr += c.basis * y;
      }
      for (const CoarseBasis& c : space.basis.at(poses[i].translation_data())) {
        Eigen::Matrix<double, 6, 1> y = Eigen::Matrix<double, 6, 1>::Zero();
        if (rigid || c.block == 2) y << omega, v + omega.cross(poses[controls[c.block]].translation);
        dt += c.basis * y;
      }
      // The quaternion manifold's step: [cos|d|, sin|d| d/|d|] q.
      const double angle = dr.norm();
      Eigen::Quaterniond step(std::cos(angle), 0, 0, 0);
      if (angle > 0) step.vec() = (std::sin(angle) / angle) * dr;
      p.rotation = step * p.rotation;
      p.translation += dt;
    }
    return out;
  };
  auto max_relative_change = [&](const PoseVector& out) {
    double worst = 0;
    for (size_t a = 0; a < poses.size(); ++a) {
      for (size_t b = a + 1; b < poses.size(); ++b) {
        const Rigid3d before = poses[a].ToRigid().inverse() * poses[b].ToRigid();
        const Rigid3d after = out[a].ToRigid().inverse() * out[b].ToRigid();
        worst = std::max(worst, (before.translation() - after.translation()).norm());
        worst = std::max(worst, Eigen::AngleAxisd(before.rotation().transpose() * after.rotation()).angle());
      }
    }
    return worst;
  };
  EXPECT_LT(max_relative_change(moved(true)), 1e-6);
  EXPECT_GT(max_relative_change(moved(false)), 1e-5);
}

}  // namespace
}  // namespace f2c
