// Keyframe odometry (odometry.h, docs/odometry.md). Frames are decoded in parallel, ahead of a
// serial step that aligns each to the current keyframe in frame order, since which frame is
// the keyframe depends on every alignment before it.

#include <spdlog/spdlog.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_pipeline.h>
#include <tbb/task_arena.h>

#include <nlohmann/json.hpp>
#include <optional>

#include "f2c/odometry/odometry.h"
#include "f2c/odometry/odometry_internal.h"
#include "f2c/odometry/pair_cache.h"
#include "f2c/util/error.h"
#include "f2c/util/fields_json.h"
#include "f2c/util/file.h"
#include "f2c/util/progress.h"
#include "f2c/util/timer.h"

namespace f2c {
namespace {

using internal::StageClock;

struct Decoded {
  int frame = -1;
  cv::Mat depth, gray;
};

double AngleDeg(const Rigid3d& t) {
  return Eigen::AngleAxisd(Eigen::Quaterniond(t.linear()).normalized()).angle() * 180.0 / M_PI;
}

// The serial part: the current keyframe, the previous frame, and T0 so far.
class KeyframeTracker {
 public:
  KeyframeTracker(const RgbdSequence& seq, const OdometryOptions& options, const OdometryRun& run, StageClock* clock,
                  Odometry* odometry)
      : k_(*seq.intrinsics), options_(options), run_(run), clock_(clock), odometry_(odometry) {
    poses_.resize(seq.frames.size());
  }

  // Replays a frame whose pair came from the cache: its pose, and, for the keyframe the
  // computed frames continue from, its tracking state.
  void Replay(Decoded&& frame, bool make_keyframe) {
    const int k = frame.frame;
    poses_[k] = k == 0 ? Rigid3d::Identity() : Chain(odometry_->pairs[k - 1]);
    if (make_keyframe) StartKeyframe(frame, internal::DescribeFrame(frame.gray, frame.depth, k_, options_, clock_));
    previous_ = std::move(frame);
  }

  // Skips a cached frame that is not decoded (before the keyframe replay starts from).
  void Skip(int k) { poses_[k] = k == 0 ? Rigid3d::Identity() : Chain(odometry_->pairs[k - 1]); }

  void Step(Decoded&& frame) {
    const int k = frame.frame;
    if (k == 0) {
      poses_[0] = Rigid3d::Identity();
      StartKeyframe(frame, internal::DescribeFrame(frame.gray, frame.depth, k_, options_, clock_));
      previous_ = std::move(frame);
      return;
    }
    PairAlignment& pair = odometry_->pairs[k - 1];
    const KeyframeOdometryOptions& ko = options_.keyframes;
    const Rigid3d motion = Velocity(k);
    const Rigid3d keyframe_from_guess = poses_[key_.frame].inverse() * poses_[k - 1] * motion;

    pair = Track(frame, keyframe_from_guess);
    std::optional<SiftFeatures> sift;
    bool aligned = pair.method == AlignmentMethod::kTrack && !internal::NeedsFallback(pair, options_);
    if (!aligned && static_cast<int>(key_.sift.size()) >= options_.min_inliers) {
      // Tracking lost the keyframe: SIFT against it (when it has keypoints enough to match).
      sift = internal::DescribeFrame(frame.gray, frame.depth, k_, options_, clock_);
      pair = internal::AlignSift(key_.sift, *sift, options_, options_.seed + k, clock_);
      pair.reference = key_.frame;
      if (pair.method == AlignmentMethod::kSift) {
        internal::ScoreOverlap(key_.depth, frame.depth, k_, options_, clock_, &pair);
      }
      aligned = !internal::NeedsFallback(pair, options_);
      pair.keyframe = aligned;  // the keyframe's keypoints no longer reach this far
    }
    if (!aligned && ko.icp_to_keyframe) {
      // No appearance to align by (a plain wall): depth ICP against the keyframe, from the
      // predicted motion, so textureless stretches chain keyframes, not every frame.
      PairAlignment icp = pair;
      icp.reference = key_.frame;
      internal::ApplyFallback({key_.depth, key_.gray}, {frame.depth, frame.gray}, k_, options_, keyframe_from_guess,
                              PriorAge(odometry_->pairs, k - 1), clock_, &icp);
      aligned = icp.method == AlignmentMethod::kIcp && icp.fitness >= options_.min_fitness;
      if (aligned) {
        pair = icp;
        pair.keyframe = false;
      }
    }
    if (!aligned) {
      // Failing that, the consecutive odometry's fallback against the previous frame (the
      // smallest motion); the SIFT answer, if any, is a candidate relative to it.
      if (key_.frame != k - 1) {
        pair.prev_from_curr = poses_[k - 1].inverse() * poses_[key_.frame] * pair.prev_from_curr;
        pair.reference = k - 1;
        if (pair.method == AlignmentMethod::kSift) {
          internal::ScoreOverlap(previous_.depth, frame.depth, k_, options_, clock_, &pair);
        }
      }
      internal::ApplyFallback({previous_.depth, previous_.gray}, {frame.depth, frame.gray}, k_, options_, motion,
                              PriorAge(odometry_->pairs, k - 1), clock_, &pair);
      pair.keyframe = true;
    }
    if (!pair.keyframe && pair.reference == key_.frame) {
      const Rigid3d& t = pair.prev_from_curr;
      pair.keyframe = t.translation().norm() > ko.max_translation || AngleDeg(t) > ko.max_rotation_deg ||
                      pair.fitness < ko.min_overlap ||
                      (pair.method == AlignmentMethod::kTrack &&
                       pair.inliers < ko.min_inlier_share * static_cast<double>(key_.sift.size())) ||
                      (ko.max_interval > 0 && k - key_.frame >= ko.max_interval);
    }
    if (pair.keyframe && !sift) sift = internal::DescribeFrame(frame.gray, frame.depth, k_, options_, clock_);
    pair.frame = k;
    poses_[k] = Chain(pair);
    if (pair.keyframe) StartKeyframe(frame, std::move(*sift));
    previous_ = std::move(frame);
  }

 private:
  // Constant velocity: the mean motion per frame over the last velocity_frames frames before
  // k (one frame's motion, between two frames tracked from one keyframe, is as noisy as two
  // trackings; the average is what a degenerate ICP keeps where the geometry is silent).
  Rigid3d Velocity(int k) const {
    const int m = std::min(k - 1, options_.keyframes.velocity_frames);
    if (m < 1) return Rigid3d::Identity();
    const Rigid3d span = poses_[k - 1 - m].inverse() * poses_[k - 1];
    const Eigen::AngleAxisd turn(span.linear());
    Rigid3d step = Rigid3d::Identity();
    step.linear() = Eigen::AngleAxisd(turn.angle() / m, turn.axis()).toRotationMatrix();
    // m equal steps: span.t = (I + R + ... + R^(m-1)) step.t
    Eigen::Matrix3d sum = Eigen::Matrix3d::Zero(), power = Eigen::Matrix3d::Identity();
    for (int i = 0; i < m; ++i) {
      sum += power;
      power = step.linear() * power;
    }
    step.translation() = sum.inverse() * span.translation();
    return step;
  }

  Rigid3d Chain(const PairAlignment& pair) const {
    return internal::ChainPose(poses_[pair.Reference()], pair.prev_from_curr);
  }

  PairAlignment Track(const Decoded& frame, const Rigid3d& keyframe_from_guess) {
    PairAlignment pair;
    pair.frame = frame.frame;
    pair.reference = key_.frame;
    Timer timer;
    const TrackedPoints points =
        TrackKeypoints(key_, frame.gray, frame.depth, k_, keyframe_from_guess, options_.sift, options_.keyframes.track);
    clock_->track += timer.Seconds();
    pair.keypoints_prev = static_cast<int>(key_.sift.size());
    pair.keypoints_curr = points.tracked;
    pair.matches = static_cast<int>(points.frame.size());
    timer.Restart();
    const RansacResult ransac =
        EstimateRigidRansac(points.frame, points.keyframe, options_.ransac, options_.seed + frame.frame);
    clock_->ransac += timer.Seconds();
    pair.inliers = static_cast<int>(ransac.inliers.size());
    pair.inlier_rmse = ransac.inlier_rmse;
    if (pair.inliers >= options_.keyframes.min_inliers) {
      pair.method = AlignmentMethod::kTrack;
      pair.prev_from_curr = ransac.b_from_a;
      pair.information = ransac.information;
      internal::ScoreOverlap(key_.depth, frame.depth, k_, options_, clock_, &pair);
    } else {
      pair.method = AlignmentMethod::kMotionPrior;
    }
    return pair;
  }

  void StartKeyframe(const Decoded& frame, SiftFeatures sift) {
    if (run_.on_sift) run_.on_sift(frame.frame, sift);
    key_ = MakeTrackingKeyframe(frame.frame, frame.gray, frame.depth, std::move(sift), options_.keyframes.track);
  }

  const CameraIntrinsics& k_;
  const OdometryOptions& options_;
  const OdometryRun& run_;
  StageClock* clock_;
  Odometry* odometry_;
  std::vector<Rigid3d> poses_;
  TrackingKeyframe key_;
  Decoded previous_;
};

}  // namespace

Odometry AlignWithKeyframes(const RgbdSequence& seq, const OdometryOptions& options, const OdometryRun& run) {
  options.Check();
  RequireIntrinsics(seq);
  Timer wall;
  StageClock clock;
  Odometry odometry;
  const int n = static_cast<int>(seq.frames.size());
  if (n == 0) return odometry;
  odometry.pairs.resize(n - 1);

  // Cache: frame k's pair is keyed by a hash chained over frames 0..k, so a hit means every
  // decision before it was taken on the same frames. The cached prefix ends at the first miss.
  PairCache cache(run.cache_file, CacheContext(seq, FieldsToJson(options).dump()));
  std::vector<std::string> keys(n);
  int first_computed = 1;  // frames [1, first_computed) come from the cache
  if (cache.enabled()) {
    Timer timer;
    std::vector<uint64_t> frame_hash(n);
    tbb::parallel_for(0, n, [&](int i) { frame_hash[i] = HashFrameFiles(seq.frames[i]); });
    uint64_t chain = frame_hash[0];
    for (int k = 1; k < n; ++k) {
      keys[k] = cache.Key(chain, frame_hash[k]);
      chain = Fnv1a64(HexString(chain) + HexString(frame_hash[k]));
    }
    while (first_computed < n && cache.Lookup(keys[first_computed], &odometry.pairs[first_computed - 1]) &&
           odometry.pairs[first_computed - 1].frame == first_computed) {
      ++first_computed;
    }
    clock.hashing += timer.Seconds();
  }
  const int cached = first_computed - 1;
  odometry.timings.pairs_cached = cached;
  if (cached > 0) spdlog::info("odometry: {} of {} pairs from cache {}", cached, n - 1, run.cache_file.string());

  // The computed frames continue from the last keyframe of the cached prefix: replay from it.
  int replay_from = 0;
  for (int k = 1; k < first_computed; ++k) {
    if (odometry.pairs[k - 1].keyframe) replay_from = k;
  }
  KeyframeTracker tracker(seq, options, run, &clock, &odometry);
  for (int k = 0; k < replay_from; ++k) tracker.Skip(k);

  Progress progress("odometry", n - first_computed, run.quiet);
  int frames_processed = 0;
  if (first_computed < n) {
    int next = replay_from;
    const int tokens = 2 * tbb::this_task_arena::max_concurrency() + 2;
    tbb::parallel_pipeline(tokens,
                           tbb::make_filter<void, int>(tbb::filter_mode::serial_in_order, [&](tbb::flow_control& fc) {
                             if (next >= n) {
                               fc.stop();
                               return 0;
                             }
                             return next++;
                           }) & tbb::make_filter<int, Decoded>(tbb::filter_mode::parallel, [&](int k) {
                             Decoded d;
                             d.frame = k;
                             internal::DecodeFrame(seq, k, &clock, &d.depth, &d.gray);
                             if (run.on_depth) run.on_depth(k, d.depth);
                             return d;
                           }) & tbb::make_filter<Decoded, void>(tbb::filter_mode::serial_in_order, [&](Decoded d) {
                             const int k = d.frame;
                             ++frames_processed;
                             if (k < first_computed) {
                               tracker.Replay(std::move(d), k == replay_from);
                               return;
                             }
                             tracker.Step(std::move(d));
                             if (k > 0) {
                               cache.Store(keys[k], odometry.pairs[k - 1]);
                               progress.Advance();
                             }
                             if (k % run.chunk_frames == 0)
                               cache.Save();  // a checkpoint: an interrupted run resumes here
                           }));
  }
  cache.Save();
  progress.Finish();

  odometry.t0 = ConcatenatePairs(seq, odometry.pairs);
  OdometryTimings& t = odometry.timings;
  internal::CopyTimings(clock, &t);
  t.keyframes = 1;  // frame 0, and the frames that started one (cached ones included)
  for (const PairAlignment& p : odometry.pairs) t.keyframes += p.keyframe;
  t.frames_processed = frames_processed;
  t.pairs_computed = n - first_computed;
  t.wall = wall.Seconds();
  return odometry;
}

}  // namespace f2c
