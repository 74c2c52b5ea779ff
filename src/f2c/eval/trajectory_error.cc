#include "f2c/eval/trajectory_error.h"

#include <fmt/format.h>

#include <Eigen/SVD>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "f2c/geometry/rigid.h"
#include "f2c/io/readers.h"
#include "f2c/util/error.h"

namespace f2c {

void EvaluationOptions::Check() const { CheckFields(*this); }

ErrorStatistics ComputeStatistics(std::vector<double> e) {
  ErrorStatistics s;
  s.count = static_cast<int>(e.size());
  if (e.empty()) return s;
  const double n = static_cast<double>(e.size());
  double sum = 0, sum2 = 0;
  for (double v : e) {
    sum += v;
    sum2 += v * v;
  }
  s.mean = sum / n;
  s.rmse = std::sqrt(sum2 / n);
  s.std = std::sqrt(std::max(0.0, sum2 / n - s.mean * s.mean));  // numpy.std: population
  std::sort(e.begin(), e.end());
  s.min = e.front();
  s.max = e.back();
  const size_t m = e.size() / 2;
  s.median = e.size() % 2 ? e[m] : 0.5 * (e[m - 1] + e[m]);
  return s;
}

AteResult ComputeAte(const Trajectory& estimate, const Trajectory& ground_truth, const EvaluationOptions& options) {
  const auto matches =
      internal::AssociateTimestamps(estimate.timestamps, ground_truth.timestamps, options.max_time_difference);
  if (estimate.size() < 3) {
    ThrowInputError("estimate", fmt::format("{} poses: a rigid alignment needs at least 3", estimate.size()));
  }
  if (matches.size() < 3) {
    ThrowInputError("estimate", fmt::format("only {} of {} poses have a ground-truth pose within {} s; "
                                            "time stamps from another sequence?",
                                            matches.size(), estimate.size(), options.max_time_difference));
  }
  Eigen::Matrix3Xd est(3, matches.size()), gt(3, matches.size());
  for (size_t i = 0; i < matches.size(); ++i) {
    est.col(i) = estimate.world_from_camera[matches[i].first].translation();
    gt.col(i) = ground_truth.world_from_camera[matches[i].second].translation();
  }
  AteResult result;
  result.estimated_poses = static_cast<int>(estimate.size());
  result.gt_from_estimate.matrix() = Eigen::umeyama(est, gt, false);
  for (size_t i = 0; i < matches.size(); ++i) {
    result.errors.push_back((result.gt_from_estimate * Eigen::Vector3d(est.col(i)) - gt.col(i)).norm());
  }
  result.translation = ComputeStatistics(result.errors);
  return result;
}

namespace {

size_t ClosestIndex(const std::vector<double>& sorted, double value) {
  const auto it = std::lower_bound(sorted.begin(), sorted.end(), value);
  size_t j = std::min<size_t>(it - sorted.begin(), sorted.size() - 1);
  if (j > 0 && std::abs(sorted[j - 1] - value) <= std::abs(sorted[j] - value)) --j;
  return j;
}

}  // namespace

RpeResult ComputeRpe(const Trajectory& estimate, const Trajectory& ground_truth, double delta, bool in_seconds) {
  RpeResult result;
  const auto& te = estimate.timestamps;
  const auto& tg = ground_truth.timestamps;
  if (te.size() < 2 || tg.size() < 2) return result;
  // A pose counts only if the ground truth has a sample within 2 median intervals (as TUM).
  std::vector<double> intervals;
  for (size_t i = 1; i < tg.size(); ++i) intervals.push_back(tg[i] - tg[i - 1]);
  std::nth_element(intervals.begin(), intervals.begin() + intervals.size() / 2, intervals.end());
  const double max_gap = 2 * intervals[intervals.size() / 2];
  std::vector<double> trans, rot;
  for (size_t i = 0; i < te.size(); ++i) {
    const size_t j = in_seconds ? ClosestIndex(te, te[i] + delta) : i + static_cast<size_t>(delta);
    // As evaluate_rpe.py: a pair whose end is (or is clamped to) the last pose is dropped.
    if (j >= te.size() - 1) continue;
    if (j <= i) continue;
    const size_t gi = ClosestIndex(tg, te[i]), gj = ClosestIndex(tg, te[j]);
    if (std::abs(tg[gi] - te[i]) > max_gap || std::abs(tg[gj] - te[j]) > max_gap) continue;
    const Rigid3d est_rel = estimate.world_from_camera[i].inverse() * estimate.world_from_camera[j];
    const Rigid3d gt_rel = ground_truth.world_from_camera[gi].inverse() * ground_truth.world_from_camera[gj];
    const Rigid3d error = gt_rel.inverse() * est_rel;
    trans.push_back(error.translation().norm());
    rot.push_back(RotationAngle(error.linear()) * 180.0 / M_PI);
  }
  result.translation = ComputeStatistics(trans);
  result.rotation = ComputeStatistics(rot);
  return result;
}

namespace {

// D_i = Q_i P_i^-1 (rotations) and the estimate's time stamp of every associated pose, in
// time order.
void RotationErrors(const Trajectory& estimate, const Trajectory& ground_truth, const EvaluationOptions& options,
                    std::vector<Eigen::Matrix3d>* d, std::vector<double>* t) {
  auto matches =
      internal::AssociateTimestamps(estimate.timestamps, ground_truth.timestamps, options.max_time_difference);
  std::stable_sort(matches.begin(), matches.end(), [&](const auto& x, const auto& y) {
    return estimate.timestamps[x.first] < estimate.timestamps[y.first];
  });
  for (const auto& [e, g] : matches) {
    d->push_back(ground_truth.world_from_camera[g].linear() * estimate.world_from_camera[e].linear().transpose());
    t->push_back(estimate.timestamps[e]);
  }
}

// The pairs' statistics over at most drift_max_poses evenly spaced poses.
RotationDrift DriftOverPairs(const std::vector<Eigen::Matrix3d>& all_d, const std::vector<double>& all_t,
                             const EvaluationOptions& options) {
  RotationDrift result;
  result.min_seconds = options.drift_min_seconds;
  const size_t total = all_d.size();
  const size_t m = std::min<size_t>(total, options.drift_max_poses);
  std::vector<Eigen::Matrix3d> d(m);
  std::vector<double> t(m);
  for (size_t k = 0; k < m; ++k) {
    const size_t i = m == total ? k : k * (total - 1) / (m - 1);
    d[k] = all_d[i];
    t[k] = all_t[i];
  }
  result.poses = static_cast<int>(m);
  std::vector<double> angles;
  for (size_t i = 0; i < m; ++i) {
    for (size_t j = i + 1; j < m; ++j) {
      if (std::abs(t[j] - t[i]) < options.drift_min_seconds) continue;
      angles.push_back(RotationAngle(d[i].transpose() * d[j]) * 180.0 / M_PI);
    }
  }
  result.threshold_deg = options.drift_threshold_deg;
  if (!angles.empty()) {
    std::sort(angles.begin(), angles.end());
    const double rank = 0.99 * static_cast<double>(angles.size() - 1);
    const size_t below = static_cast<size_t>(rank);
    const double above = angles[std::min(below + 1, angles.size() - 1)];
    result.p99 = angles[below] + (rank - static_cast<double>(below)) * (above - angles[below]);
    const auto first_over = std::upper_bound(angles.begin(), angles.end(), options.drift_threshold_deg);
    result.share_over = static_cast<double>(angles.end() - first_over) / static_cast<double>(angles.size());
  }
  result.rotation = ComputeStatistics(std::move(angles));
  return result;
}

// Each D_i replaced by the chordal mean of the D_j within drift_smoothing_seconds / 2, then
// the pairs as above.
RotationDrift SmoothedDrift(const std::vector<Eigen::Matrix3d>& d, const std::vector<double>& t,
                            const EvaluationOptions& options) {
  F2C_CHECK(options.drift_smoothing_seconds > 0, "a smoothing window");
  // Prefix sums of the D_j: each window's sum in O(1), its chordal mean the rotation
  // nearest to that sum (polar factor U V^T of its SVD, det +1).
  std::vector<Eigen::Matrix3d> prefix(d.size() + 1, Eigen::Matrix3d::Zero());
  for (size_t j = 0; j < d.size(); ++j) prefix[j + 1] = prefix[j] + d[j];
  const double half = options.drift_smoothing_seconds / 2;
  std::vector<Eigen::Matrix3d> mean(d.size());
  for (size_t i = 0; i < d.size(); ++i) {
    const size_t lo = std::lower_bound(t.begin(), t.end(), t[i] - half) - t.begin();
    const size_t hi = std::upper_bound(t.begin(), t.end(), t[i] + half) - t.begin();
    const Eigen::JacobiSVD<Eigen::Matrix3d> svd(prefix[hi] - prefix[lo], Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Matrix3d s = Eigen::Matrix3d::Identity();
    s(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1 : 1;
    mean[i] = svd.matrixU() * s * svd.matrixV().transpose();
  }
  RotationDrift result = DriftOverPairs(mean, t, options);
  result.smoothing_seconds = options.drift_smoothing_seconds;
  return result;
}

}  // namespace

RotationDrift ComputeRotationDrift(const Trajectory& estimate, const Trajectory& ground_truth,
                                   const EvaluationOptions& options) {
  std::vector<Eigen::Matrix3d> d;
  std::vector<double> t;
  RotationErrors(estimate, ground_truth, options, &d, &t);
  return DriftOverPairs(d, t, options);
}

RotationDrift ComputeSmoothedRotationDrift(const Trajectory& estimate, const Trajectory& ground_truth,
                                           const EvaluationOptions& options) {
  std::vector<Eigen::Matrix3d> d;
  std::vector<double> t;
  RotationErrors(estimate, ground_truth, options, &d, &t);
  return SmoothedDrift(d, t, options);
}

EvaluationResult Evaluate(const Trajectory& estimate, const Trajectory& ground_truth,
                          const EvaluationOptions& options) {
  options.Check();
  EvaluationResult result;
  std::vector<Eigen::Matrix3d> d;  // the rotation errors, shared by both drifts
  std::vector<double> t;
  RotationErrors(estimate, ground_truth, options, &d, &t);
  result.drift = DriftOverPairs(d, t, options);
  if (options.drift_smoothing_seconds > 0) result.drift_smoothed = SmoothedDrift(d, t, options);
  result.ate = ComputeAte(estimate, ground_truth, options);
  result.rpe_per_frame = ComputeRpe(estimate, ground_truth, options.rpe_delta_frames, false);
  result.rpe_per_second = ComputeRpe(estimate, ground_truth, options.rpe_delta_seconds, true);
  return result;
}

nlohmann::json ToJson(const ErrorStatistics& s) {
  if (s.count == 0) {  // nothing measured: null, never a 0 that reads as perfect
    return {{"rmse", nullptr}, {"mean", nullptr}, {"median", nullptr}, {"std", nullptr},
            {"min", nullptr},  {"max", nullptr},  {"count", 0}};
  }
  return {{"rmse", s.rmse}, {"mean", s.mean}, {"median", s.median}, {"std", s.std},
          {"min", s.min},   {"max", s.max},   {"count", s.count}};
}

nlohmann::json ToJson(const EvaluationResult& r) {
  nlohmann::json j = {
      {"ate_m", ToJson(r.ate.translation)},
      {"estimated_poses", r.ate.estimated_poses},
      {"rpe_per_frame",
       {{"translation_m", ToJson(r.rpe_per_frame.translation)}, {"rotation_deg", ToJson(r.rpe_per_frame.rotation)}}},
      {"rpe_per_second",
       {{"translation_m", ToJson(r.rpe_per_second.translation)}, {"rotation_deg", ToJson(r.rpe_per_second.rotation)}}},
      {"rotation_drift_deg", ToJson(r.drift.rotation)},
      {"rotation_drift_min_seconds", r.drift.min_seconds},
      {"rotation_drift_p99_deg", r.drift.p99},
      {"rotation_drift_threshold_deg", r.drift.threshold_deg},
      {"rotation_drift_share_over_threshold", r.drift.share_over}};
  if (r.drift_smoothed.smoothing_seconds > 0) {
    j["rotation_drift_smoothed_deg"] = ToJson(r.drift_smoothed.rotation);
    j["rotation_drift_smoothed_p99_deg"] = r.drift_smoothed.p99;
    j["rotation_drift_smoothing_seconds"] = r.drift_smoothed.smoothing_seconds;
  }
  return j;
}

}  // namespace f2c
