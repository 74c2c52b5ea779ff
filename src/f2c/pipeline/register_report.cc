#include "f2c/io/image_write.h"
#include "f2c/pipeline/register_report.h"

#include <fmt/format.h>

#include <filesystem>

#include "f2c/io/correspondences.h"
#include "f2c/pipeline/outputs.h"
#include "f2c/report/embed.h"
#include "f2c/report/mesh_views.h"
#include "f2c/report/report.h"

namespace f2c {
namespace fs = std::filesystem;

namespace {

std::string Seconds(double s) { return fmt::format("{:.1f} s", s); }

std::vector<std::pair<std::string, std::string>> Facts(const RegisterResult& r, const std::string& input) {
  const RgbdSequence& seq = r.sequence;
  const CameraIntrinsics& k = *seq.intrinsics;
  const nlohmann::json versions = Versions();
  const OdometryCounts& od = r.odometry_counts;
  std::vector<std::pair<std::string, std::string>> facts = {
      {"input", input},
      {"layout", LayoutName(seq.layout)},
      {"frames", fmt::format("{}", seq.frames.size())},
      {"intrinsics", fmt::format("fx {} fy {} cx {} cy {} ({})", k.fx, k.fy, k.cx, k.cy, seq.intrinsics_source)},
      {"versions", fmt::format("fine2coarse {}, OpenCV {}, Eigen {}", versions["fine2coarse"].get<std::string>(),
                               versions["opencv"].get<std::string>(), versions["eigen"].get<std::string>())},
      {"result", r.refine ? "refined fine-to-coarse" : "T0 (odometry only)"},
      {"odometry",
       fmt::format("{} ({} keyframes; {} tracked, {} SIFT, {} ICP, {} motion prior)", Seconds(r.odometry.timings.wall),
                   od.keyframes, od.track, od.sift, od.icp, od.motion_prior)},
      {"features", r.features ? fmt::format("{:.1f} s of CPU", r.features->timings.extract) : "-"},
      {"refinement", r.refine ? Seconds(r.refine->wall_s()) : "-"},
      {"mesh",
       r.fusion ? fmt::format("{} ({} triangles)", Seconds(r.fusion->timings.wall), r.fusion->mesh.faces.size()) : "-"},
      {"total", fmt::format("{:.1f} s, {:.1f} frames/s", r.total_s, seq.frames.size() / r.total_s)},
      {"peak memory", fmt::format("{:.0f} MiB", r.peak_memory_bytes / 1048576.0)},
  };
  if (r.refine && r.refine->result.self_check.done) {
    const RefineResult& refined = r.refine->result;
    facts.emplace_back(
        "self-check",
        fmt::format("held-out features {:.1f} mm RMS off the other frames at the start, {:.1f} at the end; "
                    "{} iterations undone{}",
                    1000 * refined.self_check.before.Rms(), 1000 * refined.self_check.after.Rms(),
                    refined.undone_iterations,
                    refined.self_check.undone ? "; the run agreed less: its initial poses kept" : ""));
  }
  return facts;
}

ReportIteration ToReport(const IterationSummary& it) {
  ReportIteration r;
  r.window_length = it.window_length;
  r.windows = it.windows;
  r.seconds = it.seconds;
  for (const auto& [term, cost] : it.solve.cost_after) r.cost_after.emplace_back(NameOf(term), cost);
  for (int t = 0; t < kFeatureTypeCount; ++t) {
    r.correspondences_by_type.emplace_back(FeatureTypeName(static_cast<FeatureType>(t)), it.correspondences.by_type[t]);
  }
  if (it.self_check.done) {
    r.check_before = it.self_check.before.Rms();
    r.check_after = it.self_check.after.Rms();
    r.undone = it.self_check.undone;
  }
  return r;
}

// Pictures of the mesh and its points for the 3D view; the world's up.
void AddMesh(const PlyPoints& mesh, const Trajectory& poses, ReportInput* in) {
  // Up from the horizontal surfaces near the cameras' mean -y; ahead the first camera's view.
  Eigen::Vector3d camera_up = Eigen::Vector3d::Zero();
  for (const auto& p : poses.world_from_camera) camera_up -= p.linear().col(1);
  const Eigen::Vector3d up = EstimateUp(mesh, camera_up), ahead = poses.world_from_camera.front().linear().col(2);
  std::string pictures;
  for (const MeshView& view : {TopView(mesh, up, ahead, 900), PerspectiveView(mesh, up, ahead, 900, 675)}) {
    pictures += InlineImage(EncodeJpeg(RenderMesh(mesh, view), 85), "image/jpeg", "the mesh", 640);
  }
  in->extra_html = "<section><h2>Mesh</h2>\n" + pictures + "</section>\n";
  // The 3D view: at most 150,000 of the mesh's vertices, evenly strided.
  const size_t stride = std::max<size_t>(1, (mesh.positions.size() + 149999) / 150000);
  for (size_t i = 0; i < mesh.positions.size(); i += stride) {
    in->points.push_back(mesh.positions[i]);
    if (!mesh.colors.empty()) in->point_colors.push_back(mesh.colors[i]);
  }
  in->up = up.cast<float>();
}

}  // namespace

std::string RegisterReport(const RegisterResult& r, const std::string& input, const std::string& options_json) {
  const RgbdSequence& seq = r.sequence;
  ReportInput in;
  in.title = "fine2coarse: " + seq.root.filename().string();
  in.facts = Facts(r, input);
  in.options_json = options_json;
  if (seq.ground_truth) {
    in.ground_truth = *seq.ground_truth;
    in.facts.emplace_back("ground truth", seq.ground_truth_source.string());
  }
  in.estimates.push_back({"T0", r.odometry.t0, "#d62728"});
  if (r.refine) in.estimates.push_back({"final", r.poses, "#1f77b4"});
  for (const PairAlignment& p : r.odometry.pairs) {
    if (p.method == AlignmentMethod::kIcp || p.method == AlignmentMethod::kMotionPrior) {
      in.fallback_times.push_back(seq.frames[p.frame].timestamp);
    }
  }
  for (const RgbdFrame& f : seq.frames) in.frame_timestamps.push_back(f.timestamp);
  if (r.refine) {
    for (const IterationSummary& it : r.refine->result.iterations) in.iterations.push_back(ToReport(it));
  }
  const fs::path correspondences = fs::is_directory(seq.root) ? seq.root / "correspondences.txt" : fs::path();
  if (!correspondences.empty() && fs::exists(correspondences))
    in.correspondences = ReadCorrespondences(correspondences);
  if (r.fusion && !r.fusion->mesh.faces.empty()) {
    AddMesh(r.fusion->mesh, r.poses, &in);
  } else {
    in.up = -r.poses.world_from_camera.front().linear().col(1).cast<float>();
  }
  for (const auto& p : r.poses.world_from_camera) in.camera_path.push_back(p.translation().cast<float>());
  in.three_js = ThreeJs();
  AddSliceFrames(seq, 150, &in);
  return BuildReport(in);
}

}  // namespace f2c
