#include "apps/run_report.h"

#include <fmt/format.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "apps/mesh_views.h"
#include "f2c/features/point_grid.h"
#include "f2c/io/image.h"
#include "f2c/io/correspondences.h"
#include "f2c/report/report.h"
#include "f2c/report/svg_plot.h"
#include "f2c/util/error.h"
#include "f2c/util/file.h"

namespace f2c::app {
namespace fs = std::filesystem;
using nlohmann::json;

std::string InlineImage(const std::string& bytes, const std::string& mime, const std::string& alt, int width) {
  return fmt::format("<img width=\"{}\" alt=\"{}\" src=\"data:{};base64,{}\">\n", width, EscapeXml(alt), mime, Base64(bytes));
}

std::string ThreeJs() {
  // Debian's libjs-three: the library and its orbit controls (UMD builds: they attach to THREE).
  const fs::path dir = F2C_THREE_JS_DIR;
  const fs::path lib = dir / "three.min.js", controls = dir / "examples" / "js" / "controls" / "OrbitControls.js";
  if (!fs::exists(lib) || !fs::exists(controls)) return "";
  return ReadFileToString(lib) + "\n" + ReadFileToString(controls);
}

void AddSliceFrames(const RgbdSequence& seq, int frames, ReportInput* in) {
  const CameraIntrinsics* intrinsics = seq.intrinsics ? &*seq.intrinsics : nullptr;
  if (!intrinsics || seq.frames.empty()) return;
  PointGridOptions grid;
  grid.step = 8;
  grid.normal_radius_pixels = 16;
  const int n = static_cast<int>(seq.frames.size()), count = std::min(n, frames);
  for (int j = 0; j < count; ++j) {
    const RgbdFrame& frame = seq.frames[static_cast<size_t>(j) * n / count];
    try {
      const PointGrid g = BuildPointGrid(LoadDepthMeters(seq, frame), *intrinsics, grid);
      SliceFrame f;
      for (int i = 0; i < static_cast<int>(g.points.size()); ++i) {
        if (!g.Valid(i)) continue;
        f.points.push_back(g.points[i]);
        f.normals.push_back(g.normals[i]);
      }
      in->slice_timestamps.push_back(frame.timestamp);
      in->slice_frames.push_back(std::move(f));
    } catch (const InputError&) {
      // Left out of the slice; the run itself reads every frame and says which is bad.
    }
  }
}

namespace {

std::string Seconds(const json& stage, const char* key = "wall_s") {
  return stage.is_object() && stage.contains(key) ? fmt::format("{:.1f} s", stage[key].get<double>()) : "-";
}

}  // namespace

std::string RegisterReport(const RgbdSequence& seq, const Odometry& odometry, const Trajectory& result, bool refined,
                           const json& run, const PlyPoints* mesh) {
  ReportInput in;
  in.title = "fine2coarse: " + seq.root.filename().string();
  const json& stages = run["stages"];
  const json& od = run["statistics"]["odometry"];
  const double frames = run["frames"].get<double>();
  in.facts = {
      {"input", run["input"].get<std::string>()},
      {"layout", run["layout"].get<std::string>()},
      {"frames", fmt::format("{}", seq.frames.size())},
      {"intrinsics", fmt::format("fx {} fy {} cx {} cy {} ({})", run["intrinsics"]["fx"].get<double>(),
                                 run["intrinsics"]["fy"].get<double>(), run["intrinsics"]["cx"].get<double>(),
                                 run["intrinsics"]["cy"].get<double>(), run["intrinsics"]["source"].get<std::string>())},
      {"versions", fmt::format("fine2coarse {}, OpenCV {}, Eigen {}", run["versions"]["fine2coarse"].get<std::string>(),
                               run["versions"]["opencv"].get<std::string>(), run["versions"]["eigen"].get<std::string>())},
      {"result", refined ? "refined fine-to-coarse" : "T0 (odometry only)"},
      {"odometry", fmt::format("{} ({} keyframes; {} tracked, {} SIFT, {} ICP, {} motion prior)", Seconds(stages["odometry"]),
                               od["keyframes"].get<int>(), od["track"].get<int>(), od["sift"].get<int>(),
                               od["icp"].get<int>(), od["motion_prior"].get<int>())},
      {"features", stages["features"].is_null() ? "-" : fmt::format("{:.1f} s of CPU", stages["features"]["extract_cpu_s"].get<double>())},
      {"refinement", Seconds(stages["refine"])},
      {"mesh", stages["fusion"].is_null() ? "-"
                                          : fmt::format("{} ({} triangles)", Seconds(stages["fusion"]),
                                                        stages["fusion"]["triangles"].get<size_t>())},
      {"total", fmt::format("{:.1f} s, {:.1f} frames/s", run["total_wall_s"].get<double>(),
                            frames / run["total_wall_s"].get<double>())},
      {"peak memory", fmt::format("{:.0f} MiB", run["peak_memory_bytes"].get<double>() / 1048576.0)},
  };
  if (stages["refine"].is_object() && stages["refine"].contains("self_check") &&
      stages["refine"]["self_check"].is_object()) {
    const json& check = stages["refine"]["self_check"];
    in.facts.emplace_back(
        "self-check", fmt::format("held-out features {:.1f} mm RMS off the other frames at the start, {:.1f} at the end; "
                                  "{} iterations undone{}",
                                  1000 * check["before"]["rms_m"].get<double>(), 1000 * check["after"]["rms_m"].get<double>(),
                                  stages["refine"]["self_check_undone_iterations"].get<int>(),
                                  check["undone"].get<bool>() ? "; the run agreed less: its initial poses kept" : ""));
  }
  in.options_json = run["options"].dump(2);
  if (seq.ground_truth) {
    in.ground_truth = *seq.ground_truth;
    in.facts.emplace_back("ground truth", seq.ground_truth_source.string());
  }
  in.estimates.push_back({"T0", odometry.t0, "#d62728"});
  if (refined) in.estimates.push_back({"final", result, "#1f77b4"});
  for (const PairAlignment& p : odometry.pairs) {
    if (p.method == AlignmentMethod::kIcp || p.method == AlignmentMethod::kMotionPrior) {
      in.fallback_times.push_back(seq.frames[p.frame].timestamp);
    }
  }
  for (const RgbdFrame& f : seq.frames) in.frame_timestamps.push_back(f.timestamp);
  if (stages["refine"].is_object()) {
    for (const json& it : stages["refine"]["iterations"]) {
      ReportIteration r;
      r.window_length = it["window_length"].get<double>();
      r.windows = it["windows"].get<int>();
      r.seconds = it["seconds"]["total"].get<double>();
      for (const auto& [term, cost] : it["solve"]["cost_after"].items()) r.cost_after.emplace_back(term, cost.get<double>());
      for (const auto& [type, n] : it["correspondences"]["by_type"].items()) {
        r.correspondences_by_type.emplace_back(type, n.get<int>());
      }
      if (it.contains("self_check") && it["self_check"].is_object()) {
        r.check_before = it["self_check"]["before"]["rms_m"].get<double>();
        r.check_after = it["self_check"]["after"]["rms_m"].get<double>();
        r.undone = it["self_check"]["undone"].get<bool>();
      }
      in.iterations.push_back(std::move(r));
    }
  }
  const fs::path correspondences = fs::is_directory(seq.root) ? seq.root / "correspondences.txt" : fs::path();
  if (!correspondences.empty() && fs::exists(correspondences)) in.correspondences = ReadCorrespondences(correspondences);
  if (mesh && !mesh->faces.empty()) {
    // Up from the horizontal surfaces near the cameras' mean -y; ahead the first camera's view.
    Eigen::Vector3d camera_up = Eigen::Vector3d::Zero();
    for (const auto& p : result.world_from_camera) camera_up -= p.linear().col(1);
    const Eigen::Vector3d up = EstimateUp(*mesh, camera_up), ahead = result.world_from_camera.front().linear().col(2);
    std::string pictures;
    for (const MeshView& view : {TopView(*mesh, up, ahead, 900), PerspectiveView(*mesh, up, ahead, 900, 675)}) {
      std::vector<uchar> jpeg;
      cv::imencode(".jpg", RenderMesh(*mesh, view), jpeg, {cv::IMWRITE_JPEG_QUALITY, 85});
      pictures += InlineImage(std::string(jpeg.begin(), jpeg.end()), "image/jpeg", "the mesh", 640);
    }
    in.extra_html = "<section><h2>Mesh</h2>\n" + pictures + "</section>\n";
    // The 3D view: at most 150,000 of the mesh's vertices, evenly strided.
    const size_t stride = std::max<size_t>(1, (mesh->positions.size() + 149999) / 150000);
    for (size_t i = 0; i < mesh->positions.size(); i += stride) {
      in.points.push_back(mesh->positions[i]);
      if (!mesh->colors.empty()) in.point_colors.push_back(mesh->colors[i]);
    }
    in.up = up.cast<float>();
  } else {
    in.up = -result.world_from_camera.front().linear().col(1).cast<float>();
  }
  for (const auto& p : result.world_from_camera) in.camera_path.push_back(p.translation().cast<float>());
  in.three_js = ThreeJs();
  AddSliceFrames(seq, 150, &in);
  return BuildReport(in);
}

}  // namespace f2c::app
