#include "f2c/refine/local_alignment.h"

#include <gtest/gtest.h>

#include <map>
#include <memory>
#include <random>

#include "f2c/optim/cost_functions.h"
#include "f2c/optim/pose.h"

namespace f2c {
namespace {

PairAlignment Pair(int frame, AlignmentMethod method, int inliers, double fitness, double x) {
  PairAlignment p;
  p.frame = frame;
  p.method = method;
  p.inliers = inliers;
  p.fitness = fitness;
  if (method == AlignmentMethod::kIcp) p.degenerate = 3;  // a plain wall's: two slides and a turn left free
  p.prev_from_curr.translation() = Eigen::Vector3d(x, 0, 0);
  p.prev_from_curr.linear() = Eigen::AngleAxisd(0.01 * frame, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return p;
}

TEST(PairConfidence, SiftIcpPriorAndFitness) {
  const LocalAlignmentOptions o;
  // The authors' sigmoid: 5 inliers give 1/2, many give ~1.
  EXPECT_NEAR(PairConfidence(Pair(1, AlignmentMethod::kSift, 5, 1.0, 0), o), 0.5, 1e-12);
  EXPECT_NEAR(PairConfidence(Pair(1, AlignmentMethod::kSift, 100, 1.0, 0), o), 1.0, 1e-9);
  EXPECT_NEAR(PairConfidence(Pair(1, AlignmentMethod::kIcp, 0, 1.0, 0), o), 0.3, 1e-12);
  EXPECT_NEAR(PairConfidence(Pair(1, AlignmentMethod::kMotionPrior, 0, 0.0, 0), o), 0.01, 1e-12);
  // Fitness 0.5 is a quarter of the way from 0.4 to 0.8; below 0.4 the floor of 0.05.
  EXPECT_NEAR(PairConfidence(Pair(1, AlignmentMethod::kSift, 100, 0.5, 0), o), 0.25, 1e-9);
  EXPECT_NEAR(PairConfidence(Pair(1, AlignmentMethod::kIcp, 0, 0.1, 0), o), 0.3 * 0.05, 1e-12);
  // An ICP pair whose every direction the depth or the image measured counts like a SIFT
  // pair; one that left directions to the prediction stays at 0.3.
  PairAlignment measured = Pair(1, AlignmentMethod::kIcp, 0, 1.0, 0);
  measured.degenerate = 0;
  EXPECT_NEAR(PairConfidence(measured, o), 1.0, 1e-12);
  EXPECT_NEAR(PairConfidence(Pair(1, AlignmentMethod::kIcp, 0, 1.0, 0), o), 0.3, 1e-12);
  measured.fitness = 0.5;
  EXPECT_NEAR(PairConfidence(measured, o), 0.25, 1e-12);
  LocalAlignmentOptions half;
  half.icp_measured_weight = 0.5;
  EXPECT_NEAR(PairConfidence(measured, half), 0.125, 1e-12);
}

TEST(LocalConstraints, PowersOfTwoChainedWithTheWeakestLink) {
  std::vector<PairAlignment> pairs;
  for (int k = 1; k < 20; ++k) pairs.push_back(Pair(k, AlignmentMethod::kSift, 100, 1.0, 0.1 * k));
  pairs[9] = Pair(10, AlignmentMethod::kIcp, 0, 1.0, 1.0);  // frames 9 -> 10
  LocalAlignmentOptions o;
  o.max_power = 4;  // the paper's spans
  const std::vector<RelativePoseConstraint> c = LocalConstraints(pairs, o);
  // j + 1, 2, 4, 8, 16 inside 20 frames: 19 + 18 + 16 + 12 + 4.
  ASSERT_EQ(c.size(), 69u);
  for (const RelativePoseConstraint& r : c) {
    Rigid3d chained = Rigid3d::Identity();
    for (int k = r.frame_a + 1; k <= r.frame_b; ++k) chained = chained * pairs[k - 1].prev_from_curr;
    EXPECT_LT((r.translation_a_from_b - chained.translation()).norm(), 1e-12);
    EXPECT_LT(r.rotation_a_from_b.angularDistance(Eigen::Quaterniond(chained.linear())), 1e-12);
    const bool spans_icp = r.frame_a < 10 && r.frame_b >= 10;
    EXPECT_NEAR(r.weight, spans_icp ? 0.3 : PairConfidence(pairs[0], o), 1e-9) << r.frame_a << " " << r.frame_b;
    // The ICP pair left three directions to the prediction: every span across it is unmeasured.
    EXPECT_EQ(r.measured, !spans_icp) << r.frame_a << " " << r.frame_b;
  }
}

// Keyframe odometry: frames 1-3 aligned to keyframe 0, frame 3 starting a keyframe, frames 4
// and 5 aligned to 3, frame 2's alignment weak. Relative poses come from T0 along the tree of
// references; weights are the weakest alignment on the tree path. Frame 5's own alignment
// (span 2 from frame 3) is one of the spans; frame 3's (span 3) is added as its own.
TEST(LocalConstraints, KeyframeReferencesFollowTheTreeOfReferences) {
  std::vector<PairAlignment> pairs;
  for (int k = 1; k <= 5; ++k) {
    PairAlignment p = Pair(k, AlignmentMethod::kTrack, 100, 1.0, 0.1 * k);
    p.reference = k <= 3 ? 0 : 3;
    p.keyframe = k == 3;
    pairs.push_back(p);
  }
  pairs[1] = Pair(2, AlignmentMethod::kIcp, 0, 1.0, 0.2);
  pairs[1].reference = 0;
  std::vector<Rigid3d> world(6, Rigid3d::Identity());
  for (int k = 1; k <= 5; ++k) world[k] = world[pairs[k - 1].reference] * pairs[k - 1].prev_from_curr;
  LocalAlignmentOptions o;
  o.max_power = 1;  // spans 1 and 2
  const std::vector<RelativePoseConstraint> c = LocalConstraints(pairs, o);
  const double strong = PairConfidence(pairs[0], o), weak = 0.3;
  std::map<std::pair<int, int>, double> expected = {
      {{0, 1}, strong}, {{1, 2}, weak},   {{2, 3}, weak}, {{3, 4}, strong}, {{4, 5}, strong},
      {{0, 2}, weak},   {{1, 3}, strong}, {{2, 4}, weak}, {{3, 5}, strong}, {{0, 3}, strong}};
  ASSERT_EQ(c.size(), expected.size());
  for (const RelativePoseConstraint& r : c) {
    const auto it = expected.find({r.frame_a, r.frame_b});
    ASSERT_NE(it, expected.end()) << r.frame_a << " " << r.frame_b;
    EXPECT_NEAR(r.weight, it->second, 1e-9) << r.frame_a << " " << r.frame_b;
    const Rigid3d a_from_b = world[r.frame_a].inverse() * world[r.frame_b];
    EXPECT_LT((r.translation_a_from_b - a_from_b.translation()).norm(), 1e-12);
    EXPECT_LT(r.rotation_a_from_b.angularDistance(Eigen::Quaterniond(a_from_b.linear())), 1e-12);
  }
}

// A constraint is measured when every pair on its path in the tree of references measured
// every direction: SIFT, tracking and ICP with nothing left to the prediction are; ICP that
// left directions to it (degenerate > 0) and the motion prior itself are not.
TEST(LocalConstraints, MeasuredWhereEveryPairOnThePathMeasuredEveryDirection) {
  std::vector<PairAlignment> pairs;
  for (int k = 1; k <= 6; ++k) pairs.push_back(Pair(k, AlignmentMethod::kTrack, 100, 1.0, 0.1 * k));
  pairs[1] = Pair(2, AlignmentMethod::kIcp, 0, 1.0, 0.2);  // frames 1 -> 2, degenerate 3
  pairs[3] = Pair(4, AlignmentMethod::kIcp, 0, 1.0, 0.4);  // frames 3 -> 4, every direction measured
  pairs[3].degenerate = 0;
  pairs[5] = Pair(6, AlignmentMethod::kMotionPrior, 0, 0.0, 0.6);  // frames 5 -> 6
  LocalAlignmentOptions o;
  o.max_power = 1;
  std::map<std::pair<int, int>, bool> expected = {{{0, 1}, true}, {{1, 2}, false}, {{2, 3}, true},  {{3, 4}, true},
                                                  {{4, 5}, true}, {{5, 6}, false}, {{0, 2}, false}, {{1, 3}, false},
                                                  {{2, 4}, true}, {{3, 5}, true},  {{4, 6}, false}};
  pairs[2].inliers = 30;  // frames 2 -> 3, tracked with few keypoints
  const std::vector<RelativePoseConstraint> c = LocalConstraints(pairs, o);
  ASSERT_EQ(c.size(), expected.size());
  for (const RelativePoseConstraint& r : c) {
    const auto it = expected.find({r.frame_a, r.frame_b});
    ASSERT_NE(it, expected.end()) << r.frame_a << " " << r.frame_b;
    EXPECT_EQ(r.measured, it->second) << r.frame_a << " " << r.frame_b;
    // The weakest SIFT or tracked pair on the path; ICP and the prior count as none.
    const bool through_3 = r.frame_a < 3 && r.frame_b >= 3;
    const bool tracked = !(r.frame_a == 1 && r.frame_b == 2) && !(r.frame_a == 3 && r.frame_b == 4) &&
                         !(r.frame_a == 5 && r.frame_b == 6);
    EXPECT_EQ(r.weakest_inliers, through_3 ? 30 : tracked ? 100 : kNoInlierCount) << r.frame_a << " " << r.frame_b;
  }
}

TEST(LocalConstraints, DistanceWeightingOfTheAuthors) {
  std::vector<PairAlignment> pairs = {Pair(1, AlignmentMethod::kSift, 100, 1.0, 0.25)};
  LocalAlignmentOptions o;
  o.distance_sigma = 0.25;
  const std::vector<RelativePoseConstraint> c = LocalConstraints(pairs, o);
  ASSERT_EQ(c.size(), 1u);
  EXPECT_NEAR(c[0].weight, PairConfidence(pairs[0], o) * std::exp(-0.5), 1e-9);
}

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

// exp(w, v) t: turned by w (a rotation vector), then moved by v.
Rigid3d Perturbed(const Vector6d& d, const Rigid3d& t) {
  Rigid3d e = Rigid3d::Identity();
  if (d.head<3>().norm() > 0)
    e.linear() = Eigen::AngleAxisd(d.head<3>().norm(), d.head<3>().normalized()).toRotationMatrix();
  e.translation() = d.tail<3>();
  return e * t;
}

// RelativePoseCost's residual for the estimate a_from_b (frame a at the origin).
Vector6d Residual(const Rigid3d& measured, const Rigid3d& estimate, const Matrix6d& m) {
  std::unique_ptr<ceres::CostFunction> cost(
      RelativePoseCost::Create(Eigen::Quaterniond(measured.linear()), measured.translation(), m));
  Pose a, b = Pose::FromRigid(estimate);
  const double* blocks[] = {a.rotation_data(), a.translation_data(), b.rotation_data(), b.translation_data()};
  Vector6d r;
  EXPECT_TRUE(cost->Evaluate(blocks, r.data(), nullptr));
  return r;
}

// LocalErrorCovariance is J Sigma J^T with J the error's derivative: for a rank-one Sigma =
// d d^T, the error of exp(d) a_from_b itself (to first order).
TEST(LocalErrorCovariance, MapsALeftPerturbationToRelativePoseCostsError) {
  Rigid3d a_from_b = Rigid3d::Identity();
  a_from_b.linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, -2, 0.5).normalized()).toRotationMatrix();
  a_from_b.translation() = Eigen::Vector3d(0.4, -0.3, 1.2);
  Vector6d d;
  d << 1e-5, -2e-5, 3e-5, 2e-5, 1e-5, -4e-5;
  const Vector6d e = Residual(a_from_b, Perturbed(d, a_from_b), Matrix6d::Identity());
  const Matrix6d predicted = LocalErrorCovariance(a_from_b, d * d.transpose());
  EXPECT_LT((predicted - e * e.transpose()).norm(), 1e-4 * e.squaredNorm());  // second order: ~1e-5
}

// Whitened E_L is calibrated end to end: tracked pairs whose measurements err by draws from
// their fits' covariances (the path through a shared keyframe, a direct pair, a keyframe's
// own pair) give constraints whose residuals at the true poses are chi-square with six
// degrees of freedom, |r|^2 averaging 6, once reference_sigma 1 and no floor leave M the
// information's own square root.
TEST(LocalConstraints, WhitenedResidualsAreUnitNormalAtTheTruth) {
  // Frames 1 and 2 refer to keyframe 0, frame 3 to keyframe 2.
  std::vector<Rigid3d> truth(4, Rigid3d::Identity());  // world_from_camera
  for (int k = 1; k < 4; ++k) {
    truth[k].linear() = Eigen::AngleAxisd(0.1 * k, Eigen::Vector3d(0.2, 1, 0.1 * k).normalized()).toRotationMatrix();
    truth[k].translation() = Eigen::Vector3d(0.3 * k, -0.2 * k, 0.1 * k * k);
  }
  const int reference[] = {-1, 0, 0, 2};
  std::mt19937_64 rng(5);
  std::normal_distribution<double> unit(0.0, 1.0);
  std::vector<Matrix6d> root(4);  // each pair's covariance is root root^T
  for (int k = 1; k < 4; ++k) {
    Matrix6d r = Matrix6d::Zero();
    for (int i = 0; i < 6; ++i) {
      // Turns uncertain by mrad and moves by a fifth of a mm, so that a turn's lever over
      // the path's metres decides the translation's error (and the adjoint is tested).
      for (int j = 0; j <= i; ++j) r(i, j) = (i == j ? (i < 3 ? 1e-3 : 2e-4) * k : 1e-4 * unit(rng));
    }
    root[k] = r;
  }
  LocalAlignmentOptions o;
  o.reference_sigma = 1;
  o.floor_rotation_deg = 0;
  o.floor_translation = 0;
  const int draws = 2000;
  std::map<std::pair<int, int>, double> chi2;
  for (int draw = 0; draw < draws; ++draw) {
    std::vector<PairAlignment> pairs;
    for (int k = 1; k < 4; ++k) {
      PairAlignment p = Pair(k, AlignmentMethod::kTrack, 100, 1.0, 0);
      p.reference = reference[k];
      p.keyframe = k == 2;
      Vector6d noise;
      for (int i = 0; i < 6; ++i) noise(i) = unit(rng);
      p.prev_from_curr = Perturbed(root[k] * noise, truth[reference[k]].inverse() * truth[k]);
      p.information = (root[k] * root[k].transpose()).inverse();
      pairs.push_back(p);
    }
    for (const RelativePoseConstraint& c : LocalConstraints(pairs, o)) {
      ASSERT_TRUE(c.whitened());
      Rigid3d measured = Rigid3d::Identity();
      measured.linear() = c.rotation_a_from_b.toRotationMatrix();
      measured.translation() = c.translation_a_from_b;
      const Rigid3d estimate = truth[c.frame_a].inverse() * truth[c.frame_b];
      chi2[{c.frame_a, c.frame_b}] += Residual(measured, estimate, c.sqrt_information).squaredNorm() / draws;
    }
  }
  // (0, 1) and (2, 3) direct, (1, 2) through keyframe 0, (0, 2) the keyframe's own pair.
  ASSERT_EQ(chi2.size(), 4u);
  for (const auto& [frames, mean] : chi2) EXPECT_NEAR(mean, 6.0, 0.4) << frames.first << " " << frames.second;
}

// Without the information (ICP, old caches) or with it turned off, a constraint keeps one
// weight; a floor on a pair's covariance caps what E_L trusts a very precise fit with.
TEST(LocalConstraints, WhitenedOnlyWhereEveryPairOnThePathHasItsInformation) {
  std::vector<PairAlignment> pairs;
  for (int k = 1; k <= 3; ++k) {
    // Frame 1 turns about the optical axis and does not move, so E_L's error is the
    // perturbation itself.
    pairs.push_back(Pair(k, AlignmentMethod::kTrack, 100, 1.0, 0.1 * (k - 1)));
    pairs.back().information = Matrix6d::Identity() * 1e8;  // 0.1 mm and 0.1 mrad
  }
  pairs[2] = Pair(3, AlignmentMethod::kIcp, 0, 1.0, 0.3);
  LocalAlignmentOptions o;
  o.reference_sigma = 1;
  o.floor_rotation_deg = 0;
  o.floor_translation = 0;
  std::vector<RelativePoseConstraint> c = LocalConstraints(pairs, o);
  ASSERT_EQ(c.size(), 3u);
  EXPECT_TRUE(c[0].whitened());
  EXPECT_TRUE(c[1].whitened());
  EXPECT_FALSE(c[2].whitened());
  EXPECT_NEAR(c[2].weight, PairConfidence(pairs[2], o), 1e-12);
  // Its translation rows: 1 / 0.1 mm at a reference sigma of 1 m.
  EXPECT_NEAR(c[0].sqrt_information(0, 0), 1e4, 1e-3);
  o.floor_translation = 0.001;  // adds (1 mm)^2: sigma sqrt(0.1^2 + 1) mm
  c = LocalConstraints(pairs, o);
  EXPECT_NEAR(c[0].sqrt_information.col(0).norm(), 1.0 / std::sqrt(1e-8 + 1e-6), 1e-3);
  o.information = false;
  c = LocalConstraints(pairs, o);
  for (const RelativePoseConstraint& r : c) EXPECT_FALSE(r.whitened());
}

// An ICP fallback that carries its fusion's information is whitened like a tracked pair
// (`icp_information`, on by default): a plain wall's fallback measured its distance to 0.1 mm
// and left its slide to the prior (5 mm), and the whitened link weighs them so. Off, it keeps
// the scalar ICP weight.
TEST(LocalConstraints, IcpFallbacksWhitenedByTheirFusionsInformation) {
  std::vector<PairAlignment> pairs = {Pair(1, AlignmentMethod::kIcp, 0, 1.0, 0.0)};
  pairs[0].prev_from_curr = Rigid3d::Identity();
  Eigen::Matrix<double, 6, 1> variance;
  variance << 1e-8, 1e-8, 1e-4, 2.5e-5, 2.5e-5, 1e-8;  // (w, v): tilts and distance measured
  pairs[0].information = variance.cwiseInverse().asDiagonal();
  LocalAlignmentOptions o;
  o.reference_sigma = 1;
  o.floor_rotation_deg = 0;
  o.floor_translation = 0;
  std::vector<RelativePoseConstraint> c = LocalConstraints(pairs, o);
  ASSERT_EQ(c.size(), 1u);
  ASSERT_TRUE(c[0].whitened());
  EXPECT_NEAR(c[0].weight, FitnessRamp(pairs[0], o), 1e-12);
  // Identity pose: the error is the perturbation (translation first, then 2 vec(q), the
  // rotation vector to first order), so each row is 1 / sigma of its direction.
  EXPECT_NEAR(c[0].sqrt_information(3, 3), 1 / 1e-4, 1e-6);
  EXPECT_NEAR(c[0].sqrt_information(5, 5), 1 / 1e-2, 1e-9);  // the roll left to the prior
  EXPECT_NEAR(c[0].sqrt_information(0, 0), 1 / 5e-3, 1e-9);
  EXPECT_NEAR(c[0].sqrt_information(2, 2), 1 / 1e-4, 1e-6);
  o.icp_information = false;
  c = LocalConstraints(pairs, o);
  EXPECT_FALSE(c[0].whitened());
  EXPECT_NEAR(c[0].weight, o.icp_weight, 1e-12);
}

}  // namespace
}  // namespace f2c
