#include "f2c/refine/sift_loops.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "f2c/refine/pairs.h"
#include "f2c/util/error.h"
#include "f2c/util/timer.h"

namespace f2c {

void SiftLoopOptions::Check() const { CheckFields(*this); }

SiftLoopMatcher::SiftLoopMatcher(std::vector<Keyframe> keyframes, std::vector<double> confidence,
                                 const SiftLoopOptions& options)
    : keyframes_(std::move(keyframes)), options_(options) {
  options.Check();
  weak_prefix_.assign(confidence.size() + 2, 0);
  for (size_t k = 1; k <= confidence.size(); ++k) {
    weak_prefix_[k + 1] = weak_prefix_[k] + (confidence[k - 1] < options.weak_confidence);
  }
}

bool SiftLoopMatcher::WeakBetween(int a, int b) const {
  // Pairs a+1 .. b (pair k joins frames k-1 and k).
  const int hi = std::min<int>(b, static_cast<int>(weak_prefix_.size()) - 2);
  return hi > a && weak_prefix_[hi + 1] - weak_prefix_[a + 1] > 0;
}

bool SiftLoopMatcher::TryPair(int i, int j, const FeatureIndex& index, const CameraIntrinsics& intrinsics,
                              std::vector<PointMatch>* out, LoopEdge* edge) const {
  const Keyframe& ka = keyframes_[i];
  const Keyframe& kb = keyframes_[j];
  if (ka.points.size() < 3 || kb.points.size() < 3) return false;
  SiftFeatures a, b;  // the matcher's view of the keyframes
  // Keyframes keep bytes (a quarter of the memory); the matcher wants floats.
  ka.descriptors.convertTo(a.descriptors, CV_32F);
  kb.descriptors.convertTo(b.descriptors, CV_32F);
  a.points_in_camera.resize(ka.points.size());
  b.points_in_camera.resize(kb.points.size());
  const std::vector<SiftMatch> m = MatchSiftRatio(b, a, options_.ratio, options_.ratio, 0);
  if (static_cast<int>(m.size()) < options_.min_inliers) return false;
  std::vector<Eigen::Vector3d> pb, pa;
  for (const SiftMatch& x : m) {
    pb.push_back(kb.points[x.query].cast<double>());
    pa.push_back(ka.points[x.train].cast<double>());
  }
  const uint64_t seed = options_.seed ^ (static_cast<uint64_t>(ka.frame) << 32) ^ static_cast<uint64_t>(kb.frame);
  const RansacResult r = EstimateRigidRansac(pb, pa, options_.ransac, seed);
  if (static_cast<int>(r.inliers.size()) < options_.min_inliers) return false;
  // Depth check: b's planes that camera a sees must meet a's planes.
  const Eigen::Isometry3f a_from_b = r.b_from_a.cast<float>();
  const FeatureCloud& planes_a = index.frames[ka.frame]->family(FeatureFamily::kPlane);
  const FeatureCloud& planes_b = index.frames[kb.frame]->family(FeatureFamily::kPlane);
  const float radius2 = static_cast<float>(options_.check_radius * options_.check_radius);
  const float min_cos = static_cast<float>(std::cos(options_.check_angle_deg * M_PI / 180));
  int seen = 0, agree = 0;
  for (int f = 0; f < planes_b.size(); ++f) {
    const Eigen::Vector3f q = a_from_b * planes_b.point(f);
    if (q.z() <= 0.05f) continue;
    const double u = intrinsics.fx * q.x() / q.z() + intrinsics.cx;
    const double v = intrinsics.fy * q.y() / q.z() + intrinsics.cy;
    if (u < 0 || v < 0 || u > intrinsics.width - 1 || v > intrinsics.height - 1) continue;
    ++seen;
    uint32_t nearest;
    float d2;
    if (planes_a.Nearest(q, 1, &nearest, &d2, radius2) == 1 &&
        std::abs(planes_a.direction(nearest).dot(q - planes_a.point(nearest))) <= options_.check_distance &&
        planes_a.direction(nearest).dot(a_from_b.linear() * planes_b.direction(f)) >= min_cos) {
      ++agree;
    }
  }
  if (seen == 0 || agree < options_.min_fitness * seen) return false;
  edge->frame_a = ka.frame;
  edge->frame_b = kb.frame;
  edge->a_from_b = r.b_from_a;  // RANSAC mapped b's points onto a's
  edge->confidence = options_.loop_confidence;
  const int n = static_cast<int>(r.inliers.size());
  const int take = std::min(n, options_.max_points_per_pair);
  for (int t = 0; t < take; ++t) {
    const int k = r.inliers[static_cast<int64_t>(t) * n / take];
    PointMatch pm;
    pm.frame_a = ka.frame;
    pm.frame_b = kb.frame;
    pm.point_a = pa[k].cast<float>();
    pm.point_b = pb[k].cast<float>();
    out->push_back(pm);
  }
  return true;
}

SiftLoopStats SiftLoopMatcher::Update(const WindowSchedule& schedule, int iteration, const PoseVector& poses,
                                      const FeatureIndex& index, const CameraIntrinsics& intrinsics) {
  Timer timer;
  SiftLoopStats stats;
  const int m = static_cast<int>(keyframes_.size());
  if (!options_.enabled || m < 2) {
    stats.pairs = pairs_;
    stats.points = static_cast<int>(matches_.size());
    return stats;
  }
  std::vector<Eigen::Isometry3f> pose(m);
  for (int i = 0; i < m; ++i) pose[i] = poses[keyframes_[i].frame].ToRigid().cast<float>();
  const float min_axis_cos = static_cast<float>(std::cos(options_.max_view_angle_deg * M_PI / 180));
  const float max_d2 = static_cast<float>(options_.max_camera_distance * options_.max_camera_distance);
  // Candidates per keyframe i, among keyframes j > i that first share a window now:
  // bridges over weak odometry (no pose test: the poses are what is in doubt), shortest first,
  // and loops (farther apart than E_L reaches) that the current poses make plausible, best
  // overlap first.
  std::vector<std::vector<int>> candidates(m);
  tbb::parallel_for(0, m, [&](int i) {
    const int a = keyframes_[i].frame;
    const int begin = iteration == 0 ? a + 1 : schedule.ShareEnd(iteration - 1, a);
    const int end = schedule.ShareEnd(iteration, a);
    std::vector<std::pair<float, int>> bridges, loops;
    for (int j = i + 1; j < m && keyframes_[j].frame < end; ++j) {
      const int b = keyframes_[j].frame;
      if (b < begin) continue;
      if (b - a <= options_.max_bridge_gap && WeakBetween(a, b)) {
        bridges.push_back({static_cast<float>(b - a), j});
        continue;
      }
      if (b - a < options_.loop_gap) continue;
      if ((pose[i].translation() - pose[j].translation()).squaredNorm() > max_d2) continue;
      if (pose[i].linear().col(2).dot(pose[j].linear().col(2)) < min_axis_cos) continue;
      const Eigen::Isometry3f b_from_a = pose[j].inverse() * pose[i];
      const float overlap = std::max(CoverageSeen(*index.frames[a], b_from_a, intrinsics, 5.0),
                                     CoverageSeen(*index.frames[b], b_from_a.inverse(), intrinsics, 5.0));
      loops.push_back({-overlap, j});
    }
    for (auto* list : {&bridges, &loops}) {
      std::sort(list->begin(), list->end());
      for (int c = 0; c < std::min<int>(list->size(), options_.candidates_per_keyframe); ++c) {
        candidates[i].push_back((*list)[c].second);
      }
    }
  });
  std::vector<std::pair<int, int>> work;
  for (int i = 0; i < m; ++i) {
    for (int j : candidates[i]) {
      if (tried_.insert({i, j}).second) work.push_back({i, j});
    }
  }
  std::vector<std::vector<PointMatch>> found(work.size());
  std::vector<char> ok(work.size(), 0);
  std::vector<LoopEdge> edges(work.size());
  tbb::parallel_for(0, static_cast<int>(work.size()), [&](int w) {
    ok[w] = TryPair(work[w].first, work[w].second, index, intrinsics, &found[w], &edges[w]);
  });
  stats.tried = static_cast<int>(work.size());
  for (size_t w = 0; w < work.size(); ++w) {
    if (!ok[w]) continue;
    ++stats.accepted;
    ++pairs_;
    matches_.insert(matches_.end(), found[w].begin(), found[w].end());
    edges_.push_back(edges[w]);
  }
  stats.pairs = pairs_;
  stats.points = static_cast<int>(matches_.size());
  stats.seconds = timer.Seconds();
  return stats;
}

nlohmann::json ToJson(const SiftLoopStats& s) {
  return {
      {"tried", s.tried}, {"accepted", s.accepted}, {"pairs", s.pairs}, {"points", s.points}, {"seconds", s.seconds}};
}

}  // namespace f2c
