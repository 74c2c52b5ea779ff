#include "f2c/pipeline/register.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <atomic>
#include <opencv2/core/utility.hpp>

#include "f2c/io/image.h"
#include "f2c/refine/keyframes.h"
#include "f2c/util/error.h"
#include "f2c/util/memory.h"
#include "f2c/util/timer.h"

namespace f2c {
namespace fs = std::filesystem;

namespace {

// More would not run faster on any machine, and TBB fails outright on some huge counts.
constexpr int kMaxThreads = 1024;

void Log(const RegisterOptions& options, const std::string& line) {
  if (!options.quiet) spdlog::info("{}", line);
}

// The feature extraction, fed by the odometry's decoded depth images; each frame's features
// go straight into the refinement's compact index (or are dropped when it does not run), so
// the full set is never held, and the cache is streamed to disk.
struct FeatureStep {
  std::optional<FeatureExtraction> extraction;
  std::optional<FeatureIndex> index;
  std::atomic<int64_t> index_ns{0};

  FeatureStep(const RgbdSequence& seq, const RegisterOptions& options) {
    if (!options.extract_features) return;
    if (options.refines()) {
      index.emplace();
      index->frames.resize(seq.frames.size());
    }
    FeatureRun run;
    run.quiet = options.quiet;
    if (!options.cache_dir.empty()) run.cache_file = options.cache_dir / "features.f2cf";
    run.on_frame = [this, &options](int frame, FrameFeatures&& features) {
      if (!index) return;
      Timer timer;
      index->frames[frame] = BuildFrameIndex(features, options.refine.features);
      index_ns += static_cast<int64_t>(timer.Seconds() * 1e9);
    };
    extraction.emplace(seq, options.features, run);
  }
};

// The loop matcher's keyframes' SIFT, kept as the odometry computes it.
std::optional<KeyframeStore> KeyframeStep(const RgbdSequence& seq, const RegisterOptions& options) {
  if (!options.refines() || !options.refine.loops.enabled) return std::nullopt;
  // Without keyframe odometry every frame's SIFT is offered: keep only every interval-th.
  const KeyframeOptions& keyframes = options.refine.loops.keyframes;
  const int interval = keyframes.interval > 0 ? keyframes.interval : options.odometry.keyframes.enabled ? 0 : 5;
  return std::optional<KeyframeStore>(std::in_place, seq, keyframes, options.odometry.sift,
                                      options.cache_dir.empty() ? fs::path() : options.cache_dir / "keyframes.f2ck",
                                      interval);
}

RefineStage Refine(const RegisterResult& r, const RegisterOptions& options, FeatureStep* features,
                   std::optional<KeyframeStore>* store) {
  RefineStage stage;
  stage.index_s = features->index_ns * 1e-9;
  stage.index_bytes = features->index->MemoryBytes();
  stage.peak_memory_bytes_before = PeakResidentBytes();
  Timer keyframe_timer;
  std::vector<Keyframe> keyframes;
  if (*store) {
    keyframes = (*store)->Finish(LoopKeyframes(static_cast<int>(r.sequence.frames.size()),
                                               options.refine.loops.keyframes, OdometryKeyframes(r.odometry)));
    ReferToDepthMoments(r.odometry.depth_from_color, &keyframes);
    stage.keyframes = static_cast<int>(keyframes.size());
    stage.keyframes_decoded = (*store)->computed();
  }
  stage.keyframes_s = keyframe_timer.Seconds();
  if (stage.keyframes_decoded > 0) {
    Log(options, fmt::format("keyframes: {} with SIFT for loop pairs ({} decoded again, {:.1f} s)", stage.keyframes,
                             stage.keyframes_decoded, stage.keyframes_s));
  }
  Trajectory initial = r.odometry.t0;
  if (options.initial_poses) initial.world_from_camera = *options.initial_poses;
  RefineRun run;
  run.quiet = options.quiet;
  run.keep_iterations = options.keep_iterations;
  stage.result = RefineFineToCoarse(*features->index, r.odometry.pairs, initial, *r.sequence.intrinsics, options.refine,
                                    run, std::move(keyframes));
  stage.peak_memory_bytes_after = PeakResidentBytes();
  const double frames = static_cast<double>(r.sequence.frames.size());
  Log(options,
      fmt::format("refinement: {} iterations in {:.1f} s ({:.1f} ms per frame)", stage.result.iterations.size(),
                  stage.result.seconds + stage.index_s, 1000.0 * (stage.result.seconds + stage.index_s) / frames));
  return stage;
}

}  // namespace

void RegisterOptions::Check() const {
  if (threads < 0 || threads > kMaxThreads) {
    ThrowInputError("--threads", fmt::format("must be in [0, {}], got {}", kMaxThreads, threads));
  }
  odometry.Check();
  if (extract_features) features.Check();
  if (refines()) refine.Check();
  if (fuse_mesh) fusion.Check();
  CheckStart(initial_poses.has_value());
}

void RegisterOptions::CheckStart(bool given) const {
  if (given && !refines()) {
    throw InputError(std::string("--initial-trajectory: only the refinement starts from it, and ") +
                     (extract_features ? "--stop-after odometry" : "--no-features") + " skips the refinement");
  }
}

OdometryCounts CountPairs(const Odometry& odometry) {
  OdometryCounts c;
  c.pairs = static_cast<int>(odometry.pairs.size());
  c.keyframes = odometry.timings.keyframes;
  c.min_fitness = odometry.pairs.empty() ? 0.0 : 1.0;
  for (const PairAlignment& p : odometry.pairs) {
    c.sift += p.method == AlignmentMethod::kSift;
    c.track += p.method == AlignmentMethod::kTrack;
    c.icp += p.method == AlignmentMethod::kIcp;
    c.motion_prior += p.method == AlignmentMethod::kMotionPrior;
    c.mean_inliers += p.inliers;
    c.mean_fitness += p.fitness;
    c.min_fitness = std::min(c.min_fitness, p.fitness);
  }
  const double n = std::max<size_t>(odometry.pairs.size(), 1);
  c.mean_inliers /= n;
  c.mean_fitness /= n;
  return c;
}

Trajectory PosesToTrajectory(const Trajectory& like, const PoseVector& poses) {
  Trajectory t;
  t.has_timestamps = like.has_timestamps;
  for (size_t k = 0; k < poses.size(); ++k) t.Add(like.timestamps[k], poses[k].ToRigid());
  return t;
}

RegisterResult Register(RgbdSequence sequence, const RegisterOptions& options) {
  Timer total;
  options.Check();
  std::optional<tbb::global_control> threads;
  if (options.threads > 0) {
    threads.emplace(tbb::global_control::max_allowed_parallelism, options.threads);
    cv::setNumThreads(options.threads);
  }
  const ScopedProgressListener listener(options.progress);
  RegisterResult r;
  r.sequence = std::move(sequence);
  const RgbdSequence& seq = r.sequence;  // the stages below keep references to it
  if (seq.frames.size() < 2) ThrowInputError(seq.root, "registration needs at least 2 frames");
  RequireIntrinsics(seq);
  RequireSomeValidDepth(seq);
  if (options.initial_poses && options.initial_poses->size() != seq.frames.size()) {
    ThrowInputError("--initial-trajectory",
                    fmt::format("{} poses for {} frames", options.initial_poses->size(), seq.frames.size()));
  }

  // 1. Odometry, sharing what it decodes with the features and the loop matcher's keyframes.
  FeatureStep features(seq, options);
  std::optional<KeyframeStore> keyframes = KeyframeStep(seq, options);
  OdometryRun run;
  run.quiet = options.quiet;
  if (!options.cache_dir.empty()) run.cache_file = options.cache_dir / "odometry_pairs.json";
  if (features.extraction) {
    run.on_depth = [&](int frame, const cv::Mat& depth) { features.extraction->Compute(frame, depth); };
  }
  if (keyframes) run.on_sift = [&](int frame, const SiftFeatures& sift) { keyframes->Offer(frame, sift); };
  r.odometry = AlignFrames(seq, options.odometry, run);
  r.odometry_counts = CountPairs(r.odometry);
  const OdometryCounts& c = r.odometry_counts;
  Log(options, fmt::format("odometry: {} frames aligned ({} tracked, {} SIFT, {} ICP, {} motion prior), {} keyframes, "
                           "in {:.1f} s",
                           c.pairs, c.track, c.sift, c.icp, c.motion_prior, c.keyframes, r.odometry.timings.wall));

  // 2. Features: the frames the odometry did not decode (pairs from its cache).
  if (features.extraction) {
    FeatureStage stage;
    features.extraction->Finish(&stage.timings);
    stage.statistics = features.extraction->Statistics();
    Log(options, fmt::format("features: {:.0f} per frame, {:.1f} proxies per frame ({:.1f} s of CPU)",
                             stage.statistics["per_frame"]["features"].get<double>(),
                             stage.statistics["per_frame"]["proxies"].get<double>(),
                             stage.timings.extract + stage.timings.decode));
    r.features = std::move(stage);
  }

  // 3. The refinement, from T0 or the given poses.
  r.poses = r.odometry.t0;
  if (features.index) {
    r.refine = Refine(r, options, &features, &keyframes);
    r.poses = PosesToTrajectory(r.odometry.t0, r.refine->result.poses);
  }

  // 4. The mesh, from the final poses.
  if (options.fuse_mesh) {
    const std::vector<std::optional<Rigid3d>> poses(r.poses.world_from_camera.begin(), r.poses.world_from_camera.end());
    r.fusion = FuseTsdf(seq, poses, options.fusion, options.quiet);
    const FusionTimings& t = r.fusion->timings;
    Log(options, fmt::format("mesh: {} vertices, {} triangles from {} frames in {:.1f} s ({:.1f} ms per frame)",
                             r.fusion->mesh.positions.size(), r.fusion->mesh.faces.size(), t.frames_fused, t.wall,
                             1000.0 * t.wall / std::max(t.frames_fused, 1)));
  }
  r.total_s = total.Seconds();
  r.peak_memory_bytes = PeakResidentBytes();
  return r;
}

RegisterResult Register(const fs::path& input, const IoOptions& io, const RegisterOptions& options) {
  Timer timer;
  io.Check();
  options.Check();  // before minutes of reading a long sequence
  RgbdSequence seq = ReadSequence(input, io);
  const double read_s = timer.Seconds();
  RegisterResult r = Register(std::move(seq), options);
  r.read_s = read_s;
  r.total_s += read_s;
  return r;
}

PoseList PosesFor(const RgbdSequence& sequence, const fs::path& source, const IoOptions& io) {
  std::vector<double> times;
  for (const RgbdFrame& f : sequence.frames) times.push_back(f.timestamp);
  std::optional<RgbdSequence> dataset;
  // A dataset folder gives its ground truth; a file (.conf too) is read as a trajectory.
  const Trajectory given = fs::is_directory(source) || IsRecordingFile(source) ? LoadGroundTruth(source, io, &dataset)
                                                                               : ReadTrajectoryFile(source);
  PoseList poses = PosesForFrames(given, times, FrameNames(sequence), source);
  for (size_t k = 1; k < poses.size(); ++k) {
    const double distance = (poses[k].translation() - poses[k - 1].translation()).norm();
    // Frames closer in time than 1/100 s are taken as 1/100 s apart (time stamps of layouts
    // that have none are frame / fps).
    const double seconds = std::max(times[k] - times[k - 1], 0.01);
    if (distance / seconds > kMaxInitialSpeed) {
      ThrowInputError(source, fmt::format("the poses of frames {} and {} lie {:.3g} m apart, {:.3g} s apart in time: "
                                          "faster than {:g} m/s, not a hand-held camera's path (poses in metres?)",
                                          k - 1, k, distance, times[k] - times[k - 1], kMaxInitialSpeed));
    }
  }
  return poses;
}

}  // namespace f2c
