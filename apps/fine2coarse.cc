// fine2coarse: RGB-D sequence -> camera poses (and, as the pipeline grows, mesh and report).
//
//   fine2coarse register INPUT -o OUTDIR [options]
//   fine2coarse features INPUT -o OUTDIR [--images] [--ply]
//   fine2coarse evaluate --estimate FILE --ground-truth FILE_OR_DATASET [--json]
//   fine2coarse info INPUT
//
// Exit status: 0 success, 1 bad input (one line naming the file), 2 bad usage.

#include <CLI/CLI.hpp>
#include <cstdio>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include "apps/commands.h"
#include "f2c/util/error.h"

namespace {

void AddFrameSelection(CLI::App* cmd, f2c::IoOptions* io) {
  cmd->add_option("--intrinsics", io->intrinsics,
                  "fx,fy,cx,cy or a preset: tum-fr1, tum-fr2, tum-fr3, primesense (TUM folders "
                  "carry none; overrides a dataset's own)");
  cmd->add_option("--every", io->every, "use every N-th frame")->check(CLI::PositiveNumber);
  cmd->add_option("--first", io->first, "first frame (0-based)")->check(CLI::NonNegativeNumber);
  cmd->add_option("--last", io->last, "last frame, inclusive (-1: the end)");
  cmd->add_option("--sequence", io->sequence,
                  "7-Scenes/3DMatch: read only this seq-XX subfolder (default: all, joined)");
}

void AddFeatureOptions(CLI::App* cmd, f2c::FeatureOptions* f) {
  const std::string group = "Features (paper 4.1; DESIGN.md section 2)";
  auto add = [&](const std::string& name, auto* value, const std::string& help) {
    cmd->add_option(name, *value, help)->capture_default_str()->group(group);
  };
  add("--feature-step", &f->grid.step, "pixels per grid cell of the feature extraction");
  add("--feature-max-depth", &f->grid.max_depth, "farthest depth used for features (m)");
  add("--normal-radius", &f->grid.normal_radius, "normals: neighbours within this distance (m)");
  add("--normal-radius-pixels", &f->grid.normal_radius_pixels, "normals: neighbours within this many pixels");
  add("--min-spacing", &f->min_spacing, "features of one type at least this far apart (m)");
  add("--proxy-min-points", &f->proxies.min_points, "smallest planar proxy (grid cells)");
  add("--proxy-max-distance", &f->proxies.max_distance, "clusters merge when their planes are this close (m)");
  add("--proxy-max-angle", &f->proxies.max_normal_angle, "...and their normals this close (radians)");
  add("--edge-jump-fraction", &f->edge_jump_fraction, "contours: depth jump above this fraction of depth...");
  add("--edge-min-jump", &f->edge_min_jump, "...and at least this many metres");
  add("--crease-angle", &f->crease_angle, "ridges/valleys where proxies meet at more than this (radians)");
  add("--depth-noise-a", &f->proxies.sensor_sigma_a,
      "sensor depth noise sigma(z) = a + b (z - 0.4)^2 (m; Kinect v1 defaults; 0 and 0 for noise-free depth)");
  add("--depth-noise-b", &f->proxies.sensor_sigma_b, "...its b (m per m^2)");
  cmd->add_flag("--bilateral", f->grid.bilateral, "bilateral-filter depth first (noisy sensors, e.g. SUN3D)")
      ->group(group);
}

}  // namespace

int main(int argc, char** argv) {
  // Logs go to stderr, so stdout carries only results (tables, JSON).
  spdlog::set_default_logger(spdlog::stderr_color_mt("fine2coarse"));
  spdlog::set_pattern("[%H:%M:%S] %v");
  CLI::App app{"fine2coarse: fine-to-coarse global registration of RGB-D scans"};
  app.require_subcommand(1);
  app.set_version_flag("--version", F2C_VERSION);

  f2c::app::RegisterArgs reg;
  CLI::App* reg_cmd = app.add_subcommand(
      "register", "align consecutive frames (SIFT + 3D RANSAC, ICP fallback) into T0 and write "
                  "OUTDIR/trajectory.txt (TUM), trajectory.log, trajectory.conf, odometry.json, run.json");
  reg_cmd->add_option("INPUT", reg.input, "dataset folder (TUM, 7-Scenes/3DMatch, Redwood/Open3D, SUN3D) or .conf")
      ->required();
  reg_cmd->add_option("-o,--output", reg.output, "output folder")->required();
  AddFrameSelection(reg_cmd, &reg.io);
  auto& od = reg.odometry;
  reg_cmd->add_option("--seed", od.seed, "seed of all random choices")->capture_default_str();
  reg_cmd->add_option("--min-depth", od.sift.min_depth, "nearest valid depth (m)")->capture_default_str();
  reg_cmd->add_option("--max-depth", od.sift.max_depth, "farthest valid depth (m)")->capture_default_str();
  reg_cmd->add_option("--sift-downscale", od.sift.downscale,
                      "detect SIFT on the colour image shrunk by this factor (faster, coarser)")
      ->capture_default_str();
  reg_cmd->add_option("--ratio", od.ratio, "SIFT ratio test")->capture_default_str();
  reg_cmd->add_option("--relaxed-ratio", od.relaxed_ratio, "ratio used when few matches pass")
      ->capture_default_str();
  reg_cmd->add_option("--ransac-threshold", od.ransac.inlier_threshold, "RANSAC inlier distance (m)")
      ->capture_default_str();
  reg_cmd->add_option("--ransac-iterations", od.ransac.max_iterations, "RANSAC iteration cap")
      ->capture_default_str();
  reg_cmd->add_option("--robust-scale", od.ransac.robust_scale,
                      "Cauchy scale (m) of the final reweighted refit on RANSAC inliers (0: off)")
      ->capture_default_str();
  reg_cmd->add_option("--min-fitness", od.min_fitness,
                      "SIFT answers whose depth overlap is lower are checked against ICP")
      ->capture_default_str();
  reg_cmd->add_option("--min-inliers", od.min_inliers, "fewer SIFT inliers fall back to ICP")
      ->capture_default_str();
  AddFeatureOptions(reg_cmd, &reg.features);
  bool no_icp = false, no_cache = false, no_features = false;
  reg_cmd->add_flag("--no-features", no_features, "skip the feature extraction (T0 only)");
  reg_cmd->add_flag("--no-icp-fallback", no_icp, "never use depth-only ICP");
  reg_cmd->add_flag("--no-cache", no_cache, "ignore and do not write OUTDIR/cache");
  reg_cmd->add_flag("-q,--quiet", reg.quiet, "no progress output");

  f2c::app::FeaturesArgs feat;
  CLI::App* feat_cmd = app.add_subcommand(
      "features", "extract planar proxies and plane/edge features of every frame into "
                  "OUTDIR/features.f2cf (reused when inputs and options match) and features.json");
  feat_cmd->add_option("INPUT", feat.input, "dataset folder or .conf")->required();
  feat_cmd->add_option("-o,--output", feat.output, "output folder")->required();
  AddFrameSelection(feat_cmd, &feat.io);
  AddFeatureOptions(feat_cmd, &feat.features);
  feat_cmd->add_flag("--images", feat.images, "also draw each frame's proxies and features to OUTDIR/images/");
  feat_cmd->add_flag("--ply", feat.ply, "also write each frame's features as points to OUTDIR/ply/");
  feat_cmd->add_flag("-q,--quiet", feat.quiet, "no progress output");

  f2c::app::EvaluateArgs eval;
  CLI::App* eval_cmd = app.add_subcommand(
      "evaluate", "ATE (after rigid alignment) and RPE (per frame, per second) of a trajectory, "
                  "as the TUM benchmark tools compute them");
  eval_cmd->add_option("--estimate", eval.estimate, "trajectory: TUM text, .log or .conf")->required();
  eval_cmd->add_option("--ground-truth", eval.ground_truth,
                       "ground truth: a trajectory file, or a dataset folder that has one")
      ->required();
  eval_cmd->add_flag("--json", eval.json, "print JSON instead of a table");
  eval_cmd->add_option("--correspondences", eval.correspondences,
                       "ground-truth correspondences (authors' format) to measure |T_a p_a - T_b p_b| on; "
                       "default: the dataset folder's correspondences.txt, if any");
  eval_cmd->add_option("--max-time-difference", eval.max_time_difference,
                       "association window (s)")
      ->capture_default_str();

  f2c::app::SimulateArgs sim;
  CLI::App* sim_cmd = app.add_subcommand(
      "simulate", "render a synthetic multi-room RGB-D scan with exact ground truth (TUM layout)");
  sim_cmd->add_option("--scene", sim.scene, "two-rooms, apartment or corridor")->capture_default_str();
  sim_cmd->add_option("--frames", sim.frames, "frames at 30 Hz")->capture_default_str()->check(CLI::PositiveNumber);
  sim_cmd->add_option("--seed", sim.seed, "furniture, walk and noise")->capture_default_str();
  sim_cmd->add_option("-o,--output", sim.output, "output folder")->required();
  sim_cmd->add_option("--correspondences", sim.correspondences, "ground-truth correspondences to write")
      ->capture_default_str();
  sim_cmd->add_flag("--exact", sim.exact, "no sensor noise, holes or blur");
  sim_cmd->add_option("--depth-distortion", sim.depth_distortion,
                      "low-frequency depth distortion k: z *= 1 + k r^2 (0: off)")
      ->capture_default_str();
  sim_cmd->add_flag("-q,--quiet", sim.quiet, "no progress output");

  f2c::app::DemoArgs demo;
  CLI::App* demo_cmd = app.add_subcommand(
      "demo", "no download needed: simulate an apartment scan, register it, evaluate it");
  demo_cmd->add_option("-o,--output", demo.output, "output folder")->capture_default_str();
  demo_cmd->add_option("--frames", demo.frames, "frames to simulate")->capture_default_str()->check(CLI::PositiveNumber);
  demo_cmd->add_option("--seed", demo.seed, "seed")->capture_default_str();

  f2c::app::InfoArgs info;
  CLI::App* info_cmd = app.add_subcommand("info", "what a dataset folder holds: layout, frames, "
                                                  "intrinsics, depth range, ground truth");
  info_cmd->add_option("INPUT", info.input, "dataset folder or .conf")->required();
  AddFrameSelection(info_cmd, &info.io);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return 2;
  }
  if (reg.quiet || sim.quiet || feat.quiet) spdlog::set_level(spdlog::level::warn);
  reg.odometry.icp_fallback = !no_icp;
  reg.extract_features = !no_features;
  reg.use_cache = !no_cache;
  try {
    if (*reg_cmd) return f2c::app::RunRegister(reg);
    if (*feat_cmd) return f2c::app::RunFeatures(feat);
    if (*eval_cmd) return f2c::app::RunEvaluate(eval);
    if (*info_cmd) return f2c::app::RunInfo(info);
    if (*sim_cmd) return f2c::app::RunSimulate(sim);
    if (*demo_cmd) return f2c::app::RunDemo(demo);
  } catch (const f2c::InputError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "internal error: %s\n", e.what());
    return 3;
  }
  return 2;
}
