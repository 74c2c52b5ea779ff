#include "f2c/pipeline/outputs.h"

#include <fmt/format.h>

#include <Eigen/Core>
#include <opencv2/core/version.hpp>

#include "f2c/io/conf.h"
#include "f2c/io/ply.h"
#include "f2c/io/trajectory.h"
#include "f2c/pipeline/register_report.h"
#include "f2c/refine/local_alignment.h"
#include "f2c/util/fields_json.h"
#include "f2c/util/file.h"

namespace f2c {
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

json ToJson(const OdometryCounts& c) {
  return {{"pairs", c.pairs},
          {"sift", c.sift},
          {"track", c.track},
          {"icp", c.icp},
          {"motion_prior", c.motion_prior},
          {"mean_inliers", c.mean_inliers},
          {"mean_fitness", c.mean_fitness},
          {"min_fitness", c.min_fitness},
          {"keyframes", c.keyframes}};
}

json ToJson(const RefineStage& s, const RegisterOptions& options, int frames) {
  const RefineResult& r = s.result;
  json iterations = json::array();
  for (const IterationSummary& it : r.iterations) iterations.push_back(ToJson(it));
  return {{"wall_s", s.wall_s()},
          {"index_s", s.index_s},
          {"keyframes_s", s.keyframes_s},
          {"ms_per_frame", 1000.0 * s.wall_s() / frames},
          {"index_bytes", s.index_bytes},
          {"peak_memory_bytes_before", s.peak_memory_bytes_before},
          {"peak_memory_bytes_after", s.peak_memory_bytes_after},
          {"initial", options.initial_name},
          {"initial_child_normal_spread_deg", r.initial_child_normal_spread_deg},
          {"coplanarity_noise_factor", r.coplanarity_noise_factor},
          {"self_check_undone_iterations", r.undone_iterations},
          {"self_check", ToJson(r.self_check)},
          {"iterations", iterations}};
}

bool KeyframesCached(const RegisterOptions& options) {
  return options.refines() && options.refine.loops.enabled && !options.cache_dir.empty();
}

std::vector<std::string> OutputNames(const fs::path& dir, const RegisterResult& result, const RegisterOptions& options,
                                     const OutputOptions& outputs) {
  std::vector<std::string> names = {"trajectory.txt", "trajectory.log", "trajectory.conf", "trajectory_t0.txt",
                                    "odometry.json"};
  if (outputs.iterations && result.refine) names.push_back("iterations/");
  if (result.fusion) names.push_back("mesh.ply");
  if (outputs.report) names.push_back("report.html");
  // The caches, when they are the output folder's own.
  if (!options.cache_dir.empty() && options.cache_dir.lexically_normal() == (dir / "cache").lexically_normal()) {
    if (options.extract_features) names.push_back("cache/features.f2cf");
    if (KeyframesCached(options)) names.push_back("cache/keyframes.f2ck");
  }
  return names;
}

}  // namespace

json Versions() {
  return {{"fine2coarse", F2C_VERSION},
          {"opencv", CV_VERSION},
          {"eigen", fmt::format("{}.{}.{}", EIGEN_WORLD_VERSION, EIGEN_MAJOR_VERSION, EIGEN_MINOR_VERSION)}};
}

json RunJson(const RegisterResult& r, const RegisterOptions& options, const OutputOptions& outputs,
             const std::vector<std::string>& names) {
  const RgbdSequence& seq = r.sequence;
  const CameraIntrinsics& k = *seq.intrinsics;
  const int frames = static_cast<int>(seq.frames.size());
  json run_options = outputs.options;
  if (run_options.is_null()) {
    run_options = {{"io", FieldsToJson(outputs.io)},
                   {"odometry", FieldsToJson(options.odometry)},
                   {"features", options.extract_features ? FieldsToJson(options.features) : json(nullptr)},
                   {"refine", r.refine ? FieldsToJson(options.refine) : json(nullptr)},
                   {"fusion", options.fuse_mesh ? FieldsToJson(options.fusion) : json(nullptr)},
                   {"cache", !options.cache_dir.empty()}};
  }
  return {
      {"input", outputs.input.empty() ? fs::absolute(seq.root).string() : outputs.input},
      {"layout", LayoutName(seq.layout)},
      {"frames", seq.frames.size()},
      {"intrinsics",
       {{"fx", k.fx},
        {"fy", k.fy},
        {"cx", k.cx},
        {"cy", k.cy},
        {"distortion", k.distortion},
        {"source", seq.intrinsics_source}}},
      {"versions", Versions()},
      {"preset", NameOf(options.preset)},
      {"options", run_options},
      {"stages",
       {{"read", {{"wall_s", r.read_s}}},
        {"odometry", ToJson(r.odometry.timings, frames)},
        {"features", r.features ? ToJson(r.features->timings, frames) : json(nullptr)},
        {"refine", r.refine ? ToJson(*r.refine, options, frames) : json(nullptr)},
        {"fusion", r.fusion ? ToJson(r.fusion->timings, r.fusion->mesh) : json(nullptr)}}},
      {"statistics",
       {{"odometry", ToJson(r.odometry_counts)}, {"features", r.features ? r.features->statistics : json(nullptr)}}},
      {"result", r.refine ? "refined" : "t0"},
      {"total_wall_s", r.total_s},
      {"peak_memory_bytes", r.peak_memory_bytes},
      {"outputs", names},
  };
}

json RunJson(const RegisterResult& r, const RegisterOptions& options, const OutputOptions& outputs) {
  return RunJson(r, options, outputs, OutputNames(fs::path(), r, options, outputs));
}

std::vector<std::string> WriteOutputs(const fs::path& dir, const RegisterResult& r, const RegisterOptions& options,
                                      const OutputOptions& outputs) {
  fs::create_directories(dir);
  // trajectory.txt goes last, and an older one first: a run stopped while writing never
  // leaves a trajectory.txt beside files of another run.
  std::error_code ignored;
  fs::remove(dir / "trajectory.txt", ignored);
  WriteTumTrajectory(dir / "trajectory_t0.txt", r.odometry.t0);
  WriteLogTrajectory(dir / "trajectory.log", r.poses);
  WriteConf(dir / "trajectory.conf", r.sequence, r.poses);
  WriteFileAtomic(dir / "odometry.json", PairsToJson(r.odometry.pairs, options.refine.local).dump(1) + "\n");
  if (outputs.iterations && r.refine) {
    fs::create_directories(dir / "iterations");
    const std::vector<PoseVector>& poses = r.refine->result.iteration_poses;
    for (size_t i = 0; i < poses.size(); ++i) {
      WriteTumTrajectory(dir / "iterations" / fmt::format("iteration_{:02d}.txt", i + 1),
                         PosesToTrajectory(r.odometry.t0, poses[i]));
    }
  }
  if (r.fusion) WritePly(dir / "mesh.ply", r.fusion->mesh);
  const std::vector<std::string> names = OutputNames(dir, r, options, outputs);
  const json run = RunJson(r, options, outputs, names);
  WriteFileAtomic(dir / "run.json", run.dump(2) + "\n");
  if (outputs.report)
    WriteFileAtomic(dir / "report.html", RegisterReport(r, run["input"].get<std::string>(), run["options"].dump(2)));
  WriteTumTrajectory(dir / "trajectory.txt", r.poses);
  return names;
}

}  // namespace f2c
