#pragma once
// Local alignment of consecutive frames and the initial trajectory T0 (paper §4.1,
// "Aligning Adjacent Images", "Initializing Transformations"):
//
//   L[k] = AlignImages(I[k-1], I[k])     SIFT in colour, keypoints with valid depth, RANSAC in 3D
//   T0[0] = I,  T0[k] = T0[k-1] * L[k]   (L[k] = camera k-1 from camera k)
//
// Pairs SIFT cannot align (too few inliers: textureless views) fall back to depth-only
// point-to-plane ICP from the previous motion, and so do SIFT answers the depth images
// contradict (low fitness); each pair records how it was aligned and how
// well, because the refinement weights the local-alignment term E_L by it.

#include <filesystem>
#include <functional>
#include <nlohmann/json_fwd.hpp>
#include <vector>

#include "f2c/io/sequence.h"
#include "f2c/matching/ransac.h"
#include "f2c/matching/sift.h"
#include "f2c/odometry/depth_alignment.h"
#include "f2c/odometry/tracking.h"
#include "f2c/util/fields.h"

namespace f2c {

enum class AlignmentMethod {
  kSift,         // SIFT matches + 3D RANSAC
  kTrack,        // the keyframe's SIFT keypoints tracked into the frame (KLT) + 3D RANSAC
  kIcp,          // depth-only ICP fallback
  kMotionPrior,  // both failed: the previous motion was assumed
};
std::string MethodName(AlignmentMethod method);

// Keyframe odometry (docs/odometry.md): each frame is aligned to the current keyframe by
// tracking the keyframe's SIFT keypoints into it; a frame becomes the next keyframe when its
// motion or overlap since the keyframe passes one of these limits, or when tracking fails
// (then SIFT against the keyframe, then ICP against the previous frame, align it).
struct KeyframeOdometryOptions {
  bool enabled = true;           // false: consecutive pairs, every frame with SIFT
  double max_translation = 0.1;  // metres from the keyframe
  double max_rotation_deg = 10;  // degrees from the keyframe
  // Depth overlap with the keyframe (the pair's fitness) below this starts a new keyframe.
  double min_overlap = 0.9;
  // Tracked RANSAC inliers below this share of the keyframe's keypoints start one.
  double min_inlier_share = 0.3;
  // Fewer tracked inliers than this (or fitness below min_fitness) and tracking failed.
  int min_inliers = 20;
  int max_interval = 0;  // frames from the keyframe that force a new one; 0: no limit
  // The motion prior (tracking's start, ICP's start and its degenerate directions) is the mean
  // motion per frame over this many frames.
  int velocity_frames = 4;
  // Frames neither tracking nor SIFT aligns: depth ICP against the keyframe first (true), or
  // straight against the previous frame (false, the consecutive odometry's fallback).
  bool icp_to_keyframe = false;
  TrackOptions track;

  template <class V>
  void Fields(V& v) {
    v.Group("Keyframe odometry");
    F2C_FIELD(v, enabled, "--keyframes=on|off", {},
              "on: align each frame to the current keyframe by tracking its SIFT keypoints; off: consecutive pairs, "
              "SIFT on every frame");
    F2C_FIELD(v, max_translation, "--keyframe-translation", Positive(),
              "a frame this far (m) from its keyframe starts one");
    F2C_FIELD(v, max_rotation_deg, "--keyframe-rotation", Positive(),
              "a frame turned this far (deg) from its keyframe starts one");
    F2C_FIELD(v, min_overlap, "--keyframe-overlap", Between(0, 1),
              "depth overlap with the keyframe below this starts one");
    F2C_FIELD(v, min_inlier_share, "--keyframe-inlier-share", Between(0, 1),
              "tracked inliers below this share of the keyframe's keypoints start one");
    F2C_FIELD(v, max_interval, "--keyframe-max-interval", AtLeast(0),
              "frames after which a new keyframe starts (0: no limit)");
    F2C_FIELD(v, icp_to_keyframe, "--icp-to-keyframe=on|off", {},
              "frames without texture: depth ICP against the keyframe first (on), or against the previous frame (off)");
    F2C_FIELD(v, velocity_frames, "--velocity-frames", AtLeast(1),
              "the motion prior is the mean motion over this many frames");
    F2C_FIELD(v, min_inliers, "--track-min-inliers", AtLeast(3),
              "fewer tracked inliers: SIFT against the keyframe instead");
    F2C_NESTED(v, track);
  }
  void Check() const;
};

struct OdometryOptions {
  KeyframeOdometryOptions keyframes;
  SiftOptions sift;
  // Lowe's ratio test; the authors use 0.55, relaxed to 0.8 when fewer than 50 matches pass.
  double ratio = 0.55;
  double relaxed_ratio = 0.8;
  int relax_below_matches = 50;
  // RANSAC ends with 5 steps of the ray-aware refit (matching/ransac.h): a keypoint's depth is
  // uncertain along its ray by centimetres at 2-3 m, its direction to a pixel, and the plain 3D fit
  // lets the depth noise turn the pair. Measured: T0's ATE on fr1/xyz is worse with it (0.0236 ->
  // 0.0288 m) but its motion per frame and per second better, and the refined trajectories gain:
  // fr1/xyz, redkitchen with the structure (without it even), the simulated walks (the refinement
  // keeps the relative poses, E_L, and removes the drift). The SIFT loops' RANSAC keeps the plain
  // refit (measured: no gain there).
  RansacOptions ransac = RansacOptions::WithRayAwareRefit(5);
  // SIFT alignments with fewer RANSAC inliers fall back to ICP.
  int min_inliers = 12;
  bool icp_fallback = true;
  IcpOptions icp;
  // Depth-overlap threshold (metres) for the per-pair fitness score.
  double fitness_threshold = 0.05;
  // Geometric check of SIFT answers: below this fitness the depth images contradict it, and
  // ICP from the previous motion is tried; the better-fitting answer is kept. Correct
  // consecutive pairs score > 0.86 on fr1/xyz and redkitchen.
  double min_fitness = 0.5;
  // Seed of every random choice (RANSAC); pair k uses seed + k, so results do not depend on
  // thread scheduling.
  uint64_t seed = 0;
  // Frames whose colour and depth images were taken at different moments
  // (RgbdFrame::color_time; TUM's Kinect: up to 20 ms apart): what was measured from colour
  // keypoints is referred to the depth images' moments (ReferColorToDepthMoments).
  bool sync_color = true;

  template <class V>
  void Fields(V& v) {
    v.Group("Odometry (T0)");
    F2C_FIELD(v, seed, "--seed", {}, "seed of all random choices");
    F2C_NESTED(v, sift);
    v.Field(ratio, "ratio", "--ratio", AboveUpTo(0, 1), "SIFT ratio test");
    F2C_FIELD(v, relaxed_ratio, "--relaxed-ratio", AboveUpTo(0, 1), "ratio used when few matches pass");
    F2C_FIELD(v, relax_below_matches, "", AtLeast(0), "...fewer than this many");
    F2C_NESTED(v, ransac);
    F2C_FIELD(v, min_fitness, "--min-fitness", Between(0, 1),
              "SIFT answers whose depth overlap is lower are checked against ICP");
    F2C_FIELD(v, min_inliers, "--min-inliers", AtLeast(3), "fewer SIFT inliers fall back to ICP");
    F2C_FIELD(v, fitness_threshold, "", Positive(), "depth overlap: points within this distance (m)");
    F2C_FIELD(v, icp_fallback, "!--no-icp-fallback", {}, "never use depth-only ICP");
    F2C_FIELD(v, sync_color, "--sync-color=on|off", {},
              "colour taken at another moment than depth: refer what colour measured to the depth's moment");
    F2C_NESTED(v, keyframes);
    F2C_NESTED(v, icp);
  }
  void Check() const;
};

struct PairAlignment {
  int frame = 0;          // k: this pair aligns frame k to frame `reference`
  int reference = -1;     // < k: k-1 (consecutive pairs), or k's keyframe; -1 (old caches): k-1
  bool keyframe = false;  // frame k starts a new keyframe (keyframe odometry)
  // reference_from_frame (the name predates keyframes, when the reference was always k-1).
  Rigid3d prev_from_curr = Rigid3d::Identity();
  AlignmentMethod method = AlignmentMethod::kSift;
  int keypoints_prev = 0, keypoints_curr = 0;  // SIFT keypoints with valid depth
  int matches = 0;                             // after the ratio test (tracked keypoints with valid depth, for kTrack)
  int inliers = 0;                             // RANSAC inliers
  double inlier_rmse = 0;                      // metres
  double fitness = 0;       // fraction of frame k's depth samples within fitness_threshold of the reference's
  double overlap_rmse = 0;  // metres, of those samples
  int degenerate = 0;       // ICP: directions of motion the reference's geometry left to the previous motion
  // How precisely the pair's measurements fix prev_from_curr: a left perturbation of
  // prev_from_curr in the reference's coordinates, (w radians, v metres). SIFT and tracked
  // pairs: the RANSAC inliers under the depth noise model (RigidFitInformation,
  // matching/ransac.h). ICP fallbacks: the depth's point-to-plane constraint and the image's
  // along what the photometric step refined (MeasuredInformation, depth_alignment.h), none
  // along what was left to the motion prior. Zero where not measured (motion prior, old
  // caches). E_L whitens its constraints by it (refine/local_alignment.h).
  Eigen::Matrix<double, 6, 6> information = Eigen::Matrix<double, 6, 6>::Zero();

  int Reference() const { return reference >= 0 ? reference : frame - 1; }
  // Some direction of prev_from_curr came from the motion prior, not from the images: the
  // prior itself, or an ICP fallback whose reference's geometry left directions free.
  bool LeftToPrior() const {
    return method == AlignmentMethod::kMotionPrior || (method == AlignmentMethod::kIcp && degenerate > 0);
  }
};

// How many pairs in a row before pairs[index] (pairs[index - 1], pairs[index - 2], ...) left
// directions to the motion prior: the motion prior of a fallback at `index` was taken from
// that many pairs that themselves partly repeated an older prior.
int PriorAge(const std::vector<PairAlignment>& pairs, int index);

// Seconds summed over work items (CPU time of the stage, all threads), plus wall time.
struct OdometryTimings {
  double decode = 0, sift = 0, matching = 0, ransac = 0, icp = 0, fitness = 0, hashing = 0, track = 0;
  double wall = 0;
  int sift_frames = 0;       // frames SIFT described (every decoded frame without keyframes)
  int keyframes = 0;         // keyframe odometry: frames that started a keyframe (frame 0 included)
  int frames_processed = 0;  // frames decoded and described (not all, on a cache hit)
  int pairs_computed = 0;
  int pairs_cached = 0;
};

struct Odometry {
  std::vector<PairAlignment> pairs;  // pairs[k-1] aligns frame k to its reference
  Trajectory t0;                     // world_from_camera per frame, T0[0] = identity
  // Per frame whose colour was taken at another moment than its depth
  // (OdometryOptions::sync_color): the camera at its depth's moment from the camera at its
  // colour's. Points measured from its colour keypoints are in the colour's camera; this moves
  // them to the depth's. Empty where every frame's two images share a moment.
  std::vector<std::optional<Rigid3d>> depth_from_color;
  OdometryTimings timings;
};

struct OdometryRun {
  // Pairwise results are kept here and reused when frames, intrinsics and options match.
  // Empty: no cache.
  std::filesystem::path cache_file;
  bool quiet = false;  // no progress output
  // Frames decoded and described at once; bounds memory on long sequences.
  int chunk_frames = 64;
  // Called with each depth image the odometry decodes (from worker threads, once per frame
  // index), so later stages can use it without decoding it again.
  std::function<void(int frame, const cv::Mat& depth)> on_depth;
  // Likewise with each frame's SIFT (the refinement keeps keyframes' for loop pairs).
  std::function<void(int frame, const SiftFeatures& sift)> on_sift;
};

// Where a frame's colour and depth were taken at different moments (RgbdFrame::color_time),
// a colour keypoint sees the scene from where the camera was at the colour's moment while its
// depth, and the pose the frame stands for, are the depth's: at a hand-held camera's 0.5 m/s
// and 30 deg/s, 20 ms is 1 cm and 0.6 degrees. So each frame's motion over its offset is
// taken from T0 (the central difference of its neighbours, as a constant velocity), kept in
// odometry->depth_from_color, and every pair measured from colour (tracked or SIFT; not ICP,
// which is depth's) is referred to the depth's moments,
//   reference_from_frame = depth_from_color[reference] * measured * color_from_depth[frame],
// and T0 chained again from them. BENCHMARKS.md, "Colour and depth moments", measures it.
void ReferColorToDepthMoments(const RgbdSequence& sequence, Odometry* odometry);

// Aligns every frame of `sequence` (intrinsics required): AlignWithKeyframes when
// options.keyframes.enabled, AlignConsecutive otherwise; then ReferColorToDepthMoments when
// options.sync_color.
Odometry AlignFrames(const RgbdSequence& sequence, const OdometryOptions& options, const OdometryRun& run = {});

// Each frame to the current keyframe, in frame order (decoding runs ahead in parallel).
// Pairs are cached by the chain of all frames' bytes up to theirs (a keyframe decision
// depends on every earlier frame), so a run reuses the longest prefix computed before.
Odometry AlignWithKeyframes(const RgbdSequence& sequence, const OdometryOptions& options, const OdometryRun& run = {});

// Aligns every consecutive pair of `sequence` (intrinsics required) in parallel.
Odometry AlignConsecutive(const RgbdSequence& sequence, const OdometryOptions& options, const OdometryRun& run = {});

// Aligns one pair of frames already decoded (depth in metres); used by AlignConsecutive and
// tests. `previous_motion` seeds ICP.
PairAlignment AlignPair(const cv::Mat& gray_prev, const cv::Mat& depth_prev, const cv::Mat& gray_curr,
                        const cv::Mat& depth_curr, const CameraIntrinsics& intrinsics, const OdometryOptions& options,
                        const Rigid3d& previous_motion, uint64_t seed);

// The frames that started a keyframe (frame 0 first); empty without keyframe odometry.
std::vector<int> OdometryKeyframes(const Odometry& odometry);

// T0[0] = identity, T0[k] = T0[reference] * reference_from_frame.
Trajectory ConcatenatePairs(const RgbdSequence& sequence, const std::vector<PairAlignment>& pairs);

// A pair as JSON (transform as 16 row-major numbers, method by name), and back; the parser
// throws nlohmann::json::exception or std::invalid_argument on a malformed object.
nlohmann::json ToJson(const PairAlignment& pair);
PairAlignment PairAlignmentFromJson(const nlohmann::json& json);
nlohmann::json ToJson(const OdometryTimings& timings, int frames);

}  // namespace f2c
