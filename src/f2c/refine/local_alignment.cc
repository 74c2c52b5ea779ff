#include "f2c/refine/local_alignment.h"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "f2c/util/error.h"

namespace f2c {

void LocalAlignmentOptions::Check() const {
  CheckFields(*this);
  if (!(fitness_high > fitness_low)) {
    ThrowInputError("fitness_high", fmt::format("must exceed fitness_low ({}), got {}", fitness_low, fitness_high));
  }
}

double PairConfidence(const PairAlignment& pair, const LocalAlignmentOptions& o) {
  double c = 1.0;
  switch (pair.method) {
    case AlignmentMethod::kSift:
    case AlignmentMethod::kTrack:
      c = 1.0 / (1.0 + std::exp(-o.inlier_slope * (pair.inliers - o.inlier_midpoint)));
      break;
    case AlignmentMethod::kIcp: c = pair.degenerate == 0 ? o.icp_measured_weight : o.icp_weight; break;
    case AlignmentMethod::kMotionPrior: return o.prior_weight;
  }
  const double ramp = std::clamp((pair.fitness - o.fitness_low) / (o.fitness_high - o.fitness_low), o.min_ramp, 1.0);
  return c * ramp;
}

std::vector<RelativePoseConstraint> LocalConstraints(const std::vector<PairAlignment>& pairs,
                                                     const LocalAlignmentOptions& options) {
  options.Check();
  const int n = static_cast<int>(pairs.size()) + 1;
  std::vector<double> confidence(n, 1.0);  // of frame k's pair; frame 0 has none
  std::vector<char> measured(n, 1);        // frame k's pair measured every direction
  std::vector<int> inliers(n, kNoInlierCount);    // frame k's RANSAC inliers (SIFT, tracking)
  std::vector<int> reference(n, -1);
  std::vector<Rigid3d> world_from(n, Rigid3d::Identity());  // T0, chained along the references
  for (int k = 1; k < n; ++k) {
    const PairAlignment& pair = pairs[k - 1];
    F2C_CHECK(pair.Reference() >= 0 && pair.Reference() < k, "a pair's reference precedes its frame");
    confidence[k] = PairConfidence(pair, options);
    if (pair.method == AlignmentMethod::kSift || pair.method == AlignmentMethod::kTrack) inliers[k] = pair.inliers;
    measured[k] = pair.method != AlignmentMethod::kMotionPrior && !(pair.method == AlignmentMethod::kIcp && pair.degenerate > 0);
    reference[k] = pair.Reference();
    world_from[k] = world_from[reference[k]] * pair.prev_from_curr;
  }
  // Over the path between a and b in the tree of references: the weakest alignment's
  // confidence, whether every pair measured every direction, and the fewest inliers.
  struct Path {
    double confidence = 1.0;
    bool measured = true;
    int weakest_inliers = kNoInlierCount;
  };
  auto path = [&](int a, int b) {
    Path p;
    while (a != b) {
      int& later = a > b ? a : b;
      p.confidence = std::min(p.confidence, confidence[later]);
      p.measured = p.measured && measured[later];
      p.weakest_inliers = std::min(p.weakest_inliers, inliers[later]);
      later = reference[later];
    }
    return p;
  };
  std::vector<RelativePoseConstraint> out;
  auto add = [&](int a, int b) {
    const Rigid3d a_from_b = world_from[a].inverse() * world_from[b];
    const Path p = path(a, b);
    double weight = p.confidence;
    if (options.distance_sigma > 0) {
      const double d = a_from_b.translation().norm();
      weight *= std::exp(-d * d / (2 * options.distance_sigma * options.distance_sigma));
    }
    if (weight <= 0) return;
    RelativePoseConstraint c;
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
  if (options.spans == "keyframes") {
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
    return out;
  }
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
  return out;
}

}  // namespace f2c
