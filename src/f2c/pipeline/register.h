#pragma once
// The whole pipeline as one call (docs/architecture.md), what `register`, the tests, the
// benchmarks and embedders call:
//
//   frames ──► keyframe odometry (T0) ──► fine-to-coarse refinement ──► TSDF mesh
//                 │ each depth image and keyframe SIFT it decodes
//                 ▼
//              depth features (feature index) and keyframes' SIFT (loop matching)
//
// Every frame is decoded once: the odometry hands each decoded depth image to the feature
// extraction and each keyframe's SIFT to the loop matcher's store (the two `Share` steps in
// register.cc), and both finish whatever it did not decode. The result is typed; the files
// (trajectories, run.json, report.html, mesh.ply) are written from it by outputs.h.

#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "f2c/features/depth_features.h"
#include "f2c/features/feature_set.h"
#include "f2c/fusion/fuse.h"
#include "f2c/io/sequence.h"
#include "f2c/odometry/odometry.h"
#include "f2c/pipeline/preset.h"
#include "f2c/refine/refine.h"
#include "f2c/util/progress.h"

namespace f2c {

using PoseList = std::vector<Rigid3d, Eigen::aligned_allocator<Rigid3d>>;

struct RegisterOptions {
  OdometryOptions odometry;
  FeatureOptions features;
  RefineOptions refine;
  FusionOptions fusion;
  bool extract_features = true;  // the refinement's input (false: T0 is the result)
  bool refine_poses = true;      // false: T0 is the result (features are still extracted and cached)
  bool fuse_mesh = true;         // the final poses fused into a mesh
  // features.f2cf, keyframes.f2ck and odometry_pairs.json, reused when frames, intrinsics and
  // options match (empty: no cache).
  std::filesystem::path cache_dir;
  // The refinement starts from these (one per frame) instead of T0; E_L still holds the
  // odometry's relative poses. `initial_name` names them in run.json.
  std::optional<PoseList> initial_poses;
  std::string initial_name = "T0";
  bool keep_iterations = false;      // RefineResult::iteration_poses
  int threads = 0;                   // worker threads (0: all cores); the result does not depend on it
  bool quiet = false;                // no progress bars nor per-stage log lines
  ProgressListener progress;         // told of each stage's progress (util/progress.h); may be empty
  Preset preset = Preset::kDefault;  // the preset ApplyPreset (preset.h) set, for run.json

  bool refines() const { return extract_features && refine_poses; }
  // InputError naming the option for every stage that will run, before any work.
  void Check() const;
  // InputError when a start for the refinement is `given` but the refinement does not run
  // (for a caller that reads the start later, to fail before reading it).
  void CheckStart(bool given) const;
};

// How the odometry aligned its frames (run.json's statistics.odometry).
struct OdometryCounts {
  int pairs = 0, track = 0, sift = 0, icp = 0, motion_prior = 0;
  int keyframes = 0;  // 0 without keyframe odometry
  double mean_inliers = 0, mean_fitness = 0, min_fitness = 0;
};
OdometryCounts CountPairs(const Odometry& odometry);

// `poses` (one per frame) with the time stamps of `like` (the odometry's T0).
Trajectory PosesToTrajectory(const Trajectory& like, const PoseVector& poses);

struct FeatureStage {
  FeatureTimings timings;
  nlohmann::json statistics;  // per-type totals and per-frame means (FeatureExtraction::Statistics)
};

struct RefineStage {
  RefineResult result;     // the poses, each iteration's record, the self-check
  double index_s = 0;      // CPU seconds building the feature index (inside the extraction)
  double keyframes_s = 0;  // the loop matcher's keyframes: gathered, and decoded where missing
  int keyframes = 0, keyframes_decoded = 0;
  size_t index_bytes = 0;
  int64_t peak_memory_bytes_before = 0, peak_memory_bytes_after = 0;
  double wall_s() const { return result.seconds + index_s + keyframes_s; }
};

struct RegisterResult {
  RgbdSequence sequence;  // frames, time stamps, intrinsics and ground truth when the folder has it
  Odometry odometry;      // T0, each frame's alignment, timings
  OdometryCounts odometry_counts;
  std::optional<FeatureStage> features;
  std::optional<RefineStage> refine;  // when the refinement ran
  Trajectory poses;                   // the result: refined, or T0
  std::optional<FusionResult> fusion;
  double read_s = 0;   // reading the sequence (the path overload; else what the caller sets)
  double total_s = 0;  // the whole call
  int64_t peak_memory_bytes = 0;
};

// Registers `sequence` (intrinsics required). InputError with one line for bad input or
// options; the cache is only ever written whole.
RegisterResult Register(RgbdSequence sequence, const RegisterOptions& options);
// The same on a dataset folder or .conf, read with `io`.
RegisterResult Register(const std::filesystem::path& input, const IoOptions& io, const RegisterOptions& options);

// The poses of `source` (a trajectory file: TUM by time stamp, .log by frame id, .conf by
// image name; or a dataset folder's ground truth) for each frame of `sequence`; InputError
// naming `source` when a frame has none, or when two consecutive frames' poses are further
// apart than a camera carried by hand moves (kMaxInitialSpeed: poses in millimetres, or not
// of this sequence, which the refinement would only bend into a wrong result).
constexpr double kMaxInitialSpeed = 10.0;  // m/s; hand-held cameras move at 0.1-1 m/s
PoseList PosesFor(const RgbdSequence& sequence, const std::filesystem::path& source, const IoOptions& io);

}  // namespace f2c
