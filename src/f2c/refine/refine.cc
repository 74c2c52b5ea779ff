#include "f2c/refine/refine.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <tbb/parallel_for.h>

#include <nlohmann/json.hpp>

#include "f2c/util/error.h"
#include "f2c/util/progress.h"
#include "f2c/util/timer.h"

namespace f2c {
namespace {

// How far the poses moved between two sets: the largest and the RMS change of any pose,
// metres and degrees.
void PoseChange(const PoseVector& a, const PoseVector& b, IterationSummary* s) {
  double t = 0, r = 0, t2 = 0, r2 = 0;
  for (size_t k = 0; k < a.size(); ++k) {
    const double dt = (a[k].translation - b[k].translation).norm();
    const double dr = a[k].rotation.angularDistance(b[k].rotation) * 180 / M_PI;
    t = std::max(t, dt);
    r = std::max(r, dr);
    t2 += dt * dt;
    r2 += dr * dr;
  }
  const double n = std::max<double>(1, a.size());
  s->max_translation_change = t;
  s->max_rotation_change_deg = r;
  s->rms_translation_change = std::sqrt(t2 / n);
  s->rms_rotation_change_deg = std::sqrt(r2 / n);
}

// The 90th percentile of the distances between the two sightings of matched points under
// `poses` (metres): large when some loop is not closed yet (single noisy points aside).
double MatchError(const PoseVector& poses, const std::vector<PointMatch>& matches) {
  if (matches.empty()) return 0;
  std::vector<double> e;
  for (const PointMatch& m : matches) {
    const Eigen::Vector3d a = poses[m.frame_a].ToRigid() * m.point_a.cast<double>();
    const Eigen::Vector3d b = poses[m.frame_b].ToRigid() * m.point_b.cast<double>();
    e.push_back((a - b).norm());
  }
  const size_t k = e.size() * 9 / 10;
  std::nth_element(e.begin(), e.begin() + k, e.end());
  return e[k];
}

// A converged loop presolve's cost without E_I (each pose's change from where that solve
// started, so two starts' E_I do not compare).
double GraphCost(const SolveSummary& summary) {
  double cost = 0;
  for (const auto& [term, value] : summary.cost_after) {
    if (term != Term::kI) cost += value;
  }
  return cost;
}

}  // namespace

bool KeepSecondPresolve(const SolveSummary& first, const SolveSummary& second) {
  if (!second.usable) return false;
  if (!first.usable) return true;
  return GraphCost(second) < GraphCost(first);
}

void RefineOptions::Check() const { CheckFields(*this); }

FeatureIndex BuildFeatureIndex(const FeatureSet& features, const FeatureIndexOptions& options) {
  options.Check();
  FeatureIndex index;
  index.frames.resize(features.frames.size());
  tbb::parallel_for(0, static_cast<int>(features.frames.size()),
                    [&](int i) { index.frames[i] = BuildFrameIndex(features.frames[i], options); });
  return index;
}

std::vector<double> CameraPath(const Trajectory& trajectory) {
  std::vector<double> path(trajectory.size(), 0.0);
  for (size_t k = 1; k < trajectory.size(); ++k) {
    path[k] =
        path[k - 1] +
        (trajectory.world_from_camera[k].translation() - trajectory.world_from_camera[k - 1].translation()).norm();
  }
  return path;
}

RefineResult RefineFineToCoarse(const FeatureIndex& index, const std::vector<PairAlignment>& pairs,
                                const Trajectory& t0, const CameraIntrinsics& intrinsics, const RefineOptions& options,
                                const RefineRun& run, std::vector<Keyframe> keyframes) {
  options.Check();
  Timer total;
  const int n = static_cast<int>(t0.size());
  F2C_CHECK(static_cast<int>(index.frames.size()) == n && static_cast<int>(pairs.size()) + 1 == n,
            "one index entry per frame, one odometry pair per frame after the first");
  RefineResult result;
  for (const Rigid3d& pose : t0.world_from_camera) result.poses.push_back(Pose::FromRigid(pose));
  const PoseVector start = result.poses;
  const std::vector<double> path = CameraPath(t0);
  const WindowSchedule schedule(options.windows, path);
  Constraints constraints;
  constraints.local = LocalConstraints(pairs, options.local);
  std::vector<char> unmeasured(n, 0);
  for (const PairAlignment& p : pairs) unmeasured[p.frame] = p.LeftToPrior();
  constraints.steady_motion = SteadyMotionConstraints(t0.timestamps, options.steady_motion, unmeasured);
  std::vector<double> confidence;
  std::vector<int> link_from;  // each frame's odometry reference
  for (const PairAlignment& p : pairs) {
    confidence.push_back(PairConfidence(p, options.local));
    link_from.push_back(p.Reference());
  }
  SiftLoopMatcher loops(std::move(keyframes), confidence, options.loops);
  CorrespondenceOptions correspondence_options = options.correspondences;
  if (options.self_check.enabled) correspondence_options.held_out_every = options.self_check.every;
  CheckPairCache check_cache;  // the self-check's pairs under the poses the next iteration starts from
  int first_structure = options.structure_first_iteration;  // < 0: the first full window
  if (first_structure < 0) {
    first_structure = 0;
    while (first_structure < schedule.iterations() && !schedule.Full(first_structure)) ++first_structure;
  }

  // E_H's weight from how well the views agree on their planes' tilt: measured once, from
  // the initial poses, in windows of l_0 consecutive frames (where they barely drift),
  // whatever the schedule (--structure-from, --no-fine-to-coarse).
  double coplanarity_factor = 1, initial_spread = 0;
  if (options.structure && options.coplanarity_noise_reference_deg > 0) {
    WindowOptions short_windows;
    short_windows.initial_frames = options.windows.initial_frames;
    const WindowSchedule measure(short_windows, std::vector<double>(n, 0.0));
    initial_spread = ChildNormalSpreadDeg(
        BuildProxyHierarchy(measure, 0, index, result.poses, options.hierarchy).structure, result.poses);
    if (initial_spread > 0) {
      const double ratio = options.coplanarity_noise_reference_deg / initial_spread;
      coplanarity_factor = std::min(1.0, ratio * ratio);
    }
  }
  result.initial_child_normal_spread_deg = initial_spread;
  result.coplanarity_noise_factor = coplanarity_factor;

  // The schedule's iterations, then added polish iterations while the poses still move.
  auto more = [&](int it) {
    if (it < schedule.iterations()) return true;
    return it < schedule.iterations() + options.windows.max_added_polish && !result.iterations.empty() &&
           result.iterations.back().rms_translation_change > options.windows.polish_tolerance;
  };
  // Heard by a progress listener only: each iteration has a log line of its own.
  Progress progress("refine", schedule.iterations(), /*quiet=*/true);
  for (int it = 0; more(it); ++it) {
    Timer timer;
    IterationSummary s;
    s.iteration = it;
    s.window_length = schedule.Length(it);
    s.windows = static_cast<int>(schedule.Windows(it).size());
    s.full = schedule.Full(it);
    s.polish = schedule.Polishing(it);
    s.local_constraints = static_cast<int>(constraints.local.size());
    s.velocity_constraints = static_cast<int>(constraints.steady_motion.size());

    const PoseVector before = result.poses;
    // New SIFT loops first: when matches were accepted, the poses they imply (with E_L and
    // E_I, no closest points: those found under the old poses would pull back) are solved
    // to convergence before this iteration's correspondences are searched.
    s.loops = loops.Update(schedule, it, result.poses, index, intrinsics);
    s.seconds_loops = s.loops.seconds;
    constraints.matches = loops.matches();
    // Only loops that disagree with the poses are placed first (the spanning tree, then the
    // converged solve); loops the poses already agree with join this iteration's one step.
    // Re-placing poses that agree would swap refined relative poses for single RANSAC
    // estimates and odometry links: measured, that moved poses by about 0.1 m in every
    // iteration and undid part of the structural model's straightening.
    if (s.loops.accepted > 0 && options.loops.presolve &&
        (LoopDisagreement(result.poses, loops.edges(), s.loops.accepted, options.solver.rotation_lever_arm) >
             options.loops.presolve_min_change ||
         MatchError(result.poses, constraints.matches) > options.loops.presolve_min_change)) {
      Timer presolve;
      SolverOptions graph = options.solver;
      graph.solve = SolveMode::kConverge;
      const Constraints loop_graph{{}, constraints.local, constraints.matches, {}, constraints.steady_motion};
      PoseVector current = result.poses;
      if (options.loops.spanning_tree) {
        result.poses = SpanningTreePoses(result.poses, confidence, loops.edges(), link_from);
      }
      s.presolve = SolvePoses(loop_graph, graph, &result.poses);
      s.presolve_start = options.loops.spanning_tree ? "tree" : "current";
      if (options.loops.spanning_tree && options.loops.better_start) {
        // E_I counts each pose's change from its own start, so the starts compare without it.
        SolveSummary from_current = SolvePoses(loop_graph, graph, &current);
        if (KeepSecondPresolve(s.presolve, from_current)) {
          result.poses = std::move(current);
          s.presolve = from_current;
          s.presolve_start = "current";
        }
      }
      s.seconds_loops += presolve.Seconds();
    }

    Timer stage;
    const std::vector<FramePair> candidates =
        CandidatePairs(schedule, it, index, result.poses, intrinsics, options.pairs);
    s.candidate_pairs = static_cast<int>(candidates.size());
    s.seconds_pairs = stage.Seconds();

    stage.Restart();
    constraints.correspondences = FindCorrespondences(candidates, index, result.poses, schedule, it, path,
                                                      correspondence_options, &s.correspondences);
    if (run.tamper) run.tamper(it, &constraints.correspondences);
    s.seconds_correspondences = stage.Seconds();

    // The structural model under the current poses.
    stage.Restart();
    constraints.structure = {};
    if (options.structure && it >= first_structure) {
      HierarchyOptions hierarchy_options = options.hierarchy;
      if (s.polish && options.polish_coplanar_agreement_scale > 0) {
        hierarchy_options.agreement_scale = options.polish_coplanar_agreement_scale;
      }
      ProxyHierarchy hierarchy = BuildProxyHierarchy(schedule, it, index, result.poses, hierarchy_options);
      hierarchy.structure.relations = DetectRelations(hierarchy, options.relations, &s.relations);
      s.hierarchy = hierarchy.stats;
      s.child_normal_spread_deg = ChildNormalSpreadDeg(hierarchy.structure, result.poses);
      constraints.structure = std::move(hierarchy.structure);
    }
    s.seconds_structure = stage.Seconds();

    SolverOptions solver = options.solver;
    const double t =
        schedule.iterations() > 1 ? std::min(1.0, static_cast<double>(it) / (schedule.iterations() - 1)) : 1.0;
    const double first = options.weight_schedule == WeightSchedule::kAuthors ? 1.5 : 1.0;
    auto scheduled = [t, first](double final_weight) { return final_weight * (first + t * (1.0 - first)); };
    solver.weight_correspondence = scheduled(options.solver.weight_correspondence);
    solver.weight_proxy = scheduled(options.solver.weight_proxy);
    solver.weight_coplanarity = coplanarity_factor * scheduled(options.solver.weight_coplanarity);
    s.coplanarity_noise_factor = coplanarity_factor;
    solver.weight_relation = scheduled(options.solver.weight_relation);
    s.weight_correspondence = solver.weight_correspondence;
    s.weight_proxy = solver.weight_proxy;
    s.weight_coplanarity = solver.weight_coplanarity;
    s.weight_relation = solver.weight_relation;
    stage.Restart();
    // Polish iterations trust the closest features alone: SIFT points (depth read at a
    // keypoint, colour and depth not always registered) are less precise than they are, and
    // by then the loops they closed are within the correspondences' reach (E_M kept there:
    // fr1/desk 0.0256 -> 0.0274 m).
    if (s.polish) constraints.matches.clear();
    // In the polish iterations, the tighter of the two losses: --relation-loss-scale or
    // --coplanarity-loss-scale may already ask for one in every iteration (0: none).
    auto tighten = [&](double polish_scale, double* scale) {
      if (s.polish && polish_scale > 0 && (*scale == 0 || polish_scale < *scale)) *scale = polish_scale;
    };
    tighten(options.polish_relation_loss_scale_deg, &solver.relation_loss_scale_deg);
    tighten(options.polish_coplanarity_loss_scale, &solver.coplanarity_loss_scale);
    tighten(options.polish_local_loss_scale, &solver.measured_local_loss_scale);
    s.relation_loss_scale_deg = solver.relation_loss_scale_deg;
    s.coplanarity_loss_scale = solver.coplanarity_loss_scale;
    s.local_loss_scale = solver.measured_local_loss_scale;
    s.solve = SolvePoses(constraints, solver, &result.poses);
    s.seconds_solve = stage.Seconds();
    if (options.self_check.enabled) {
      stage.Restart();
      std::vector<FramePair> pairs_before = check_cache.For(index, before, intrinsics, options.pairs);
      std::vector<FramePair> pairs_after = WholeScanPairs(index, result.poses, intrinsics, options.pairs);
      const std::vector<FramePair> check_pairs = UnitePairs(pairs_before, pairs_after);
      s.self_check.done = true;
      s.self_check.before =
          ScoreHeldOut(check_pairs, index, before, intrinsics, options.self_check, options.pairs.max_depth);
      s.self_check.after =
          ScoreHeldOut(check_pairs, index, result.poses, intrinsics, options.self_check, options.pairs.max_depth);
      if (s.self_check.after.score > (1 + options.self_check.tolerance) * s.self_check.before.score) {
        s.self_check.undone = true;
        ++result.undone_iterations;
        result.poses = before;
        check_cache.Keep(before, std::move(pairs_before));
      } else {
        check_cache.Keep(result.poses, std::move(pairs_after));
      }
      s.seconds_check = stage.Seconds();
    }
    PoseChange(before, result.poses, &s);
    s.seconds = timer.Seconds();
    if (!run.quiet) {
      spdlog::info(
          "refine {}/{}{}: windows of {:.4g} {} ({}), {} pairs, {} correspondences, {} SIFT loops (+{}), "
          "{} parents, {} relations, "
          "E_C {:.4g} -> {:.4g}, {} Ceres iterations, max change {:.3f} m / {:.2f} deg{}, {:.2f} s",
          it + 1, schedule.iterations(), it < schedule.iterations() ? "" : " (added polish)", s.window_length,
          options.windows.mode == WindowMode::kPath ? "m" : "frames", s.windows, s.candidate_pairs,
          s.correspondences.total(), s.loops.pairs, s.loops.accepted, s.hierarchy.parents, s.relations.total(),
          s.solve.cost_before.count(Term::kC) ? s.solve.cost_before.at(Term::kC) : 0.0,
          s.solve.cost_after.count(Term::kC) ? s.solve.cost_after.at(Term::kC) : 0.0, s.solve.iterations,
          s.max_translation_change, s.max_rotation_change_deg,
          !s.self_check.done ? std::string()
                             : fmt::format(", check {:.4f} -> {:.4f} m{}", s.self_check.before.Rms(),
                                           s.self_check.after.Rms(), s.self_check.undone ? " (undone)" : ""),
          s.seconds);
    }
    result.iterations.push_back(s);
    if (run.keep_iterations) result.iteration_poses.push_back(result.poses);
    if (it < schedule.iterations()) progress.Advance();
  }
  progress.Finish();
  // The whole run against where it started: each iteration may raise the check by up to its
  // tolerance, and so many of them by more. A run that ends further from agreeing than it
  // started gives back its start.
  if (options.self_check.enabled && !result.iterations.empty()) {
    SelfCheckRecord& r = result.self_check;
    const std::vector<FramePair> pairs = UnitePairs(WholeScanPairs(index, start, intrinsics, options.pairs),
                                                    check_cache.For(index, result.poses, intrinsics, options.pairs));
    r.done = true;
    r.before = ScoreHeldOut(pairs, index, start, intrinsics, options.self_check, options.pairs.max_depth);
    r.after = ScoreHeldOut(pairs, index, result.poses, intrinsics, options.self_check, options.pairs.max_depth);
    if (r.after.score > (1 + options.self_check.run_tolerance) * r.before.score) {
      r.undone = true;
      result.poses = start;
      spdlog::warn(
          "self-check: the refinement left overlapping frames agreeing less than at its start ({:.4f} -> "
          "{:.4f} m RMS); the initial poses are kept",
          r.before.Rms(), r.after.Rms());
    }
  }
  result.seconds = total.Seconds();
  return result;
}

nlohmann::json ToJson(const IterationSummary& s) {
  return {
      {"iteration", s.iteration},
      {"window_length", s.window_length},
      {"windows", s.windows},
      {"full", s.full},
      {"polish", s.polish},
      {"candidate_pairs", s.candidate_pairs},
      {"correspondences", ToJson(s.correspondences)},
      {"sift_loops", ToJson(s.loops)},
      {"local_constraints", s.local_constraints},
      {"velocity_constraints", s.velocity_constraints},
      {"weights",
       {{NameOf(Term::kC), s.weight_correspondence},
        {NameOf(Term::kP), s.weight_proxy},
        {NameOf(Term::kH), s.weight_coplanarity},
        {NameOf(Term::kG), s.weight_relation}}},
      {"relation_loss_scale_deg", s.relation_loss_scale_deg},
      {"coplanarity_loss_scale_m", s.coplanarity_loss_scale},
      {"local_loss_scale_m", s.local_loss_scale},
      {"hierarchy", ToJson(s.hierarchy)},
      {"child_normal_spread_deg", s.child_normal_spread_deg},
      {"coplanarity_noise_factor", s.coplanarity_noise_factor},
      {"relations", ToJson(s.relations)},
      {"loop_presolve", s.presolve.termination.empty() ? nlohmann::json(nullptr) : ToJson(s.presolve)},
      {"loop_presolve_start", s.presolve_start.empty() ? nlohmann::json(nullptr) : nlohmann::json(s.presolve_start)},
      {"solve", ToJson(s.solve)},
      {"max_translation_change_m", s.max_translation_change},
      {"max_rotation_change_deg", s.max_rotation_change_deg},
      {"rms_translation_change_m", s.rms_translation_change},
      {"rms_rotation_change_deg", s.rms_rotation_change_deg},
      {"self_check", ToJson(s.self_check)},
      {"seconds",
       {{"pairs", s.seconds_pairs},
        {"correspondences", s.seconds_correspondences},
        {"sift_loops", s.seconds_loops},
        {"structure", s.seconds_structure},
        {"solve", s.seconds_solve},
        {"self_check", s.seconds_check},
        {"total", s.seconds}}}};
}

}  // namespace f2c
