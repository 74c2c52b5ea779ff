// fine2coarse register: a dataset folder to camera poses.

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <cstdio>
#include <map>
#include <memory>
#include <atomic>
#include <optional>
#include <sstream>
#include <opencv2/core/utility.hpp>
#include <tbb/global_control.h>

#include "apps/commands.h"
#include "apps/common.h"
#include "apps/fields_cli.h"
#include "apps/refine_options.h"
#include "apps/run_report.h"
#include "f2c/features/feature_set.h"
#include "f2c/io/conf.h"
#include "f2c/io/trajectory.h"
#include "f2c/util/error.h"
#include "f2c/util/fields_json.h"
#include "f2c/util/file.h"
#include "f2c/util/memory.h"
#include "f2c/util/timer.h"

namespace f2c::app {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// Each frame's alignment, with `confidence`: the weight E_L gives it (refine/local_alignment.h).
json PairsToJson(const std::vector<PairAlignment>& pairs, const LocalAlignmentOptions& local) {
  json out = json::array();
  for (const PairAlignment& p : pairs) {
    json j = ToJson(p);
    j["confidence"] = PairConfidence(p, local);
    out.push_back(std::move(j));
  }
  return out;
}

json PairStatistics(const std::vector<PairAlignment>& pairs) {
  int sift = 0, track = 0, icp = 0, prior = 0;
  double inliers = 0, fitness = 0, min_fitness = pairs.empty() ? 0.0 : 1.0;
  for (const PairAlignment& p : pairs) {
    sift += p.method == AlignmentMethod::kSift;
    track += p.method == AlignmentMethod::kTrack;
    icp += p.method == AlignmentMethod::kIcp;
    prior += p.method == AlignmentMethod::kMotionPrior;
    inliers += p.inliers;
    fitness += p.fitness;
    min_fitness = std::min(min_fitness, p.fitness);
  }
  const double n = std::max<size_t>(pairs.size(), 1);
  return {{"pairs", pairs.size()},   {"sift", sift},  {"track", track},
          {"icp", icp},              {"motion_prior", prior},
          {"mean_inliers", inliers / n}, {"mean_fitness", fitness / n},
          {"min_fitness", min_fitness}};
}

struct RegisterFlags {
  bool no_cache = false, no_features = false, no_mesh = false, no_report = false;
  std::string stop_after = "refine";
};

void WriteTrajectories(const fs::path& out, const RgbdSequence& seq, const Trajectory& trajectory) {
  WriteTumTrajectory(out / "trajectory.txt", trajectory);
  WriteLogTrajectory(out / "trajectory.log", trajectory);
  WriteConf(out / "trajectory.conf", seq, trajectory);
}

Trajectory ToTrajectory(const Trajectory& like, const PoseVector& poses) {
  Trajectory t;
  t.has_timestamps = like.has_timestamps;
  for (size_t k = 0; k < poses.size(); ++k) t.Add(like.timestamps[k], poses[k].ToRigid());
  return t;
}

}  // namespace

int RunRegister(const RegisterArgs& args) {
  Timer total;
  // More would not run faster on any machine, and TBB fails outright on some huge counts.
  constexpr int kMaxThreads = 1024;
  if (args.threads < 0 || args.threads > kMaxThreads) {
    ThrowInputError("--threads", fmt::format("must be in [0, {}], got {}", kMaxThreads, args.threads));
  }
  std::optional<tbb::global_control> threads;
  if (args.threads > 0) {
    threads.emplace(tbb::global_control::max_allowed_parallelism, args.threads);
    cv::setNumThreads(args.threads);
  }
  args.odometry.Check();
  const fs::path out = args.output;
  Timer timer;
  // The input first (a bad one leaves no output folder behind), then the output folder:
  // both fail in seconds, before minutes of work.
  const RgbdSequence seq = ReadSequence(args.input, args.io);
  const double read_s = timer.Seconds();
  // A given start for the refinement, checked against the frames before any work.
  std::optional<std::vector<Rigid3d, Eigen::aligned_allocator<Rigid3d>>> initial_poses;
  if (!args.initial_trajectory.empty() && args.run_refinement) {
    std::vector<double> times;
    for (const RgbdFrame& f : seq.frames) times.push_back(f.timestamp);
    const fs::path source = args.initial_trajectory;
    std::optional<RgbdSequence> dataset;
    // A dataset folder gives its ground truth; a file (.conf too) is read as a trajectory.
    const Trajectory given = fs::is_directory(source) ? LoadGroundTruth(source, args.io, &dataset)
                                                      : ReadTrajectoryFile(source);
    initial_poses = PosesForFrames(given, times, source);
  }
  const OutputFolder output_folder(out);  // a run stopped by an error leaves no empty folders
  spdlog::info("{}: {} layout, {} frames", args.input, LayoutName(seq.layout), seq.frames.size());
  if (seq.frames.size() < 2) ThrowInputError(args.input, "registration needs at least 2 frames");

  // Features from the depth images the odometry decodes (no second decode); frames it
  // does not decode (pairs from its cache) are decoded by the extraction itself.
  // Each frame's features go straight into the refinement's compact index (or are dropped
  // when it does not run): the full set is never held, and the cache is streamed to disk.
  std::optional<FeatureExtraction> extraction;
  std::optional<FeatureIndex> index;
  std::atomic<int64_t> index_ns{0};
  if (args.extract_features) {
    if (args.run_refinement) {
      index.emplace();
      index->frames.resize(seq.frames.size());
    }
    FeatureRun feature_run;
    feature_run.quiet = args.quiet;
    if (args.use_cache) feature_run.cache_file = out / "cache" / "features.f2cf";
    feature_run.on_frame = [&](int frame, FrameFeatures&& features) {
      if (!index) return;
      Timer timer;
      index->frames[frame] = BuildFrameIndex(features, args.refine.features);
      index_ns += static_cast<int64_t>(timer.Seconds() * 1e9);
    };
    extraction.emplace(seq, args.features, feature_run);
  }
  OdometryRun run;
  run.quiet = args.quiet;
  if (args.use_cache) run.cache_file = out / "cache" / "odometry_pairs.json";
  if (extraction) run.on_depth = [&](int frame, const cv::Mat& depth) { extraction->Compute(frame, depth); };
  // Keyframes' SIFT for the refinement's loop matcher, kept as the odometry computes it.
  std::optional<KeyframeStore> keyframe_store;
  if (args.run_refinement && args.extract_features && args.refine.loops.enabled) {
    // Without keyframe odometry every frame's SIFT is offered: keep only every interval-th.
    const int interval = args.refine.loops.keyframes.interval > 0 ? args.refine.loops.keyframes.interval
                         : args.odometry.keyframes.enabled        ? 0
                                                                  : 5;
    keyframe_store.emplace(seq, args.refine.loops.keyframes, args.odometry.sift,
                           args.use_cache ? out / "cache" / "keyframes.f2ck" : fs::path(), interval);
    run.on_sift = [&](int frame, const SiftFeatures& sift) { keyframe_store->Offer(frame, sift); };
  }
  const Odometry odometry = AlignFrames(seq, args.odometry, run);
  json stats = PairStatistics(odometry.pairs);
  stats["keyframes"] = odometry.timings.keyframes;  // 0 without keyframe odometry
  spdlog::info("odometry: {} frames aligned ({} tracked, {} SIFT, {} ICP, {} motion prior), {} keyframes, in {:.1f} s",
               odometry.pairs.size(), stats["track"].get<int>(), stats["sift"].get<int>(), stats["icp"].get<int>(),
               stats["motion_prior"].get<int>(), odometry.timings.keyframes,
               odometry.timings.wall);

  json feature_stage = nullptr, feature_stats = nullptr;
  if (extraction) {
    FeatureTimings timings;
    extraction->Finish(&timings);
    feature_stage = ToJson(timings, static_cast<int>(seq.frames.size()));
    feature_stats = extraction->Statistics();
    spdlog::info("features: {:.0f} per frame, {:.1f} proxies per frame ({:.1f} s of CPU)",
                 feature_stats["per_frame"]["features"].get<double>(),
                 feature_stats["per_frame"]["proxies"].get<double>(), timings.extract + timings.decode);
  }
  const double index_s = index_ns * 1e-9;  // CPU seconds, inside the feature extraction
  const int64_t peak_before_refine = PeakResidentBytes();

  WriteTumTrajectory(out / "trajectory_t0.txt", odometry.t0);
  Trajectory result = odometry.t0;
  json refine_stage = nullptr;
  if (index) {
    RefineRun refine_run;
    refine_run.quiet = args.quiet;
    refine_run.keep_iterations = args.save_iterations;
    Timer keyframe_timer;
    std::vector<Keyframe> keyframes;
    if (keyframe_store) {
      keyframes = keyframe_store->Finish(LoopKeyframes(static_cast<int>(seq.frames.size()), args.refine.loops.keyframes,
                                                       OdometryKeyframes(odometry)));
    }
    const double keyframe_s = keyframe_timer.Seconds();
    if (keyframe_store && keyframe_store->computed() > 0) {
      spdlog::info("keyframes: {} with SIFT for loop pairs ({} decoded again, {:.1f} s)", keyframes.size(),
                   keyframe_store->computed(), keyframe_s);
    }
    Trajectory initial = odometry.t0;
    if (initial_poses) initial.world_from_camera = *initial_poses;
    const RefineResult refined = RefineFineToCoarse(*index, odometry.pairs, initial, *seq.intrinsics, args.refine,
                                                    refine_run, std::move(keyframes));
    result = ToTrajectory(odometry.t0, refined.poses);
    json iterations = json::array();
    for (const IterationSummary& s : refined.iterations) iterations.push_back(ToJson(s));
    refine_stage = {{"wall_s", refined.seconds + index_s + keyframe_s},
                    {"index_s", index_s},
                    {"keyframes_s", keyframe_s},
                    {"ms_per_frame", 1000.0 * (refined.seconds + index_s + keyframe_s) / seq.frames.size()},
                    {"index_bytes", index->MemoryBytes()},
                    {"peak_memory_bytes_before", peak_before_refine},
                    {"peak_memory_bytes_after", PeakResidentBytes()},
                    {"initial", args.initial_trajectory.empty() ? "T0" : args.initial_trajectory},
                    {"initial_child_normal_spread_deg", refined.initial_child_normal_spread_deg},
                    {"coplanarity_noise_factor", refined.coplanarity_noise_factor},
                    {"self_check_undone_iterations", refined.undone_iterations},
                    {"self_check", ToJson(refined.self_check)},
                    {"iterations", iterations}};
    spdlog::info("refinement: {} iterations in {:.1f} s ({:.1f} ms per frame)", refined.iterations.size(),
                 refined.seconds + index_s, 1000.0 * (refined.seconds + index_s) / seq.frames.size());
    if (args.save_iterations) {
      fs::create_directories(out / "iterations");
      for (size_t i = 0; i < refined.iteration_poses.size(); ++i) {
        WriteTumTrajectory(out / "iterations" / fmt::format("iteration_{:02d}.txt", i + 1),
                           ToTrajectory(odometry.t0, refined.iteration_poses[i]));
      }
    }
  }
  WriteTrajectories(out, seq, result);
  WriteFileAtomic(out / "odometry.json", PairsToJson(odometry.pairs, args.refine.local).dump(1) + "\n");
  json fusion_stage = nullptr;
  std::optional<PlyPoints> mesh;
  if (args.fuse_mesh) {
    // The final poses (T0 with --stop-after odometry) into the mesh.
    std::vector<std::optional<Rigid3d>> poses(result.world_from_camera.begin(), result.world_from_camera.end());
    FusionResult fused = FuseTsdf(seq, poses, args.fusion, args.quiet);
    WritePly(out / "mesh.ply", fused.mesh);
    fusion_stage = ToJson(fused.timings, fused.mesh);
    spdlog::info("mesh: {} vertices, {} triangles from {} frames in {:.1f} s ({:.1f} ms per frame)",
                 fused.mesh.positions.size(), fused.mesh.faces.size(), fused.timings.frames_fused, fused.timings.wall,
                 1000.0 * fused.timings.wall / std::max(fused.timings.frames_fused, 1));
    if (args.write_report) mesh = std::move(fused.mesh);  // for its pictures and 3D view
  }

  const CameraIntrinsics& k = *seq.intrinsics;
  json outputs = {"trajectory.txt", "trajectory.log", "trajectory.conf", "trajectory_t0.txt", "odometry.json"};
  if (args.save_iterations && index) outputs.push_back("iterations/");
  if (args.fuse_mesh) outputs.push_back("mesh.ply");
  if (args.write_report) outputs.push_back("report.html");
  const bool features_cached = args.extract_features && args.use_cache;
  if (features_cached) outputs.push_back("cache/features.f2cf");
  if (keyframe_store && args.use_cache) outputs.push_back("cache/keyframes.f2ck");
  const json report = {
      {"input", fs::absolute(args.input).string()},
      {"layout", LayoutName(seq.layout)},
      {"frames", seq.frames.size()},
      {"intrinsics",
       {{"fx", k.fx}, {"fy", k.fy}, {"cx", k.cx}, {"cy", k.cy}, {"distortion", k.distortion},
        {"source", seq.intrinsics_source}}},
      {"versions", Versions()},
      {"options",
       {{"io", FieldsToJson(args.io)},
        {"odometry", FieldsToJson(args.odometry)},
        {"features", args.extract_features ? FieldsToJson(args.features) : json(nullptr)},
        {"refine", index ? FieldsToJson(args.refine) : json(nullptr)},
        {"fusion", args.fuse_mesh ? FieldsToJson(args.fusion) : json(nullptr)},
        {"cache", args.use_cache}}},
      {"stages",
       {{"read", {{"wall_s", read_s}}},
        {"odometry", ToJson(odometry.timings, static_cast<int>(seq.frames.size()))},
        {"features", feature_stage},
        {"refine", refine_stage},
        {"fusion", fusion_stage}}},
      {"statistics", {{"odometry", stats}, {"features", feature_stats}}},
      {"result", index ? "refined" : "t0"},
      {"total_wall_s", total.Seconds()},
      {"peak_memory_bytes", PeakResidentBytes()},
      {"outputs", outputs},
  };
  WriteFileAtomic(out / "run.json", report.dump(2) + "\n");
  if (args.write_report) {
    WriteFileAtomic(out / "report.html", RegisterReport(seq, odometry, result, index.has_value(), report,
                                                        mesh ? &*mesh : nullptr));
  }
  std::printf("wrote %s (TUM; %s), trajectory.log, trajectory.conf, trajectory_t0.txt, odometry.json, run.json%s%s%s%s\n",
              (out / "trajectory.txt").string().c_str(), index ? "refined" : "T0", args.fuse_mesh ? ", mesh.ply" : "",
              args.write_report ? ", report.html" : "",
              args.save_iterations && index ? ", iterations/" : "",
              features_cached ? (keyframe_store ? ", cache/features.f2cf, cache/keyframes.f2ck" : ", cache/features.f2cf") : "");
  std::printf("%zu frames in %.1f s (%.1f frames/s)\n", seq.frames.size(), total.Seconds(),
              seq.frames.size() / total.Seconds());
  return 0;
}

Subcommand AddRegisterCommand(CLI::App* app) {
  auto args = std::make_shared<RegisterArgs>();
  CLI::App* cmd = app->add_subcommand(
      "register", "align the frames (keyframe odometry: tracking, SIFT + 3D RANSAC, ICP fallback) into T0, refine "
                  "it fine-to-coarse, fuse a mesh and write OUTDIR/trajectory.txt (TUM), trajectory.log, "
                  "trajectory.conf, trajectory_t0.txt, mesh.ply, odometry.json, run.json");
  cmd->add_option("INPUT", args->input, "dataset folder (TUM, 7-Scenes/3DMatch, Redwood/Open3D, SUN3D) or .conf")
      ->required();
  cmd->add_option("-o,--output", args->output, "output folder")->required();
  AddFieldFlags(cmd, &args->io);
  AddFieldFlags(cmd, &args->odometry);  // odometry/odometry.h
  AddFieldFlags(cmd, &args->features);
  auto flags = std::make_shared<RegisterFlags>();
  cmd->add_option("--stop-after", flags->stop_after,
                  "odometry: T0 is the result (no refinement, no mesh); refine: the fine-to-coarse refinement, "
                  "then the mesh")
      ->check(CLI::IsMember({"odometry", "refine"}))
      ->capture_default_str();
  const std::function<void()> refine_names = AddRefineOptions(cmd, &args->refine);
  auto write_config = std::make_shared<std::string>();
  cmd->add_option("--write-config", *write_config, "write this run's options (all of them) to FILE as TOML, for --config")
      ->group("Output");
  cmd->add_option("--initial-trajectory", args->initial_trajectory,
                  "refine from these poses instead of T0: a trajectory (TUM by time stamp, .log or .conf in order), or a dataset "
                  "folder's ground truth")
      ->type_name("FILE")
      ->group("Refinement: windows (paper 4.2)");
  cmd->add_flag("--save-iterations", args->save_iterations, "write each refinement iteration's trajectory to OUTDIR/iterations/");
  AddFieldFlags(cmd, &args->fusion);
  cmd->add_flag("--no-mesh", flags->no_mesh, "do not fuse the frames into OUTDIR/mesh.ply");
  cmd->add_flag("--no-report", flags->no_report, "do not write OUTDIR/report.html");
  cmd->add_flag("--no-features", flags->no_features, "skip the feature extraction, and so the refinement (T0 only)");
  cmd->add_flag("--no-cache", flags->no_cache, "ignore and do not write OUTDIR/cache");
  cmd->add_option("--threads", args->threads, "worker threads (0: all cores, at most 1024; results are the same for any)")
      ->capture_default_str();
  cmd->add_flag("-q,--quiet", args->quiet, "no progress output");

  return {cmd, [app, args, flags, refine_names, write_config] {
    refine_names();
    if (!write_config->empty()) {
      // Every option with its value (defaults too), so the file reproduces the run.
      std::string text;
      std::istringstream lines(app->config_to_str(true, false));
      for (std::string line; std::getline(lines, line);) {
        if (line.find("write-config=") == std::string::npos) text += line + "\n";
      }
      WriteFileAtomic(*write_config, text);
      spdlog::info("options written to {}", *write_config);
    }
    args->run_refinement = flags->stop_after == "refine" && !flags->no_features;
    if (!args->initial_trajectory.empty() && !args->run_refinement) {
      throw InputError(std::string("--initial-trajectory: only the refinement starts from it, and ") +
                       (flags->no_features ? "--no-features" : "--stop-after odometry") + " skips the refinement");
    }
    // Every stage's options, once, before the input is read or minutes of odometry run.
    args->io.Check();
    args->odometry.Check();
    if (!flags->no_features) args->features.Check();
    if (args->run_refinement) args->refine.Check();
    args->fuse_mesh = !flags->no_mesh && flags->stop_after != "odometry";
    args->write_report = !flags->no_report;
    if (args->fuse_mesh) args->fusion.Check();
    args->extract_features = !flags->no_features;
    args->use_cache = !flags->no_cache;
    if (args->quiet) spdlog::set_level(spdlog::level::warn);
    return RunRegister(*args);
  }};
}

}  // namespace f2c::app
