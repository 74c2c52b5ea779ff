#include "f2c/refine/local_alignment.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <optional>

#include "f2c/optim/cost_functions.h"
#include "f2c/util/error.h"

namespace f2c {
namespace {

using Matrix6d = Eigen::Matrix<double, 6, 6>;

// Moves a left perturbation (w, v) in b's coordinates into a's, for a_from_b = (R, t):
// a_from_b exp(w, v) b_from_a = exp(R w, R v + t x R w).
Matrix6d Adjoint(const Rigid3d& a_from_b) {
  const Eigen::Matrix3d r = a_from_b.linear();
  Matrix6d ad = Matrix6d::Zero();
  ad.topLeftCorner<3, 3>() = r;
  ad.bottomLeftCorner<3, 3>() = Skew(a_from_b.translation()) * r;
  ad.bottomRightCorner<3, 3>() = r;
  return ad;
}

// The pair's covariance (its information's inverse plus the floor) where E_L whitens it.
std::optional<Matrix6d> PairCovariance(const PairAlignment& pair, const LocalAlignmentOptions& o) {
  const bool fitted = pair.method == AlignmentMethod::kSift || pair.method == AlignmentMethod::kTrack;
  const bool icp = pair.method == AlignmentMethod::kIcp && o.icp_information;
  if (!o.information || !(fitted || icp) || pair.information.isZero()) return std::nullopt;
  const Eigen::LDLT<Matrix6d> ldlt(pair.information);
  if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().array() > 0).all()) return std::nullopt;
  Matrix6d covariance = ldlt.solve(Matrix6d::Identity());
  const double floor_rotation = o.floor_rotation_deg * M_PI / 180;
  covariance.diagonal().head<3>().array() += floor_rotation * floor_rotation;
  covariance.diagonal().tail<3>().array() += o.floor_translation * o.floor_translation;
  if (!covariance.allFinite()) return std::nullopt;
  return covariance;
}

}  // namespace

Matrix6d LocalErrorCovariance(const Rigid3d& a_from_b, const Matrix6d& left_covariance_in_a) {
  // RelativePoseCost's error of the estimate exp(w, v) a_from_b: the translation moves by
  // w x t + v (a's coordinates), the rotation by R^T w (b's coordinates).
  Matrix6d jacobian = Matrix6d::Zero();
  jacobian.topLeftCorner<3, 3>() = -Skew(a_from_b.translation());
  jacobian.topRightCorner<3, 3>() = Eigen::Matrix3d::Identity();
  jacobian.bottomLeftCorner<3, 3>() = a_from_b.linear().transpose();
  return jacobian * left_covariance_in_a * jacobian.transpose();
}

void LocalAlignmentOptions::Check() const {
  CheckFields(*this);
  if (!(fitness_high > fitness_low)) {
    ThrowInputError("fitness_high", fmt::format("must exceed fitness_low ({}), got {}", fitness_low, fitness_high));
  }
}

double FitnessRamp(const PairAlignment& pair, const LocalAlignmentOptions& o) {
  return std::clamp((pair.fitness - o.fitness_low) / (o.fitness_high - o.fitness_low), o.min_ramp, 1.0);
}

bool Whitens(const PairAlignment& pair, const LocalAlignmentOptions& o) { return PairCovariance(pair, o).has_value(); }

double PairConfidence(const PairAlignment& pair, const LocalAlignmentOptions& o) {
  // The fit's information replaces the inlier logistic; a poor depth overlap still lowers
  // the trust.
  if (Whitens(pair, o)) return FitnessRamp(pair, o);
  double c = 1.0;
  switch (pair.method) {
    case AlignmentMethod::kSift:
    case AlignmentMethod::kTrack:
      c = 1.0 / (1.0 + std::exp(-o.inlier_slope * (pair.inliers - o.inlier_midpoint)));
      break;
    case AlignmentMethod::kIcp:
      c = pair.degenerate == 0 ? o.icp_measured_weight : o.icp_weight;
      break;
    case AlignmentMethod::kMotionPrior:
      return o.prior_weight;
  }
  return c * FitnessRamp(pair, o);
}

std::vector<RelativePoseConstraint> LocalConstraints(const std::vector<PairAlignment>& pairs,
                                                     const LocalAlignmentOptions& options) {
  options.Check();
  const int n = static_cast<int>(pairs.size()) + 1;
  std::vector<double> confidence(n, 1.0);       // of frame k's pair; frame 0 has none
  std::vector<char> measured(n, 1);             // frame k's pair measured every direction
  std::vector<int> inliers(n, kNoInlierCount);  // frame k's RANSAC inliers (SIFT, tracking)
  std::vector<int> reference(n, -1);
  std::vector<Rigid3d> world_from(n, Rigid3d::Identity());  // T0, chained along the references
  // Frame k's pair's covariance (a left perturbation of reference_from_frame in the
  // reference's coordinates), where its fit measured every direction.
  std::vector<std::optional<Matrix6d>> covariance(n);
  for (int k = 1; k < n; ++k) {
    const PairAlignment& pair = pairs[k - 1];
    F2C_CHECK(pair.Reference() >= 0 && pair.Reference() < k, "a pair's reference precedes its frame");
    confidence[k] = PairConfidence(pair, options);
    if (pair.method == AlignmentMethod::kSift || pair.method == AlignmentMethod::kTrack) inliers[k] = pair.inliers;
    measured[k] = !pair.LeftToPrior();
    reference[k] = pair.Reference();
    world_from[k] = world_from[reference[k]] * pair.prev_from_curr;
    covariance[k] = PairCovariance(pair, options);
  }
  // Over the path between a and b in the tree of references: the weakest alignment's
  // confidence, whether every pair measured every direction, and the fewest inliers.
  // With every pair's covariance known, also their sum, each moved into a's coordinates:
  // a_from_b = (world_from_a)^-1 world_from_b, and a perturbation of pair k (reference r)
  // perturbs it on the left by Adjoint(a_from_r) of itself.
  struct Path {
    double confidence = 1.0;
    bool measured = true;
    int weakest_inliers = kNoInlierCount;
    bool has_covariance = true;
    Matrix6d covariance = Matrix6d::Zero();
  };
  auto path = [&](int a, int b) {
    Path p;
    const Rigid3d a_from_world = world_from[a].inverse();
    while (a != b) {
      int& later = a > b ? a : b;
      p.confidence = std::min(p.confidence, confidence[later]);
      p.measured = p.measured && measured[later];
      p.weakest_inliers = std::min(p.weakest_inliers, inliers[later]);
      p.has_covariance = p.has_covariance && covariance[later].has_value();
      if (p.has_covariance) {
        const Matrix6d ad = Adjoint(a_from_world * world_from[reference[later]]);
        p.covariance += ad * *covariance[later] * ad.transpose();
      }
      later = reference[later];
    }
    return p;
  };
  std::vector<RelativePoseConstraint> out;
  std::vector<double> translation_sigmas;  // of the whitened constraints
  auto add = [&](int a, int b) {
    const Rigid3d a_from_b = world_from[a].inverse() * world_from[b];
    const Path p = path(a, b);
    RelativePoseConstraint c;
    double weight = p.confidence;
    if (p.has_covariance) {
      const Matrix6d error_covariance = LocalErrorCovariance(a_from_b, p.covariance);
      const Eigen::LLT<Matrix6d> llt(error_covariance.inverse());
      if (llt.info() == Eigen::Success && llt.matrixU().toDenseMatrix().allFinite()) {
        c.sqrt_information = llt.matrixU().toDenseMatrix();
        translation_sigmas.push_back(std::sqrt(error_covariance.topLeftCorner<3, 3>().trace() / 3));
      }
    }
    if (options.distance_sigma > 0) {
      const double d = a_from_b.translation().norm();
      weight *= std::exp(-d * d / (2 * options.distance_sigma * options.distance_sigma));
    }
    if (weight <= 0) return;
    c.frame_a = a;
    c.frame_b = b;
    c.rotation_a_from_b = Eigen::Quaterniond(a_from_b.linear()).normalized();
    c.translation_a_from_b = a_from_b.translation();
    c.weight = weight;
    c.measured = p.measured;
    c.weakest_inliers = p.weakest_inliers;
    out.push_back(c);
  };
  const int max_span = 1 << options.max_power;
  if (options.spans == LocalSpans::kKeyframes) {
    std::vector<int> keyframes = {0};
    for (int k = 1; k < n; ++k) {
      add(reference[k], k);
      if (pairs[k - 1].keyframe) keyframes.push_back(k);
    }
    const int m = static_cast<int>(keyframes.size());
    for (int i = 0; i < m; ++i) {
      for (int p = 1; p <= options.max_power && i + (1 << p) < m; ++p) add(keyframes[i], keyframes[i + (1 << p)]);
    }
    if (m == 1 && n > 1) {  // no keyframe odometry: the chain's spans
      for (int j = 0; j < n; ++j) {
        for (int p = 1; p <= options.max_power && j + (1 << p) < n; ++p) add(j, j + (1 << p));
      }
    }
  } else {
    for (int j = 0; j < n; ++j) {
      // Each frame's own alignment (to its keyframe), unless a span below holds it already.
      const int span = j - reference[j];
      if (j > 0 && (span > max_span || (span & (span - 1)) != 0)) add(reference[j], j);
      for (int p = 0; p <= options.max_power; ++p) {
        const int b = j + (1 << p);
        if (b >= n) break;
        add(j, b);
      }
    }
  }
  // Whitened constraints in the units of the scalar ones: a constraint whose translation is
  // uncertain by the reference sigma weighs as a scalar constraint of the same weight.
  if (!translation_sigmas.empty()) {
    double sigma = options.reference_sigma;
    if (sigma <= 0) {
      auto middle = translation_sigmas.begin() + translation_sigmas.size() / 2;
      std::nth_element(translation_sigmas.begin(), middle, translation_sigmas.end());
      sigma = *middle;
    }
    for (RelativePoseConstraint& c : out) c.sqrt_information *= sigma;
  }
  return out;
}

}  // namespace f2c
