#include "f2c/optim/problem.h"

#include <gtest/gtest.h>

#include <random>

#include "f2c/geometry/rigid.h"

namespace f2c {
namespace {

// A corner of a room (floor and two walls) and two edges, seen by `n` cameras on an arc.
struct Scene {
  std::vector<Eigen::Vector3d> plane_normals = {Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitX(),
                                                Eigen::Vector3d::UnitY()};
  std::vector<double> plane_offsets = {0.0, -2.0, -2.5};  // n . x = d
  PoseVector truth;
};

Scene MakeScene(int n) {
  Scene scene;
  for (int i = 0; i < n; ++i) {
    const double angle = 0.15 * i;
    Pose pose;
    pose.rotation = Eigen::AngleAxisd(-2.3 + angle, Eigen::Vector3d::UnitZ()) *
                    Eigen::AngleAxisd(-1.9, Eigen::Vector3d::UnitX());
    pose.translation = Eigen::Vector3d(0.3 * std::cos(angle), 0.3 * std::sin(angle), 1.4);
    scene.truth.push_back(pose);
  }
  return scene;
}

Eigen::Vector3d InCamera(const Pose& pose, const Eigen::Vector3d& x) { return pose.rotation.conjugate() * (x - pose.translation); }

// Exact correspondences between every pair of frames: points on each plane and on the two
// wall-floor edges, each frame sampling its own points.
std::vector<FeatureCorrespondence> ExactCorrespondences(const Scene& scene, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  std::vector<FeatureCorrespondence> out;
  const int n = static_cast<int>(scene.truth.size());
  for (int a = 0; a < n; ++a) {
    for (int b = 0; b < n; ++b) {
      if (a == b) continue;
      const Pose& pa = scene.truth[a];
      const Pose& pb = scene.truth[b];
      for (int k = 0; k < 30; ++k) {
        const int plane = k % 3;
        const Eigen::Vector3d& normal = scene.plane_normals[plane];
        auto on_plane = [&]() -> Eigen::Vector3d {
          Eigen::Vector3d x(u(rng), u(rng), 1.0 + 0.5 * u(rng));
          return x - (normal.dot(x) - scene.plane_offsets[plane]) * normal;
        };
        FeatureCorrespondence c;
        c.target_frame = a;
        c.point_frame = b;
        c.target_point = InCamera(pa, on_plane()).cast<float>();
        c.target_direction = (pa.rotation.conjugate() * normal).cast<float>();
        c.point = InCamera(pb, on_plane()).cast<float>();
        out.push_back(c);
      }
      // Edges: the floor meets x = -2 along y, and y = -2.5 along x.
      for (int k = 0; k < 6; ++k) {
        const bool along_y = k % 2 == 0;
        const Eigen::Vector3d direction = along_y ? Eigen::Vector3d::UnitY() : Eigen::Vector3d::UnitX();
        auto on_edge = [&]() -> Eigen::Vector3d { return along_y ? Eigen::Vector3d(-2.0, u(rng), 0) : Eigen::Vector3d(u(rng), -2.5, 0); };
        FeatureCorrespondence c;
        c.target_frame = a;
        c.point_frame = b;
        c.kind = CorrespondenceKind::kPointToLine;
        c.weight = 0.5;
        c.target_point = InCamera(pa, on_edge()).cast<float>();
        c.target_direction = (pa.rotation.conjugate() * direction).cast<float>();
        c.point = InCamera(pb, on_edge()).cast<float>();
        out.push_back(c);
      }
    }
  }
  return out;
}

PoseVector Perturb(const PoseVector& truth, double metres, double radians, std::mt19937& rng) {
  std::normal_distribution<double> g(0, 1);
  PoseVector out = truth;
  for (size_t i = 1; i < out.size(); ++i) {
    out[i].translation += metres * Eigen::Vector3d(g(rng), g(rng), g(rng));
    out[i].rotation = out[i].rotation * Eigen::Quaterniond(Eigen::AngleAxisd(radians, Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized()));
  }
  return out;
}

double MaxTranslationError(const PoseVector& a, const PoseVector& b) {
  double e = 0;
  for (size_t i = 0; i < a.size(); ++i) e = std::max(e, (a[i].translation - b[i].translation).norm());
  return e;
}
double MaxRotationErrorDeg(const PoseVector& a, const PoseVector& b) {
  double e = 0;
  for (size_t i = 0; i < a.size(); ++i) e = std::max(e, a[i].rotation.angularDistance(b[i].rotation) * 180 / M_PI);
  return e;
}

TEST(SolvePoses, CorrespondencesAloneRecoverPerturbedPoses) {
  const Scene scene = MakeScene(6);
  std::mt19937 rng(3);
  const std::vector<FeatureCorrespondence> c = ExactCorrespondences(scene, rng);
  PoseVector poses = Perturb(scene.truth, 0.03, 0.02, rng);
  SolverOptions options;
  options.one_step = false;
  options.weight_inertia = 1e-6;  // the reference here is the perturbed start
  SolveSummary s;
  for (int round = 0; round < 3; ++round) s = SolvePoses({c, {}, {}}, options, &poses);
  ASSERT_TRUE(s.usable) << s.termination;
  EXPECT_LT(MaxTranslationError(poses, scene.truth), 1e-4);
  EXPECT_LT(MaxRotationErrorDeg(poses, scene.truth), 0.01);
  EXPECT_LT(s.cost_after.at("E_C"), 1e-10);
  EXPECT_EQ(s.residual_blocks.at("E_C"), 6 * 5);  // one block per ordered pair of frames
}

TEST(SolvePoses, LocalConstraintsAtTheTruthCostNothing) {
  const Scene scene = MakeScene(5);
  std::vector<RelativePoseConstraint> local;
  for (int a = 0; a + 1 < 5; ++a) {
    const Rigid3d a_from_b = scene.truth[a].ToRigid().inverse() * scene.truth[a + 1].ToRigid();
    local.push_back({a, a + 1, Eigen::Quaterniond(a_from_b.linear()), a_from_b.translation(), 1.0 + a});
  }
  PoseVector poses = scene.truth;
  SolveSummary s = SolvePoses({{}, local, {}}, {}, &poses);
  EXPECT_LT(s.cost_before.at("E_L"), 1e-20);
  EXPECT_LT(MaxTranslationError(poses, scene.truth), 1e-9);
  // From perturbed poses, the chain of relative transforms alone brings them back (the first
  // pose is the gauge).
  std::mt19937 rng(5);
  poses = Perturb(scene.truth, 0.05, 0.03, rng);
  SolverOptions options;
  options.one_step = false;
  options.weight_inertia = 1e-9;
  for (int round = 0; round < 3; ++round) s = SolvePoses({{}, local, {}}, options, &poses);
  EXPECT_LT(MaxTranslationError(poses, scene.truth), 1e-5);
  EXPECT_LT(MaxRotationErrorDeg(poses, scene.truth), 1e-3);
}

TEST(SolvePoses, TermWeightsAreTotalsSharedAmongResiduals) {
  // One local constraint 10 cm off: its cost is w_L / 2 * 0.1^2 whatever its relative weight.
  PoseVector poses(2);
  poses[1].translation = Eigen::Vector3d(1.1, 0, 0);
  std::vector<RelativePoseConstraint> local = {{0, 1, Eigen::Quaterniond::Identity(), Eigen::Vector3d(1, 0, 0), 7.0}};
  SolverOptions options;
  options.weight_local = 300;
  const SolveSummary s = SolvePoses({{}, local, {}}, options, &poses);
  EXPECT_NEAR(s.cost_before.at("E_L"), 0.5 * 300 * 0.01, 1e-9);
  // E_I starts at zero and ends small; E_L almost vanishes.
  EXPECT_NEAR(s.cost_before.at("E_I"), 0.0, 1e-15);
  EXPECT_LT(s.cost_after.at("E_L"), 1e-4);
}

TEST(SolvePoses, OneGaussNewtonStepReducesTheCost) {
  const Scene scene = MakeScene(6);
  std::mt19937 rng(9);
  const std::vector<FeatureCorrespondence> c = ExactCorrespondences(scene, rng);
  PoseVector poses = Perturb(scene.truth, 0.02, 0.01, rng);
  SolverOptions options;
  options.one_step = true;
  const SolveSummary s = SolvePoses({c, {}, {}}, options, &poses);
  EXPECT_EQ(s.iterations, 1);
  EXPECT_LT(s.cost_after.at("E_C"), 0.05 * s.cost_before.at("E_C"));
}

}  // namespace
}  // namespace f2c
