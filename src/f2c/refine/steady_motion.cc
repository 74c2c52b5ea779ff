#include "f2c/refine/steady_motion.h"

#include <algorithm>

#include "f2c/util/error.h"

namespace f2c {

void SteadyMotionOptions::Check() const { CheckFields(*this); }

std::vector<SteadyMotionConstraint> SteadyMotionConstraints(const std::vector<double>& timestamps,
                                                            const SteadyMotionOptions& options,
                                                            const std::vector<char>& unmeasured) {
  options.Check();
  F2C_CHECK(unmeasured.empty() || unmeasured.size() == timestamps.size(), "one unmeasured flag per frame");
  std::vector<SteadyMotionConstraint> out;
  const int n = static_cast<int>(timestamps.size());
  if (n < 3) return out;
  std::vector<double> intervals;
  for (int k = 1; k < n; ++k) {
    const double dt = timestamps[k] - timestamps[k - 1];
    if (dt > 0) intervals.push_back(dt);
  }
  if (intervals.empty()) return out;
  std::nth_element(intervals.begin(), intervals.begin() + intervals.size() / 2, intervals.end());
  const double median = intervals[intervals.size() / 2];
  auto usable = [&](double dt) { return dt > 0 && dt <= options.max_gap * median; };
  const double unit = 1.0 / options.reference_rate;
  for (int k = 1; k + 1 < n; ++k) {
    const double ab = timestamps[k] - timestamps[k - 1];
    const double bc = timestamps[k + 1] - timestamps[k];
    if (!usable(ab) || !usable(bc)) continue;
    const bool prior = !unmeasured.empty() && (unmeasured[k] || unmeasured[k + 1]);
    out.push_back({k - 1, k, k + 1, unit / ab, unit / bc, prior ? options.unmeasured_weight : 1.0, !prior});
  }
  return out;
}

}  // namespace f2c
