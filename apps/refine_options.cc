#include "apps/refine_options.h"

#include <cmath>
#include <memory>
#include <string>

#include "f2c/util/error.h"

namespace f2c::app {

std::function<void()> AddRefineOptions(CLI::App* cmd, RefineOptions* o) {
  auto add = [&](const std::string& group, const std::string& name, auto* value, const std::string& help) {
    cmd->add_option(name, *value, help)->capture_default_str()->group(group);
  };
  struct Names {
    std::string windows = "frames", thresholds = "age", loss = "cauchy", solve = "one-step", linear = "sparse";
    std::string schedule = "constant";
    double coplanar_angle = 0, sigma = 0, max_angle = 0, covisible = 0;  // degrees
  };
  auto names = std::make_shared<Names>();
  names->windows = WindowModeName(o->windows.mode);
  names->thresholds = ThresholdScheduleName(o->correspondences.schedule);
  names->loss = RobustLossName(o->solver.loss);
  names->solve = o->solver.one_step ? "one-step" : "converge";
  names->linear = o->solver.iterative ? "cgnr" : "sparse";
  constexpr double kDeg = M_PI / 180;
  names->coplanar_angle = o->hierarchy.max_normal_angle / kDeg;
  names->sigma = o->relations.sigma / kDeg;
  names->max_angle = o->relations.max_angle / kDeg;
  names->covisible = o->relations.covisible_tolerance / kDeg;

  const std::string w = "Refinement: windows (paper 4.2)";
  add(w, "--windows", &names->windows, "frames: l_0 consecutive frames, doubling (the paper); path: by camera path (the authors' code)");
  add(w, "--window-frames", &o->windows.initial_frames, "l_0, frames in the first windows");
  add(w, "--window-path", &o->windows.initial_path, "path windows: the first windows' length (m)");
  add(w, "--window-path-cap", &o->windows.path_cap, "path windows: longest window, times the scan's path");
  add(w, "--extra-iterations", &o->windows.extra_iterations, "iterations after one window holds the whole scan");
  add(w, "--polish-iterations", &o->windows.polish_iterations,
      "then this many more with the polish thresholds (beyond the paper; 0: the paper's schedule only)");
  cmd->add_flag("!--no-fine-to-coarse", o->windows.fine_to_coarse,
                "the paper's ablation: every iteration has one window holding the whole scan (as many iterations)")
      ->group(w);

  const std::string p = "Refinement: frame pairs and correspondences (paper 4.2)";
  add(p, "--max-plane-features", &o->features.max_planes, "plane features kept per frame");
  add(p, "--max-edge-features", &o->features.max_edges, "edge features kept per frame");
  cmd->add_flag("--use-shadows", o->features.use_shadows, "also match shadow edges (view-dependent)")->group(p);
  cmd->add_flag("--use-borders", o->features.use_borders, "also match image-border points (view-dependent)")->group(p);
  add(p, "--pair-cell-size", &o->pairs.cell_size, "grid of frames' feature centroids for pair candidates (m)");
  add(p, "--min-overlap", &o->pairs.min_overlap, "pairs: share of one frame's points the other camera sees");
  add(p, "--max-view-angle", &o->pairs.max_view_angle_deg, "pairs: largest angle between optical axes (deg)");
  add(p, "--pairs-per-octave", &o->pairs.per_octave, "partners per frame and power-of-two frame gap");
  add(p, "--long-range-stride", &o->pairs.long_range_stride, "pairs far apart join only every N-th frame (1: all)");
  add(p, "--long-range-gap", &o->pairs.long_range_gap, "...when at least this many frames apart");
  add(p, "--max-distance-initial", &o->correspondences.initial_max_distance, "correspondence distance when a pair first shares a window (m)");
  add(p, "--max-distance-final", &o->correspondences.final_max_distance, "...decreasing linearly to this (m)");
  add(p, "--max-angle-initial", &o->correspondences.initial_max_angle_deg, "normal/direction angle when a pair first shares a window (deg)");
  add(p, "--max-angle-final", &o->correspondences.final_max_angle_deg, "...decreasing linearly to this (deg)");
  add(p, "--threshold-decay", &o->correspondences.decay_iterations, "iterations from the initial to the final thresholds");
  add(p, "--polish-max-distance", &o->correspondences.polish_max_distance, "correspondence distance in polish iterations (m)");
  add(p, "--polish-max-angle", &o->correspondences.polish_max_angle_deg, "normal/direction angle in polish iterations (deg)");
  add(p, "--thresholds", &names->thresholds, "age: by iterations together (the paper); path: per pair by camera path (the authors' code)");
  add(p, "--correspondences-per-frame", &o->correspondences.per_frame, "|C| = this times the frames, per iteration");
  add(p, "--min-correspondences-per-pair", &o->correspondences.min_per_pair, "each pair's share at least this");
  auto& tw = o->correspondences.type_weights;
  add(p, "--weight-plane", &tw[0], "E_C weight of plane correspondences (relative)");
  add(p, "--weight-silhouette", &tw[1], "...of silhouette edges");
  add(p, "--weight-ridge", &tw[4], "...of ridges");
  add(p, "--weight-valley", &tw[5], "...of valleys");

  const std::string e = "Refinement: energy and solver (paper 4.3)";
  add(e, "--weight-correspondence", &o->solver.weight_correspondence, "w_C, E_C's total weight");
  add(e, "--weight-correspondence-initial", &o->weight_correspondence_initial,
      "w_C in the first iteration, linear to --weight-correspondence in the last (the authors: 1500); < 0: constant");
  add(e, "--weight-local", &o->solver.weight_local, "w_L, E_L's total weight");
  add(e, "--weight-inertia", &o->solver.weight_inertia, "w_I, E_I's total weight");
  add(e, "--rotation-lever-arm", &o->solver.rotation_lever_arm, "E_L/E_I compare rotations at this distance (m/rad)");
  add(e, "--local-max-power", &o->local.max_power, "E_L between frames j and j + 2^k, k <= this");
  add(e, "--local-icp-weight", &o->local.icp_weight, "E_L confidence of ICP-fallback pairs (SIFT pairs up to 1)");
  add(e, "--local-prior-weight", &o->local.prior_weight, "E_L confidence of motion-prior pairs");
  add(e, "--local-spans", &o->local.spans,
      "E_L pairs: frames (j, j + 2^k, and each frame with its keyframe) or keyframes (each frame with its "
      "keyframe, and keyframes i, i + 2^k)");
  add(e, "--local-distance-sigma", &o->local.distance_sigma, "E_L weight exp(-d^2/2s^2) by camera distance (m; 0: off)");
  add(e, "--local-loss-scale", &o->solver.local_loss_scale, "Cauchy scale of E_L (m; 0: least squares)");
  add(e, "--weight-match", &o->solver.weight_match, "w_M: each SIFT loop match weighs w_M / frames");
  add(e, "--match-loss-scale", &o->solver.match_loss_scale, "Cauchy scale of E_M (m)");
  add(e, "--loss", &names->loss, "robust loss of E_C: none, huber, cauchy");
  add(e, "--loss-scale", &o->solver.loss_scale, "its scale (m)");
  add(e, "--solver-iterations", &o->solver.max_iterations, "Ceres iterations per refinement iteration");
  add(e, "--solve", &names->solve, "one-step: one Gauss-Newton step per iteration (the authors' code); converge: to convergence");
  add(e, "--linear-solver", &names->linear, "sparse: Cholesky (exact); cgnr: conjugate gradients (memory linear in the constraints)");
  add(e, "--linear-iterations", &o->solver.max_linear_iterations, "cgnr: iterations per step");
  add(e, "--solver-threads", &o->solver.threads, "Ceres threads (0: as --threads)");
  add(e, "--refine-seed", &o->correspondences.seed, "seed of the correspondence sampling");

  const std::string st = "Refinement: planar structure (paper 4.2-4.3)";
  cmd->add_flag("--structure,!--no-structure", o->structure,
                "the planar structural model E_P, E_H, E_G (default off for now, BENCHMARKS.md; --no-structure: the paper's ablation)")
      ->default_str(o->structure ? "true" : "false")
      ->group(st);
  add(st, "--structure-from", &o->structure_first_iteration,
      "the structure from this iteration on (< 0: from the first whose window holds the whole scan)");
  add(st, "--weight-proxy", &o->solver.weight_proxy, "w_P, E_P's total weight (children fit their images)");
  add(st, "--weight-coplanarity", &o->solver.weight_coplanarity, "w_H, E_H's total weight (children coplanar with parents)");
  add(st, "--coplanarity-loss-scale", &o->solver.coplanarity_loss_scale, "Cauchy scale of E_H (m; 0: least squares)");
  add(st, "--weight-relation", &o->solver.weight_relation, "w_G, E_G's total weight (parallel/antiparallel/orthogonal parents)");
  add(st, "--weight-proxy-initial", &o->weight_proxy_initial, "w_P in the first iteration, linear to --weight-proxy; < 0: constant");
  add(st, "--weight-coplanarity-initial", &o->weight_coplanarity_initial, "w_H in the first iteration; < 0: constant");
  add(st, "--weight-relation-initial", &o->weight_relation_initial, "w_G in the first iteration; < 0: constant");
  add(st, "--weight-schedule", &names->schedule,
      "constant: the *-initial options as given; authors: every term's first weight 1.5 times its last (E_C, E_P, E_H, E_G), as their 1500 -> 1000");
  add(st, "--max-proxies", &o->features.max_proxies, "per-image proxies per frame taken as children (largest)");
  add(st, "--min-proxy-inliers", &o->features.min_proxy_inliers, "...with at least this many member cells");
  add(st, "--coplanar-distance", &o->hierarchy.max_distance, "parents: children merge within this plane distance (m)");
  add(st, "--coplanar-angle", &names->coplanar_angle, "...and this normal angle (deg)");
  add(st, "--relation-sigma", &names->sigma, "relations: sigma of the Gaussian weight on the angle (deg)");
  add(st, "--relation-max-angle", &names->max_angle, "relations: admitted within this of 0, 90, 180 deg (deg)");
  add(st, "--relation-min-weight", &o->relations.min_weight, "relations: and with a weight above this");
  cmd->add_flag("!--no-adjacent-relations", o->relations.adjacent_windows,
                "relations within a window only (default: also between adjacent windows)")
      ->group(st);
  add(st, "--relations-per-parent", &o->relations.max_per_parent,
      "each parent keeps its strongest relations to at most this many others (0: all, as the paper)");
  add(st, "--plane-presolve-iterations", &o->solver.plane_presolve_iterations,
      "one-step solves: iterations on the planes alone before the joint step (0: off)");
  add(st, "--relation-covisible-tolerance", &names->covisible,
      "drop a relation when images that see both parents measure their angle farther than this from it (deg; 0: off)");

  const std::string l = "Refinement: SIFT loops and bridges (beyond the paper)";
  auto& lo = o->loops;
  cmd->add_flag("--sift-loops,!--no-sift-loops", lo.enabled, "SIFT re-matching of keyframes (default on; --no-sift-loops: closest features only, as the paper)")
      ->default_str(lo.enabled ? "true" : "false")
      ->group(l);
  add(l, "--keyframe-interval", &lo.keyframes.interval, "every N-th frame keeps its SIFT for re-matching (0: the odometry's keyframes; every 5th without them)");
  add(l, "--keyframe-keypoints", &lo.keyframes.max_keypoints, "SIFT points kept per keyframe");
  add(l, "--loop-candidates", &lo.candidates_per_keyframe, "new loop (and bridge) partners per keyframe and iteration");
  add(l, "--loop-gap", &lo.loop_gap, "loops: keyframes at least this many frames apart");
  add(l, "--bridge-gap", &lo.max_bridge_gap, "bridges over weak odometry: at most this many frames apart");
  add(l, "--loop-max-distance", &lo.max_camera_distance, "loops: cameras at most this far apart now (m)");
  add(l, "--loop-max-view-angle", &lo.max_view_angle_deg, "loops: optical axes within this now (deg)");
  add(l, "--loop-ratio", &lo.ratio, "loops: SIFT ratio test");
  add(l, "--loop-min-inliers", &lo.min_inliers, "loops: RANSAC inliers needed");
  add(l, "--loop-min-fitness", &lo.min_fitness, "loops: share of seen planes the match must explain");
  add(l, "--loop-points", &lo.max_points_per_pair, "E_M points kept per matched pair");
  cmd->add_flag("--spanning-tree,!--no-spanning-tree", lo.spanning_tree, "re-place poses along the most trusted links when loops arrive (default on)")
      ->default_str(lo.spanning_tree ? "true" : "false")
      ->group(l);
  cmd->add_flag("--loop-in-polish", lo.in_polish, "keep E_M in the polish iterations")->group(l);

  return [o, names] {
    o->windows.mode = WindowModeFromName(names->windows);
    o->correspondences.schedule = ThresholdScheduleFromName(names->thresholds);
    o->solver.loss = RobustLossFromName(names->loss);
    if (names->solve != "one-step" && names->solve != "converge") {
      throw InputError("--solve: unknown mode '" + names->solve + "' (one-step, converge)");
    }
    o->solver.one_step = names->solve == "one-step";
    if (names->linear != "sparse" && names->linear != "cgnr") {
      throw InputError("--linear-solver: unknown solver '" + names->linear + "' (sparse, cgnr)");
    }
    o->solver.iterative = names->linear == "cgnr";
    o->hierarchy.max_normal_angle = names->coplanar_angle * kDeg;
    o->relations.sigma = names->sigma * kDeg;
    o->relations.max_angle = names->max_angle * kDeg;
    o->relations.covisible_tolerance = names->covisible * kDeg;
    if (names->schedule == "authors") {
      o->weight_correspondence_initial = 1.5 * o->solver.weight_correspondence;
      o->weight_proxy_initial = 1.5 * o->solver.weight_proxy;
      o->weight_coplanarity_initial = 1.5 * o->solver.weight_coplanarity;
      o->weight_relation_initial = 1.5 * o->solver.weight_relation;
    } else if (names->schedule != "constant") {
      throw InputError("--weight-schedule: unknown schedule '" + names->schedule + "' (constant, authors)");
    }
  };
}

}  // namespace f2c::app
