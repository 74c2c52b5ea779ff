#include "f2c/odometry/odometry.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <opencv2/imgproc.hpp>

#include "f2c/io/image.h"
#include "f2c/odometry/odometry_internal.h"
#include "f2c/odometry/pair_cache.h"
#include "f2c/util/error.h"
#include "f2c/util/fields_json.h"
#include "f2c/util/file.h"
#include "f2c/util/progress.h"
#include "f2c/util/timer.h"

namespace f2c {

using namespace internal;  // NOLINT: this file defines them

std::string MethodName(AlignmentMethod method) {
  switch (method) {
    case AlignmentMethod::kSift:
      return "sift";
    case AlignmentMethod::kTrack:
      return "track";
    case AlignmentMethod::kIcp:
      return "icp";
    case AlignmentMethod::kMotionPrior:
      return "motion_prior";
  }
  return "?";
}

void KeyframeOdometryOptions::Check() const { CheckFields(*this); }

void OdometryOptions::Check() const {
  CheckFields(*this);
  if (relaxed_ratio < ratio) {
    ThrowInputError("--relaxed-ratio", fmt::format("must be >= --ratio ({}), got {}", ratio, relaxed_ratio));
  }
}

namespace {

struct MatchSet {
  std::vector<Eigen::Vector3d> prev, curr;
};

MatchSet MatchFeatures(const SiftFeatures& prev, const SiftFeatures& curr, const OdometryOptions& o) {
  MatchSet set;
  for (const SiftMatch& m : MatchSiftRatio(curr, prev, o.ratio, o.relaxed_ratio, o.relax_below_matches)) {
    set.curr.push_back(curr.points_in_camera[m.query]);
    set.prev.push_back(prev.points_in_camera[m.train]);
  }
  return set;
}

}  // namespace

namespace internal {

// SIFT + RANSAC. Leaves method = kMotionPrior when there are too few inliers, for the
// fallback to resolve.
PairAlignment AlignSift(const SiftFeatures& prev, const SiftFeatures& curr, const OdometryOptions& options,
                        uint64_t seed, StageClock* clock) {
  PairAlignment pair;
  pair.keypoints_prev = static_cast<int>(prev.size());
  pair.keypoints_curr = static_cast<int>(curr.size());
  Timer timer;
  const MatchSet matches = MatchFeatures(prev, curr, options);
  clock->matching += timer.Seconds();
  pair.matches = static_cast<int>(matches.prev.size());
  timer.Restart();
  const RansacResult ransac = EstimateRigidRansac(matches.curr, matches.prev, options.ransac, seed);
  clock->ransac += timer.Seconds();
  pair.inliers = static_cast<int>(ransac.inliers.size());
  pair.inlier_rmse = ransac.inlier_rmse;
  if (pair.inliers >= options.min_inliers) {
    pair.method = AlignmentMethod::kSift;
    pair.prev_from_curr = ransac.b_from_a;
    pair.information = ransac.information;
  } else {
    pair.method = AlignmentMethod::kMotionPrior;
  }
  return pair;
}

void ScoreOverlap(const cv::Mat& depth_prev, const cv::Mat& depth_curr, const CameraIntrinsics& k,
                  const OdometryOptions& options, StageClock* clock, PairAlignment* pair) {
  Timer timer;
  const DepthOverlap overlap =
      MeasureDepthOverlap(depth_curr, depth_prev, k, pair->prev_from_curr, options.fitness_threshold);
  clock->fitness += timer.Seconds();
  pair->fitness = overlap.fitness;
  pair->overlap_rmse = overlap.rmse;
}

bool NeedsFallback(const PairAlignment& pair, const OdometryOptions& options) {
  const bool matched = pair.method == AlignmentMethod::kSift || pair.method == AlignmentMethod::kTrack;
  return !matched || pair.fitness < options.min_fitness;
}

// For a pair SIFT could not align, or whose SIFT answer the depth images contradict
// (fitness below min_fitness): depth-only ICP from the previous motion, refined by intensity
// along the motions the depth leaves free where the grey images are given (IcpOptions).
// Keeps whichever of the SIFT answer, the ICP answer and the previous motion the depth images
// agree with most (SIFT wins ties).
void ApplyFallback(const FrameImages& prev, const FrameImages& curr, const CameraIntrinsics& k,
                   const OdometryOptions& options, const Rigid3d& previous_motion, int prior_age, StageClock* clock,
                   PairAlignment* pair) {
  const IcpOptions& o = options.icp;
  PairAlignment best = *pair;
  if (pair->method != AlignmentMethod::kSift) {
    best.method = AlignmentMethod::kMotionPrior;
    best.prev_from_curr = previous_motion;
    best.information.setZero();
    ScoreOverlap(prev.depth, curr.depth, k, options, clock, &best);
  }
  if (options.icp_fallback) {
    Timer timer;
    PairAlignment icp = *pair;
    icp.prev_from_curr = previous_motion;
    icp.information.setZero();  // not the SIFT fit's, which this pair replaces
    const bool ok = AlignDepthIcp(curr.depth, prev.depth, k, previous_motion, o, &icp.prev_from_curr);
    clock->icp += timer.Seconds();
    std::optional<ViewConstraints> analysed;
    Eigen::Matrix<double, 6, Eigen::Dynamic> refined_along(6, 0);  // what the photometric step measured
    if (ok && o.prior_information > 0) {
      // Where the reference's geometry leaves ICP free (a plain wall), keep the previous motion.
      timer.Restart();
      const bool photometric = o.photometric && !prev.gray.empty() && !curr.gray.empty();
      const ViewConstraints view = AnalyseViewConstraints(prev.depth, photometric ? prev.gray : cv::Mat(), k,
                                                          o.degeneracy_stride, o.min_gradient);
      icp.prev_from_curr = ConstrainToGeometry(icp.prev_from_curr, previous_motion, view.depth, o.prior_information);
      icp.degenerate = view.depth.Degenerate(o.prior_information);
      const Eigen::Matrix<double, 6, Eigen::Dynamic> weak = photometric && icp.degenerate > 0
                                                                ? PhotometricDirections(view, o.prior_information)
                                                                : Eigen::Matrix<double, 6, Eigen::Dynamic>(6, 0);
      if (weak.cols() > 0) {
        // ...unless its image measures them: the fused answer refined by intensity along them
        // (and along any the image measures better than the depth), and kept as far as the
        // image's information weighs against the depth's and the prior's.
        Rigid3d refined = icp.prev_from_curr;
        if (AlignPhotometric(prev.gray, prev.depth, curr.gray, k, weak, view.depth.mean_depth, o.dense, &refined).ok) {
          icp.prev_from_curr =
              FusePhotometric(refined, icp.prev_from_curr, view, weak, o.prior_information, &icp.degenerate);
          refined_along = weak;
        }
      }
      analysed = view;
      clock->icp += timer.Seconds();
    }
    if (ok) {
      icp.method = AlignmentMethod::kIcp;
      ScoreOverlap(prev.depth, curr.depth, k, options, clock, &icp);
      if (analysed && analysed->depth.samples > 0) {
        icp.information = MeasuredInformation(*analysed, refined_along, o.prior_information, o.prior_sigma,
                                              1.0 + o.prior_sigma_growth * prior_age);
      }
      if (best.method == AlignmentMethod::kMotionPrior || icp.fitness > best.fitness) best = icp;
    }
  }
  *pair = best;
}

void DecodeFrame(const RgbdSequence& seq, int index, StageClock* clock, cv::Mat* depth, cv::Mat* gray) {
  Timer timer;
  const RgbdFrame& frame = seq.frames[index];
  *depth = LoadDepthMeters(seq, frame);
  *gray = LoadGray(seq, frame, depth->size());
  clock->decode += timer.Seconds();
}

SiftFeatures DescribeFrame(const cv::Mat& gray, const cv::Mat& depth, const CameraIntrinsics& k,
                           const OdometryOptions& options, StageClock* clock) {
  Timer timer;
  SiftFeatures sift = ExtractSiftWithDepth(gray, depth, k, options.sift);
  clock->sift += timer.Seconds();
  ++clock->sift_frames;
  return sift;
}

Rigid3d ChainPose(const Rigid3d& world_from_reference, const Rigid3d& reference_from_frame) {
  Rigid3d pose = world_from_reference * reference_from_frame;
  pose.linear() = Eigen::Quaterniond(pose.linear()).normalized().toRotationMatrix();
  return pose;
}

void CopyTimings(const StageClock& clock, OdometryTimings* t) {
  t->decode = clock.decode;
  t->sift = clock.sift;
  t->matching = clock.matching;
  t->ransac = clock.ransac;
  t->icp = clock.icp;
  t->fitness = clock.fitness;
  t->hashing = clock.hashing;
  t->track = clock.track;
  t->sift_frames = clock.sift_frames;
}

}  // namespace internal

namespace {

struct FrameData {
  FrameImages images;
  SiftFeatures sift;
  bool loaded = false;
};

void LoadFrame(const RgbdSequence& seq, int index, const OdometryOptions& options, StageClock* clock, FrameData* data) {
  DecodeFrame(seq, index, clock, &data->images.depth, &data->images.gray);
  data->sift = DescribeFrame(data->images.gray, data->images.depth, *seq.intrinsics, options, clock);
  data->loaded = true;
}

}  // namespace

PairAlignment AlignPair(const cv::Mat& gray_prev, const cv::Mat& depth_prev, const cv::Mat& gray_curr,
                        const cv::Mat& depth_curr, const CameraIntrinsics& intrinsics, const OdometryOptions& options,
                        const Rigid3d& previous_motion, uint64_t seed) {
  StageClock clock;
  const SiftFeatures prev = ExtractSiftWithDepth(gray_prev, depth_prev, intrinsics, options.sift);
  const SiftFeatures curr = ExtractSiftWithDepth(gray_curr, depth_curr, intrinsics, options.sift);
  PairAlignment pair = AlignSift(prev, curr, options, seed, &clock);
  if (pair.method == AlignmentMethod::kSift) ScoreOverlap(depth_prev, depth_curr, intrinsics, options, &clock, &pair);
  if (NeedsFallback(pair, options)) {
    ApplyFallback({depth_prev, gray_prev}, {depth_curr, gray_curr}, intrinsics, options, previous_motion, 0, &clock,
                  &pair);
  }
  return pair;
}

int PriorAge(const std::vector<PairAlignment>& pairs, int index) {
  int age = 0;
  for (int i = std::min(index, static_cast<int>(pairs.size())) - 1; i >= 0 && pairs[i].LeftToPrior(); --i) ++age;
  return age;
}

std::vector<int> OdometryKeyframes(const Odometry& odometry) {
  std::vector<int> out;
  for (const PairAlignment& p : odometry.pairs) {
    if (p.keyframe) out.push_back(p.frame);
  }
  if (!out.empty() || odometry.timings.keyframes > 0) out.insert(out.begin(), 0);
  return out;
}

Trajectory ConcatenatePairs(const RgbdSequence& sequence, const std::vector<PairAlignment>& pairs) {
  F2C_CHECK(pairs.size() + 1 == sequence.frames.size(), "one pair per frame after the first");
  Trajectory t0;
  t0.Add(sequence.frames[0].timestamp, Rigid3d::Identity());
  for (size_t k = 1; k < sequence.frames.size(); ++k) {
    const PairAlignment& pair = pairs[k - 1];
    F2C_CHECK(pair.frame == static_cast<int>(k) && pair.Reference() >= 0 && pair.Reference() < pair.frame,
              "pairs[k-1] aligns frame k to an earlier frame");
    t0.Add(sequence.frames[k].timestamp, ChainPose(t0.world_from_camera[pair.Reference()], pair.prev_from_curr));
  }
  return t0;
}

void ReferColorToDepthMoments(const RgbdSequence& sequence, Odometry* odometry) {
  const int n = static_cast<int>(sequence.frames.size());
  F2C_CHECK(static_cast<int>(odometry->t0.size()) == n && static_cast<int>(odometry->pairs.size()) + 1 == n,
            "T0 and the pairs of the sequence's frames");
  odometry->depth_from_color.assign(n, std::nullopt);
  bool any = false;
  const auto& world_from_camera = odometry->t0.world_from_camera;
  for (int k = 0; k < n && n > 1; ++k) {
    const double offset = sequence.frames[k].color_time;
    if (offset == 0) continue;
    const int a = std::max(k - 1, 0), b = std::min(k + 1, n - 1);
    const double seconds = sequence.frames[b].timestamp - sequence.frames[a].timestamp;
    if (!(seconds > 0)) continue;
    // The camera at t from the camera at t + offset: the motion from a to b scaled by
    // offset / seconds, its rotation about its axis and its translation in proportion.
    const Rigid3d a_from_b = world_from_camera[a].inverse() * world_from_camera[b];
    const double f = offset / seconds;
    const Eigen::AngleAxisd turn(a_from_b.linear());
    Rigid3d depth_from_color = Rigid3d::Identity();
    depth_from_color.linear() = Eigen::AngleAxisd(turn.angle() * f, turn.axis()).toRotationMatrix();
    depth_from_color.translation() = f * a_from_b.translation();
    odometry->depth_from_color[k] = depth_from_color;
    any = true;
  }
  if (!any) {
    odometry->depth_from_color.clear();
    return;
  }
  const auto motion = [&](int k) { return odometry->depth_from_color[k].value_or(Rigid3d::Identity()); };
  for (PairAlignment& pair : odometry->pairs) {
    if (pair.method != AlignmentMethod::kSift && pair.method != AlignmentMethod::kTrack) continue;
    pair.prev_from_curr = motion(pair.Reference()) * pair.prev_from_curr * motion(pair.frame).inverse();
  }
  odometry->t0 = ConcatenatePairs(sequence, odometry->pairs);
}

Odometry AlignFrames(const RgbdSequence& sequence, const OdometryOptions& options, const OdometryRun& run) {
  Odometry odometry =
      options.keyframes.enabled ? AlignWithKeyframes(sequence, options, run) : AlignConsecutive(sequence, options, run);
  if (options.sync_color) ReferColorToDepthMoments(sequence, &odometry);
  return odometry;
}

Odometry AlignConsecutive(const RgbdSequence& seq, const OdometryOptions& options, const OdometryRun& run) {
  options.Check();
  RequireIntrinsics(seq);
  Timer wall;
  StageClock clock;
  Odometry odometry;
  const int n = static_cast<int>(seq.frames.size());
  odometry.pairs.resize(std::max(n - 1, 0));

  // Cache look-up: a pair's key covers both frames' bytes, the intrinsics, the depth
  // decoding and every option, so any change recomputes exactly the pairs it affects.
  PairCache cache(run.cache_file, CacheContext(seq, FieldsToJson(options).dump()));
  std::vector<std::string> keys(std::max(n - 1, 0));
  std::vector<char> have(std::max(n - 1, 0), 0);
  if (cache.enabled()) {
    Timer timer;
    std::vector<uint64_t> frame_hash(n);
    tbb::parallel_for(0, n, [&](int i) { frame_hash[i] = HashFrameFiles(seq.frames[i]); });
    for (int k = 1; k < n; ++k) {
      keys[k - 1] = cache.Key(frame_hash[k - 1], frame_hash[k]);
      have[k - 1] = cache.Lookup(keys[k - 1], &odometry.pairs[k - 1]);
    }
    clock.hashing += timer.Seconds();
  }
  const int cached = static_cast<int>(std::count(have.begin(), have.end(), 1));
  odometry.timings.pairs_cached = cached;
  if (cached > 0) spdlog::info("odometry: {} of {} pairs from cache {}", cached, n - 1, run.cache_file.string());

  Progress progress("odometry", n - 1 - cached, run.quiet);
  std::atomic<int> frames_processed{0};
  // Chunks of frames: decode + SIFT in parallel, then align the chunk's pairs in parallel.
  // A chunk shares its first frame with the previous chunk's last.
  FrameData carry;
  for (int begin = 0; begin < n - 1; begin += run.chunk_frames) {
    const int end = std::min(n - 1, begin + run.chunk_frames);  // pairs (k-1, k), k in (begin, end]
    bool any = false;
    for (int k = begin + 1; k <= end; ++k) any = any || !have[k - 1];
    if (!any) {
      carry = FrameData();
      continue;
    }
    std::vector<FrameData> frames(end - begin + 1);
    if (carry.loaded) frames[0] = std::move(carry);
    tbb::parallel_for(0, end - begin + 1, [&](int i) {
      const int f = begin + i;
      const bool needed = (f > begin && !have[f - 1]) || (f < end && !have[f]);
      if (needed && !frames[i].loaded) {
        LoadFrame(seq, f, options, &clock, &frames[i]);
        ++frames_processed;
        if (run.on_depth) run.on_depth(f, frames[i].images.depth);
        if (run.on_sift) run.on_sift(f, frames[i].sift);
      }
    });
    tbb::parallel_for(begin + 1, end + 1, [&](int k) {
      if (have[k - 1]) return;
      PairAlignment& pair = odometry.pairs[k - 1];
      pair = AlignSift(frames[k - 1 - begin].sift, frames[k - begin].sift, options, options.seed + k, &clock);
      pair.frame = k;
      pair.reference = k - 1;
      if (pair.method == AlignmentMethod::kSift) {
        ScoreOverlap(frames[k - 1 - begin].images.depth, frames[k - begin].images.depth, *seq.intrinsics, options,
                     &clock, &pair);
      }
    });
    // Fallbacks in frame order, so each starts from the final previous motion.
    for (int k = begin + 1; k <= end; ++k) {
      PairAlignment& pair = odometry.pairs[k - 1];
      if (!have[k - 1] && NeedsFallback(pair, options)) {
        const Rigid3d previous = k > 1 ? odometry.pairs[k - 2].prev_from_curr : Rigid3d::Identity();
        ApplyFallback(frames[k - 1 - begin].images, frames[k - begin].images, *seq.intrinsics, options, previous,
                      PriorAge(odometry.pairs, k - 1), &clock, &pair);
      }
      if (!have[k - 1]) progress.Advance();
    }
    carry = std::move(frames.back());
    for (int k = begin + 1; k <= end; ++k) {
      if (!have[k - 1]) cache.Store(keys[k - 1], odometry.pairs[k - 1]);
    }
    cache.Save();  // a checkpoint per chunk: an interrupted run resumes here
  }
  progress.Finish();

  odometry.t0 = ConcatenatePairs(seq, odometry.pairs);
  OdometryTimings& t = odometry.timings;
  CopyTimings(clock, &t);
  t.frames_processed = frames_processed;
  t.pairs_computed = n - 1 - cached;
  t.wall = wall.Seconds();
  return odometry;
}

nlohmann::json ToJson(const PairAlignment& p) {
  std::vector<double> m(16);
  for (int i = 0; i < 16; ++i) m[i] = p.prev_from_curr.matrix()(i / 4, i % 4);
  nlohmann::json j = {{"frame", p.frame},
                      {"reference", p.Reference()},
                      {"keyframe", p.keyframe},
                      {"method", MethodName(p.method)},
                      {"prev_from_curr", m},
                      {"keypoints_prev", p.keypoints_prev},
                      {"keypoints_curr", p.keypoints_curr},
                      {"matches", p.matches},
                      {"inliers", p.inliers},
                      {"inlier_rmse", p.inlier_rmse},
                      {"fitness", p.fitness},
                      {"degenerate", p.degenerate},
                      {"overlap_rmse", p.overlap_rmse}};
  if (p.method != AlignmentMethod::kMotionPrior && !p.information.isZero()) {
    // All 36 entries, row by row: the computed matrix is symmetric only to rounding, and a
    // cached pair must be the computed one bit for bit (the refinement's result too).
    std::vector<double> entries;
    for (int r = 0; r < 6; ++r) {
      for (int c = 0; c < 6; ++c) entries.push_back(p.information(r, c));
    }
    j["information"] = entries;
  }
  return j;
}

namespace {

// A whole number within int's range. nlohmann's get<int> turns 3.5 into 3 silently and 2e89
// into undefined behaviour (a fuzz finding).
int WholeNumber(const nlohmann::json& j, const char* key) {
  const nlohmann::json& v = j.at(key);
  if (!v.is_number_integer()) throw std::invalid_argument(std::string(key) + " is not a whole number");
  const bool fits = v.is_number_unsigned() ? v.get<uint64_t>() <= uint64_t{INT32_MAX}
                                           : v.get<int64_t>() >= INT32_MIN && v.get<int64_t>() <= INT32_MAX;
  if (!fits) throw std::invalid_argument(std::string(key) + " is out of range");
  return static_cast<int>(v.get<int64_t>());
}

}  // namespace

PairAlignment PairAlignmentFromJson(const nlohmann::json& j) {
  PairAlignment p;
  p.frame = WholeNumber(j, "frame");
  p.reference = j.contains("reference") ? WholeNumber(j, "reference") : p.frame - 1;
  p.keyframe = j.value("keyframe", false);
  if (p.reference < 0 || p.reference >= p.frame) throw std::invalid_argument("reference must precede frame");
  const auto m = j.at("prev_from_curr").get<std::vector<double>>();
  if (m.size() != 16) throw std::invalid_argument("prev_from_curr needs 16 numbers");
  for (int i = 0; i < 16; ++i) p.prev_from_curr.matrix()(i / 4, i % 4) = m[i];
  // Trust nothing read back: a damaged entry must not become a NaN or sheared trajectory.
  const Eigen::Matrix4d& t = p.prev_from_curr.matrix();
  if (!t.allFinite()) throw std::invalid_argument("prev_from_curr is not finite");
  if (!t.row(3).isApprox(Eigen::RowVector4d(0, 0, 0, 1), 1e-12))
    throw std::invalid_argument("prev_from_curr's last row is not 0 0 0 1");
  const Eigen::Matrix3d r = t.topLeftCorner<3, 3>();
  if (!(r.transpose() * r).isApprox(Eigen::Matrix3d::Identity(), 1e-6) || r.determinant() < 0) {
    throw std::invalid_argument("prev_from_curr is not a rotation");
  }
  if (t.col(3).head<3>().norm() > 100) throw std::invalid_argument("prev_from_curr moves more than 100 m");
  const std::string method = j.at("method").get<std::string>();
  if (method == MethodName(AlignmentMethod::kSift)) {
    p.method = AlignmentMethod::kSift;
  } else if (method == MethodName(AlignmentMethod::kTrack)) {
    p.method = AlignmentMethod::kTrack;
  } else if (method == MethodName(AlignmentMethod::kIcp)) {
    p.method = AlignmentMethod::kIcp;
  } else if (method == MethodName(AlignmentMethod::kMotionPrior)) {
    p.method = AlignmentMethod::kMotionPrior;
  } else {
    throw std::invalid_argument("unknown method " + method);
  }
  p.keypoints_prev = WholeNumber(j, "keypoints_prev");
  p.keypoints_curr = WholeNumber(j, "keypoints_curr");
  p.matches = WholeNumber(j, "matches");
  p.inliers = WholeNumber(j, "inliers");
  p.inlier_rmse = j.at("inlier_rmse").get<double>();
  p.fitness = j.at("fitness").get<double>();
  p.degenerate = j.contains("degenerate") ? WholeNumber(j, "degenerate") : 0;
  p.overlap_rmse = j.at("overlap_rmse").get<double>();
  if (p.keypoints_prev < 0 || p.keypoints_curr < 0 || p.matches < 0 || p.inliers < 0 || p.inliers > p.matches) {
    throw std::invalid_argument("negative or inconsistent counts");
  }
  if (j.contains("information")) {
    const auto entries = j.at("information").get<std::vector<double>>();
    int i = 0;
    if (entries.size() == 36) {
      for (int r = 0; r < 6; ++r) {
        for (int c = 0; c < 6; ++c) p.information(r, c) = entries[i++];
      }
    } else if (entries.size() == 21) {  // the upper triangle, as older odometry.json files hold it
      for (int r = 0; r < 6; ++r) {
        for (int c = r; c < 6; ++c) p.information(r, c) = p.information(c, r) = entries[i++];
      }
    } else {
      throw std::invalid_argument("information needs 36 numbers (or its 21 upper-triangle ones)");
    }
    if (!p.information.allFinite() || (p.information.diagonal().array() < 0).any()) {
      throw std::invalid_argument("information is not finite or has a negative diagonal");
    }
  }
  if (!(p.fitness >= 0 && p.fitness <= 1)) throw std::invalid_argument("fitness outside [0, 1]");
  if (!(std::isfinite(p.inlier_rmse) && p.inlier_rmse >= 0) ||
      !(std::isfinite(p.overlap_rmse) && p.overlap_rmse >= 0)) {
    throw std::invalid_argument("an RMSE is negative or not finite");
  }
  return p;
}

nlohmann::json ToJson(const OdometryTimings& t, int frames) {
  const double per = frames > 0 ? 1000.0 / frames : 0.0;
  return {{"wall_s", t.wall},
          {"frames_processed", t.frames_processed},
          {"pairs_computed", t.pairs_computed},
          {"pairs_cached", t.pairs_cached},
          {"keyframes", t.keyframes},
          {"sift_frames", t.sift_frames},
          {"sift_per_frame", frames > 0 ? static_cast<double>(t.sift_frames) / frames : 0.0},
          {"cpu_ms_per_frame",
           {{"decode", t.decode * per},
            {"sift", t.sift * per},
            {"matching", t.matching * per},
            {"ransac", t.ransac * per},
            {"track", t.track * per},
            {"icp", t.icp * per},
            {"fitness", t.fitness * per},
            {"hashing", t.hashing * per}}}};
}

}  // namespace f2c
