// fine2coarse evaluate: ATE, RPE and the correspondence metric of a trajectory.

#include <fmt/format.h>

#include <cstdio>
#include <memory>
#include <optional>

#include "apps/commands.h"
#include "apps/fields_cli.h"
#include "f2c/report/embed.h"
#include "f2c/eval/correspondence_error.h"
#include "f2c/eval/mesh_error.h"
#include "f2c/eval/trajectory_error.h"
#include "f2c/io/correspondences.h"
#include "f2c/io/ply.h"
#include "f2c/report/report.h"
#include "f2c/report/svg_plot.h"
#include "f2c/util/error.h"
#include "f2c/util/file.h"

namespace f2c::app {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// A trajectory file; .log / .conf files name frames (by id, by image name), placed at the
// dataset's frame times.
Trajectory LoadEstimate(const fs::path& path, const Trajectory& gt, const std::optional<RgbdSequence>& dataset) {
  Trajectory est = ReadTrajectoryFile(path);
  if (est.has_timestamps || !gt.has_timestamps) return est;
  if (!dataset) {
    ThrowInputError(path,
                    "has no time stamps (.log/.conf); give --ground-truth as the "
                    "dataset folder so frame ids can be placed in time");
  }
  return PlaceAtFrames(std::move(est), *dataset, path);
}

// A row with nothing measured (no pair spans the interval, no pose associated) says n/a: a
// 0.0000 would read as a perfect result.
void PrintStatsRow(const char* name, const char* unit, const ErrorStatistics& s) {
  if (s.count == 0) {
    std::printf("%-24s %-4s %9s %9s %9s %9s %9s %9s %6d\n", name, unit, "n/a", "n/a", "n/a", "n/a", "n/a", "n/a", 0);
    return;
  }
  std::printf("%-24s %-4s %9.4f %9.4f %9.4f %9.4f %9.4f %9.4f %6d\n", name, unit, s.rmse, s.mean, s.median, s.std,
              s.min, s.max, s.count);
}

}  // namespace

int RunEvaluate(const EvaluateArgs& args) {
  args.evaluation.Check();  // before any file is read
  std::optional<RgbdSequence> dataset;
  const Trajectory gt = LoadGroundTruth(args.ground_truth, args.io, &dataset);
  std::vector<double> frame_timestamps;
  if (dataset) {
    for (const RgbdFrame& f : dataset->frames) frame_timestamps.push_back(f.timestamp);
  }
  const Trajectory est = LoadEstimate(args.estimate, gt, dataset);
  // The report's further trajectories, read (and checked) before anything is measured.
  std::vector<std::pair<std::string, Trajectory>> also;
  for (const std::string& spec : args.also) {
    const size_t eq = spec.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == spec.size()) {
      ThrowInputError("--also", fmt::format("'{}' is not NAME=FILE", spec));
    }
    also.emplace_back(spec.substr(0, eq), LoadEstimate(spec.substr(eq + 1), gt, dataset));
  }
  const EvaluationOptions& options = args.evaluation;
  const EvaluationResult r = Evaluate(est, gt, options);

  // The authors' metric on ground-truth correspondences, when there are some.
  fs::path correspondence_file = args.correspondences;
  if (correspondence_file.empty() && fs::is_directory(args.ground_truth) &&
      fs::exists(fs::path(args.ground_truth) / "correspondences.txt")) {
    correspondence_file = fs::path(args.ground_truth) / "correspondences.txt";
  }
  std::optional<CorrespondenceResult> corr;
  std::vector<Correspondence> correspondences;
  if (!correspondence_file.empty()) {
    if (frame_timestamps.empty()) {
      ThrowInputError(correspondence_file, "correspondences name frames: give --ground-truth as the dataset folder");
    }
    // Those between the frames --first/--last/--every keep, numbered as the selection is.
    correspondences =
        SelectFrames(ReadCorrespondences(correspondence_file), args.io.first, args.io.last, args.io.every);
    corr = CorrespondenceError(PosesAtFrames(est, frame_timestamps, args.evaluation.max_time_difference),
                               correspondences, correspondence_file.string());
  }
  // A mesh made with the estimate's poses, moved into the truth's frame by ATE's alignment.
  std::optional<MeshError> mesh_error;
  fs::path surfaces = args.true_surfaces;
  if (!args.mesh.empty()) {
    if (surfaces.empty()) {
      if (!fs::is_directory(args.ground_truth) || !fs::exists(fs::path(args.ground_truth) / "scene.ply")) {
        ThrowInputError(args.mesh,
                        "--mesh needs the true surfaces: --true-surfaces FILE, or --ground-truth as a "
                        "simulated folder (with scene.ply)");
      }
      surfaces = fs::path(args.ground_truth) / "scene.ply";
    }
    PlyPoints mesh = ReadPly(args.mesh);
    const Eigen::Affine3f gt_from_estimate = r.ate.gt_from_estimate.cast<float>();
    for (Eigen::Vector3f& p : mesh.positions) p = gt_from_estimate * p;
    const PlyPoints truth = ReadPly(surfaces);
    if (truth.faces.empty()) ThrowInputError(surfaces, "has no triangles: the true surfaces must be a PLY mesh");
    mesh_error = EvaluateMesh(mesh, truth);
  }
  if (!args.report.empty()) {
    // The page for this estimate alone (register's report also shows T0 and the mesh).
    ReportInput in;
    in.title = "fine2coarse evaluate: " + fs::path(args.estimate).filename().string();
    in.facts = {{"estimate", args.estimate},
                {"ground truth", args.ground_truth},
                {"poses associated", fmt::format("{} of {}", r.ate.translation.count, r.ate.estimated_poses)},
                {"ATE RMSE", fmt::format("{:.4f} m", r.ate.translation.rmse)},
                {"RPE per frame",
                 fmt::format("{:.4f} m, {:.3f} deg", r.rpe_per_frame.translation.rmse, r.rpe_per_frame.rotation.rmse)},
                {"rotation drift",
                 fmt::format("{:.3f} deg RMS over pairs >= {:g} s apart", r.drift.rotation.rmse, r.drift.min_seconds)}};
    if (corr)
      in.facts.emplace_back("correspondences",
                            fmt::format("RMSE {:.4f} m over {}", corr->distance.rmse, corr->distance.count));
    in.ground_truth = gt;
    // The estimate in the palette's first colour, the others in the rest; the estimate last:
    // the page is about it.
    for (size_t i = 0; i < also.size(); ++i) {
      in.estimates.push_back({also[i].first, also[i].second, SeriesColor(1 + static_cast<int>(i % 7))});
    }
    in.estimates.push_back({args.name, est, SeriesColor(0)});
    in.max_time_difference = args.evaluation.max_time_difference;
    if (!correspondence_file.empty() && !frame_timestamps.empty()) {
      in.correspondences = correspondences;
      in.frame_timestamps = frame_timestamps;
    }
    if (dataset && dataset->intrinsics) {
      AddSliceFrames(*dataset, 150, &in);
    } else {
      in.no_slice_reason = dataset ? "The dataset has no intrinsics (TUM folders carry none): pass --intrinsics to "
                                     "draw the slice."
                                   : "--ground-truth is a trajectory file: give the dataset folder to draw the slice.";
    }
    WriteFileAtomic(args.report, BuildReport(in));
  }
  if (args.json) {
    json j = {{"estimate", args.estimate}, {"ground_truth", args.ground_truth}};
    j.update(ToJson(r));
    if (corr) {
      j["correspondences"] = ToJson(*corr);
      j["correspondences"]["file"] = correspondence_file.string();
    }
    if (mesh_error) {
      j["mesh"] = {{"file", args.mesh},
                   {"true_surfaces", surfaces.string()},
                   {"accuracy_m", ToJson(mesh_error->accuracy)},
                   {"accuracy_p90_m", mesh_error->p90},
                   {"far_fraction", mesh_error->far_fraction},
                   {"completeness", mesh_error->completeness},
                   {"completeness_distance_m", MeshErrorOptions().completeness_distance}};
    }
    std::printf("%s\n", j.dump(2).c_str());
    return 0;
  }
  std::printf("%s vs %s: %d of %d poses associated\n", args.estimate.c_str(), args.ground_truth.c_str(),
              r.ate.translation.count, r.ate.estimated_poses);
  std::printf("%-24s %-4s %9s %9s %9s %9s %9s %9s %6s\n", "metric", "unit", "rmse", "mean", "median", "std", "min",
              "max", "n");
  PrintStatsRow("ATE", "m", r.ate.translation);
  PrintStatsRow("RPE/frame translation", "m", r.rpe_per_frame.translation);
  PrintStatsRow("RPE/frame rotation", "deg", r.rpe_per_frame.rotation);
  PrintStatsRow("RPE/s translation", "m", r.rpe_per_second.translation);
  PrintStatsRow("RPE/s rotation", "deg", r.rpe_per_second.rotation);
  PrintStatsRow(fmt::format("rotation drift >={:g} s", r.drift.min_seconds).c_str(), "deg", r.drift.rotation);
  if (r.drift.rotation.count > 0) {
    std::printf("rotation drift: 99%% of the %d pairs within %.3f deg, %.2f%% beyond %g deg\n", r.drift.rotation.count,
                r.drift.p99, 100 * r.drift.share_over, r.drift.threshold_deg);
  }
  if (r.drift_smoothed.smoothing_seconds > 0) {
    PrintStatsRow(fmt::format("...over {:g} s means", r.drift_smoothed.smoothing_seconds).c_str(), "deg",
                  r.drift_smoothed.rotation);
  }
  if (corr) {
    PrintStatsRow("correspondences", "m", corr->distance);
    if (corr->skipped > 0)
      std::printf("(%d correspondences skipped: a frame without an estimated pose)\n", corr->skipped);
  }
  if (mesh_error) {
    PrintStatsRow("mesh to true surface", "m", mesh_error->accuracy);
    std::printf(
        "mesh: 90%% of vertices within %.4f m of the true surfaces (%.1f%% beyond %.2f m); completeness "
        "%.1f%% (true surface within %.2f m of a vertex)\n",
        mesh_error->p90, 100 * mesh_error->far_fraction, MeshErrorOptions().max_distance,
        100 * mesh_error->completeness, MeshErrorOptions().completeness_distance);
  }
  return 0;
}

Subcommand AddEvaluateCommand(CLI::App* app) {
  auto args = std::make_shared<EvaluateArgs>();
  CLI::App* cmd = app->add_subcommand("evaluate",
                                      "ATE (after rigid alignment) and RPE (per frame, per second) of a trajectory, "
                                      "as the TUM benchmark tools compute them");
  cmd->add_option("--estimate", args->estimate, "trajectory: TUM text, .log or .conf")->required();
  cmd->add_option(
         "--ground-truth", args->ground_truth,
         "ground truth: a trajectory file, or a dataset folder or .sens recording that has one (ROS bags carry none)")
      ->required();
  cmd->add_flag("--json", args->json, "print JSON instead of a table");
  cmd->add_option("--correspondences", args->correspondences,
                  "ground-truth correspondences (authors' format) to measure |T_a p_a - T_b p_b| on; "
                  "default: the dataset folder's correspondences.txt, if any");
  cmd->add_option("--mesh", args->mesh,
                  "also measure this mesh (made with the estimate's poses) against the true surfaces: accuracy "
                  "(vertex to surface) and completeness");
  cmd->add_option("--true-surfaces", args->true_surfaces,
                  "the true surfaces as a PLY mesh in the ground truth's frame (default: the simulated folder's "
                  "scene.ply)");
  cmd->add_option("--report", args->report,
                  "also write a page with the plots (trajectories, errors over time and frame gap, correspondence "
                  "errors) to this HTML file");
  cmd->add_option("--name", args->name, "the estimate's name in the report")->capture_default_str();
  cmd->add_option("--also", args->also,
                  "NAME=FILE: another trajectory (T0, a peer's result) drawn beside the estimate in the report; "
                  "repeatable");
  AddFieldFlags(cmd, &args->io);
  AddFieldFlags(cmd, &args->evaluation);  // eval/trajectory_error.h

  return {cmd, [args] { return RunEvaluate(*args); }};
}

}  // namespace f2c::app
