#include "apps/commands.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <Eigen/Core>
#include <cstdio>
#include <optional>
#include <nlohmann/json.hpp>
#include <opencv2/core/version.hpp>
#include <opencv2/imgcodecs.hpp>
#include <tbb/parallel_for.h>

#include "apps/feature_views.h"
#include "f2c/eval/correspondence_error.h"
#include "f2c/eval/trajectory_error.h"
#include "f2c/features/feature_set.h"
#include "f2c/io/conf.h"
#include "f2c/io/image.h"
#include "f2c/io/ply.h"
#include "f2c/sim/simulate.h"
#include "f2c/util/error.h"
#include "f2c/util/file.h"
#include "f2c/util/timer.h"

namespace f2c::app {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

json Versions() {
  return {{"fine2coarse", F2C_VERSION},
          {"opencv", CV_VERSION},
          {"eigen", fmt::format("{}.{}.{}", EIGEN_WORLD_VERSION, EIGEN_MAJOR_VERSION, EIGEN_MINOR_VERSION)}};
}

json ToJson(const IoOptions& io) {
  return {{"intrinsics", io.intrinsics}, {"every", io.every},   {"first", io.first},
          {"last", io.last},             {"max_time_difference", io.max_time_difference},
          {"assumed_fps", io.assumed_fps}, {"sequence", io.sequence}};
}

json PairsToJson(const std::vector<PairAlignment>& pairs) {
  json out = json::array();
  for (const PairAlignment& p : pairs) out.push_back(ToJson(p));
  return out;
}

json PairStatistics(const std::vector<PairAlignment>& pairs) {
  int sift = 0, icp = 0, prior = 0;
  double inliers = 0, fitness = 0, min_fitness = pairs.empty() ? 0.0 : 1.0;
  for (const PairAlignment& p : pairs) {
    sift += p.method == AlignmentMethod::kSift;
    icp += p.method == AlignmentMethod::kIcp;
    prior += p.method == AlignmentMethod::kMotionPrior;
    inliers += p.inliers;
    fitness += p.fitness;
    min_fitness = std::min(min_fitness, p.fitness);
  }
  const double n = std::max<size_t>(pairs.size(), 1);
  return {{"pairs", pairs.size()},   {"sift", sift},
          {"icp", icp},              {"motion_prior", prior},
          {"mean_inliers", inliers / n}, {"mean_fitness", fitness / n},
          {"min_fitness", min_fitness}};
}

}  // namespace

int RunRegister(const RegisterArgs& args) {
  Timer total;
  args.odometry.Check();
  const fs::path out = args.output;
  EnsureWritableDirectory(out);  // fail before minutes of work, not after
  Timer timer;
  const RgbdSequence seq = ReadSequence(args.input, args.io);
  const double read_s = timer.Seconds();
  spdlog::info("{}: {} layout, {} frames", args.input, LayoutName(seq.layout), seq.frames.size());
  if (seq.frames.size() < 2) ThrowInputError(args.input, "registration needs at least 2 frames");

  // Features from the depth images the odometry decodes (no second decode); frames it
  // does not decode (pairs from its cache) are decoded by the extraction itself.
  std::optional<FeatureExtraction> extraction;
  if (args.extract_features) {
    FeatureRun feature_run;
    feature_run.quiet = args.quiet;
    if (args.use_cache) feature_run.cache_file = out / "cache" / "features.f2cf";
    extraction.emplace(seq, args.features, feature_run);
  }
  OdometryRun run;
  run.quiet = args.quiet;
  if (args.use_cache) run.cache_file = out / "cache" / "odometry_pairs.json";
  if (extraction) run.on_depth = [&](int frame, const cv::Mat& depth) { extraction->Compute(frame, depth); };
  const Odometry odometry = AlignConsecutive(seq, args.odometry, run);
  const json stats = PairStatistics(odometry.pairs);
  spdlog::info("odometry: {} pairs ({} SIFT, {} ICP, {} motion prior) in {:.1f} s",
               odometry.pairs.size(), stats["sift"].get<int>(), stats["icp"].get<int>(),
               stats["motion_prior"].get<int>(), odometry.timings.wall);

  json feature_stage = nullptr, feature_stats = nullptr;
  if (extraction) {
    FeatureTimings timings;
    const FeatureSet features = extraction->Finish(&timings);
    feature_stage = ToJson(timings, static_cast<int>(seq.frames.size()));
    feature_stats = FeatureStatistics(features);
    spdlog::info("features: {:.0f} per frame, {:.1f} proxies per frame ({:.1f} s of CPU)",
                 feature_stats["per_frame"]["features"].get<double>(),
                 feature_stats["per_frame"]["proxies"].get<double>(), timings.extract + timings.decode);
  }

  WriteTumTrajectory(out / "trajectory.txt", odometry.t0);
  WriteLogTrajectory(out / "trajectory.log", odometry.t0);
  WriteConf(out / "trajectory.conf", seq, odometry.t0);
  WriteFileAtomic(out / "odometry.json", PairsToJson(odometry.pairs).dump(1) + "\n");

  const CameraIntrinsics& k = *seq.intrinsics;
  json outputs = {"trajectory.txt", "trajectory.log", "trajectory.conf", "odometry.json"};
  const bool features_cached = args.extract_features && args.use_cache;
  if (features_cached) outputs.push_back("cache/features.f2cf");
  const json report = {
      {"input", fs::absolute(args.input).string()},
      {"layout", LayoutName(seq.layout)},
      {"frames", seq.frames.size()},
      {"intrinsics", {{"fx", k.fx}, {"fy", k.fy}, {"cx", k.cx}, {"cy", k.cy}, {"source", seq.intrinsics_source}}},
      {"versions", Versions()},
      {"options",
       {{"io", ToJson(args.io)},
        {"odometry", ToJson(args.odometry)},
        {"features", args.extract_features ? ToJson(args.features) : json(nullptr)},
        {"cache", args.use_cache}}},
      {"stages",
       {{"read", {{"wall_s", read_s}}},
        {"odometry", ToJson(odometry.timings, static_cast<int>(seq.frames.size()))},
        {"features", feature_stage}}},
      {"statistics", {{"odometry", stats}, {"features", feature_stats}}},
      {"total_wall_s", total.Seconds()},
      {"outputs", outputs},
  };
  WriteFileAtomic(out / "run.json", report.dump(2) + "\n");
  std::printf("wrote %s (TUM), trajectory.log, trajectory.conf, odometry.json, run.json%s\n",
              (out / "trajectory.txt").string().c_str(), features_cached ? ", cache/features.f2cf" : "");
  std::printf("%zu frames in %.1f s (%.1f frames/s)\n", seq.frames.size(), total.Seconds(),
              seq.frames.size() / total.Seconds());
  return 0;
}

int RunFeatures(const FeaturesArgs& args) {
  const fs::path out = args.output;
  EnsureWritableDirectory(out);
  const RgbdSequence seq = ReadSequence(args.input, args.io);
  spdlog::info("{}: {} layout, {} frames", args.input, LayoutName(seq.layout), seq.frames.size());
  FeatureRun run;
  run.quiet = args.quiet;
  run.cache_file = out / "features.f2cf";  // the output, reused by the next run with the same inputs
  FeatureTimings timings;
  const FeatureSet set = ExtractFeatures(seq, args.features, run, &timings);
  const int n = static_cast<int>(seq.frames.size());
  if (args.images || args.ply) {
    if (args.images) fs::create_directories(out / "images");
    if (args.ply) fs::create_directories(out / "ply");
    const CameraIntrinsics& k = *seq.intrinsics;
    tbb::parallel_for(0, n, [&](int i) {
      const std::string name = fmt::format("{:06d}", i);
      if (args.ply) WritePly(out / "ply" / (name + ".ply"), FeaturesToPly(set.frames[i]));
      if (args.images) {
        // The picture needs the grid and labels, which the cache does not keep: recompute.
        FeatureDebug debug;
        const FrameFeatures f = ExtractFrameFeatures(LoadDepthMeters(seq, seq.frames[i]), k, args.features, &debug);
        const fs::path path = out / "images" / (name + ".png");
        const fs::path tmp = path.string() + ".tmp.png";
        if (!cv::imwrite(tmp.string(), DrawFeatures(f, debug, k))) ThrowInputError(path, "cannot write image");
        fs::rename(tmp, path);
      }
    });
  }
  const json stats = FeatureStatistics(set);
  const json report = {{"input", fs::absolute(args.input).string()},
                       {"layout", LayoutName(seq.layout)},
                       {"frames", n},
                       {"versions", Versions()},
                       {"options", {{"io", ToJson(args.io)}, {"features", ToJson(args.features)}}},
                       {"timings", ToJson(timings, n)},
                       {"statistics", stats}};
  WriteFileAtomic(out / "features.json", report.dump(2) + "\n");
  std::printf("wrote %s (%d frames)%s%s, features.json\n", run.cache_file.string().c_str(), n,
              args.images ? ", images/" : "", args.ply ? ", ply/" : "");
  std::printf("per frame:");
  for (const auto& [type, count] : stats["per_frame"].items()) std::printf(" %s %.1f", type.c_str(), count.get<double>());
  std::printf("\n%d frames computed, %d from cache; extraction %.2f ms per frame per core\n", timings.frames_computed,
              timings.frames_cached, timings.frames_computed ? 1000.0 * timings.extract / timings.frames_computed : 0.0);
  return 0;
}

namespace {

// Ground truth from a trajectory file or a dataset folder. `frame_timestamps` receives the
// dataset's frame time stamps (to place estimates that carry frame ids, not stamps).
Trajectory LoadGroundTruth(const fs::path& path, std::vector<double>* frame_timestamps) {
  if (fs::is_directory(path) || path.extension() == ".conf") {
    IoOptions io;
    io.check_files = false;
    const RgbdSequence seq = ReadSequence(path, io);
    if (!seq.ground_truth) ThrowInputError(path, "dataset has no ground-truth trajectory");
    for (const RgbdFrame& f : seq.frames) frame_timestamps->push_back(f.timestamp);
    return *seq.ground_truth;
  }
  return ReadTrajectoryFile(path);
}

void PrintStatsRow(const char* name, const char* unit, const ErrorStatistics& s) {
  std::printf("%-22s %-4s %9.4f %9.4f %9.4f %9.4f %9.4f %9.4f %6d\n", name, unit, s.rmse, s.mean,
              s.median, s.std, s.min, s.max, s.count);
}

json StatsJson(const ErrorStatistics& s) {
  return {{"rmse", s.rmse}, {"mean", s.mean}, {"median", s.median}, {"std", s.std},
          {"min", s.min},   {"max", s.max},   {"count", s.count}};
}

}  // namespace

int RunEvaluate(const EvaluateArgs& args) {
  std::vector<double> frame_timestamps;
  Trajectory gt = LoadGroundTruth(args.ground_truth, &frame_timestamps);
  Trajectory est = ReadTrajectoryFile(args.estimate);
  if (!est.has_timestamps && gt.has_timestamps) {
    // .log / .conf estimates carry frame ids: place them at the dataset's frame times.
    if (frame_timestamps.empty()) {
      ThrowInputError(args.estimate, "has no time stamps (.log/.conf); give --ground-truth as the "
                                     "dataset folder so frame ids can be placed in time");
    }
    for (double& id : est.timestamps) {
      const auto i = static_cast<long>(id);
      if (i < 0 || i >= static_cast<long>(frame_timestamps.size())) {
        ThrowInputError(args.estimate, fmt::format("frame id {} but the dataset has {} frames", i,
                                                   frame_timestamps.size()));
      }
      id = frame_timestamps[i];
    }
  }
  EvaluationOptions options;
  options.max_time_difference = args.max_time_difference;
  const EvaluationResult r = Evaluate(est, gt, options);

  // The authors' metric on ground-truth correspondences, when there are some.
  fs::path correspondence_file = args.correspondences;
  if (correspondence_file.empty() && fs::is_directory(args.ground_truth) &&
      fs::exists(fs::path(args.ground_truth) / "correspondences.txt")) {
    correspondence_file = fs::path(args.ground_truth) / "correspondences.txt";
  }
  std::optional<CorrespondenceResult> corr;
  if (!correspondence_file.empty()) {
    if (frame_timestamps.empty()) {
      ThrowInputError(correspondence_file, "correspondences name frames: give --ground-truth as the dataset folder");
    }
    corr = CorrespondenceError(PosesAtFrames(est, frame_timestamps, args.max_time_difference),
                               ReadCorrespondences(correspondence_file), correspondence_file.string());
  }
  if (args.json) {
    json j = {{"estimate", args.estimate},
              {"ground_truth", args.ground_truth},
              {"ate_m", StatsJson(r.ate.translation)},
              {"estimated_poses", r.ate.estimated_poses},
              {"rpe_per_frame", {{"translation_m", StatsJson(r.rpe_per_frame.translation)},
                                 {"rotation_deg", StatsJson(r.rpe_per_frame.rotation)}}},
              {"rpe_per_second", {{"translation_m", StatsJson(r.rpe_per_second.translation)},
                                  {"rotation_deg", StatsJson(r.rpe_per_second.rotation)}}}};
    if (corr) {
      j["correspondences"] = {{"file", correspondence_file.string()},
                              {"distance_m", StatsJson(corr->distance)},
                              {"skipped", corr->skipped}};
    }
    std::printf("%s\n", j.dump(2).c_str());
    return 0;
  }
  std::printf("%s vs %s: %d of %d poses associated\n", args.estimate.c_str(), args.ground_truth.c_str(),
              r.ate.translation.count, r.ate.estimated_poses);
  std::printf("%-22s %-4s %9s %9s %9s %9s %9s %9s %6s\n", "metric", "unit", "rmse", "mean", "median",
              "std", "min", "max", "n");
  PrintStatsRow("ATE", "m", r.ate.translation);
  PrintStatsRow("RPE/frame translation", "m", r.rpe_per_frame.translation);
  PrintStatsRow("RPE/frame rotation", "deg", r.rpe_per_frame.rotation);
  PrintStatsRow("RPE/s translation", "m", r.rpe_per_second.translation);
  PrintStatsRow("RPE/s rotation", "deg", r.rpe_per_second.rotation);
  if (corr) {
    PrintStatsRow("correspondences", "m", corr->distance);
    if (corr->skipped > 0) std::printf("(%d correspondences skipped: a frame without an estimated pose)\n", corr->skipped);
  }
  return 0;
}

int RunSimulate(const SimulateArgs& args) {
  sim::SimulateOptions options;
  options.scene = args.scene;
  options.seed = args.seed;
  options.walk.frames = args.frames;
  options.correspondences = args.correspondences;
  if (args.exact) options.sensor = sim::SensorOptions::Exact();
  options.sensor.radial_distortion = args.depth_distortion;
  Timer timer;
  const Trajectory poses = sim::Simulate(args.output, options, args.quiet);
  double path = 0;
  for (size_t i = 1; i < poses.size(); ++i) {
    path += (poses.world_from_camera[i].translation() - poses.world_from_camera[i - 1].translation()).norm();
  }
  std::printf("wrote %s: %d frames of '%s' (%.1f m of camera path) in %.1f s, TUM layout with "
              "camera-intrinsics.txt, groundtruth.txt, correspondences.txt\n",
              args.output.c_str(), args.frames, args.scene.c_str(), path, timer.Seconds());
  return 0;
}

int RunDemo(const DemoArgs& args) {
  Timer timer;
  const fs::path root = args.output;
  std::printf("fine2coarse demo: simulating an apartment scan, registering it, evaluating it\n");
  SimulateArgs sim_args;
  sim_args.output = (root / "scan").string();
  sim_args.scene = "apartment";
  sim_args.frames = args.frames;
  sim_args.seed = args.seed;
  RunSimulate(sim_args);
  RegisterArgs reg;
  reg.input = sim_args.output;
  reg.output = (root / "registration").string();
  RunRegister(reg);
  EvaluateArgs eval;
  eval.estimate = (fs::path(reg.output) / "trajectory.txt").string();
  eval.ground_truth = sim_args.output;
  RunEvaluate(eval);
  std::printf("\nscan (TUM layout, ground truth): %s\nposes (TUM, .log, .conf), run.json: %s\n"
              "demo took %.1f s\n",
              sim_args.output.c_str(), reg.output.c_str(), timer.Seconds());
  return 0;
}

int RunInfo(const InfoArgs& args) {
  const RgbdSequence seq = ReadSequence(args.input, args.io);
  std::printf("input        %s\n", args.input.c_str());
  std::printf("layout       %s\n", LayoutName(seq.layout).c_str());
  std::printf("frames       %zu (%.3f .. %.3f s)\n", seq.frames.size(), seq.frames.front().timestamp,
              seq.frames.back().timestamp);
  if (seq.intrinsics) {
    const CameraIntrinsics& k = *seq.intrinsics;
    std::printf("intrinsics   fx %.3f fy %.3f cx %.3f cy %.3f (%s)\n", k.fx, k.fy, k.cx, k.cy,
                seq.intrinsics_source.c_str());
  } else {
    std::printf("intrinsics   none in the folder: pass --intrinsics (tum-fr1, tum-fr2, tum-fr3, "
                "primesense, or fx,fy,cx,cy)\n");
  }
  std::printf("depth        %s, %.6g m per unit, invalid values %s\n",
              seq.depth_encoding == DepthEncoding::kSun3dBitRotated ? "SUN3D bit-rotated" : "plain 16-bit",
              seq.depth_scale, fmt::format("{}", fmt::join(seq.invalid_depth_values, ", ")).c_str());
  // Depth range measured on the first frame.
  const cv::Mat depth = LoadDepthMeters(seq, seq.frames.front());
  double lo = 1e9, hi = 0;
  int valid = 0;
  for (int v = 0; v < depth.rows; ++v) {
    for (int u = 0; u < depth.cols; ++u) {
      const float z = depth.at<float>(v, u);
      if (z > 0) {
        lo = std::min<double>(lo, z);
        hi = std::max<double>(hi, z);
        ++valid;
      }
    }
  }
  std::printf("depth range  %.3f .. %.3f m in frame 0 (%.1f%% of pixels valid)\n", valid ? lo : 0.0, hi,
              100.0 * valid / depth.total());
  if (seq.ground_truth) {
    std::printf("ground truth %zu poses (%s)\n", seq.ground_truth->size(), seq.ground_truth_source.string().c_str());
  } else {
    std::printf("ground truth none\n");
  }
  return 0;
}

}  // namespace f2c::app
