#include "f2c/refine/local_alignment.h"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "f2c/util/error.h"

namespace f2c {

void LocalAlignmentOptions::Check() const {
  if (max_power < 0 || max_power > 20) ThrowInputError("--local-max-power", "must be in 0..20");
  if (!(icp_weight >= 0 && icp_weight <= 1)) ThrowInputError("--local-icp-weight", "must be in [0, 1]");
  if (!(prior_weight >= 0 && prior_weight <= 1)) ThrowInputError("--local-prior-weight", "must be in [0, 1]");
  if (!(inlier_slope >= 0)) ThrowInputError("local.inlier_slope", "must be >= 0");
  if (!(fitness_high > fitness_low)) ThrowInputError("local.fitness_high", "must exceed fitness_low");
  if (!(min_ramp >= 0 && min_ramp <= 1)) ThrowInputError("local.min_ramp", "must be in [0, 1]");
  if (!(distance_sigma >= 0)) ThrowInputError("--local-distance-sigma", "must be >= 0");
}

double PairConfidence(const PairAlignment& pair, const LocalAlignmentOptions& o) {
  double c = 1.0;
  switch (pair.method) {
    case AlignmentMethod::kSift:
      c = 1.0 / (1.0 + std::exp(-o.inlier_slope * (pair.inliers - o.inlier_midpoint)));
      break;
    case AlignmentMethod::kIcp: c = o.icp_weight; break;
    case AlignmentMethod::kMotionPrior: return o.prior_weight;
  }
  const double ramp = std::clamp((pair.fitness - o.fitness_low) / (o.fitness_high - o.fitness_low), o.min_ramp, 1.0);
  return c * ramp;
}

std::vector<RelativePoseConstraint> LocalConstraints(const std::vector<PairAlignment>& pairs,
                                                     const LocalAlignmentOptions& options) {
  options.Check();
  const int n = static_cast<int>(pairs.size()) + 1;
  std::vector<double> confidence(pairs.size());
  for (size_t k = 0; k < pairs.size(); ++k) confidence[k] = PairConfidence(pairs[k], options);
  std::vector<RelativePoseConstraint> out;
  for (int j = 0; j < n; ++j) {
    for (int p = 0; p <= options.max_power; ++p) {
      const int b = j + (1 << p);
      if (b >= n) break;
      // a_from_b = L[j+1] L[j+2] ... L[b], the weakest link's confidence.
      Rigid3d a_from_b = Rigid3d::Identity();
      double weight = 1.0;
      for (int k = j + 1; k <= b; ++k) {
        a_from_b = a_from_b * pairs[k - 1].prev_from_curr;
        weight = std::min(weight, confidence[k - 1]);
      }
      if (options.distance_sigma > 0) {
        const double d = a_from_b.translation().norm();
        weight *= std::exp(-d * d / (2 * options.distance_sigma * options.distance_sigma));
      }
      if (weight <= 0) continue;
      RelativePoseConstraint c;
      c.frame_a = j;
      c.frame_b = b;
      c.rotation_a_from_b = Eigen::Quaterniond(a_from_b.linear()).normalized();
      c.translation_a_from_b = a_from_b.translation();
      c.weight = weight;
      out.push_back(c);
    }
  }
  return out;
}

nlohmann::json ToJson(const LocalAlignmentOptions& o) {
  return {{"max_power", o.max_power},         {"icp_weight", o.icp_weight},
          {"prior_weight", o.prior_weight},   {"inlier_midpoint", o.inlier_midpoint},
          {"inlier_slope", o.inlier_slope},   {"fitness_low", o.fitness_low},
          {"fitness_high", o.fitness_high},   {"min_ramp", o.min_ramp},
          {"distance_sigma", o.distance_sigma}};
}

}  // namespace f2c
