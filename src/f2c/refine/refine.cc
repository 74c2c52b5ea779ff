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

namespace {

// Algorithm 1 of the paper, its state and its steps: RefineFineToCoarse below reads as the
// algorithm, each step a member function.
class FineToCoarse {
 public:
  FineToCoarse(const FeatureIndex& index, const std::vector<PairAlignment>& pairs, const Trajectory& t0,
               const CameraIntrinsics& intrinsics, const RefineOptions& options, const RefineRun& run,
               std::vector<Keyframe> keyframes);

  // The schedule's iterations, then added polish iterations while the poses still move.
  bool More(int it) const;
  IterationSummary Start(int it) const;
  void CloseLoops(int it, IterationSummary* s);
  void FindCorrespondences(int it, IterationSummary* s);
  void BuildStructure(int it, IterationSummary* s);
  void Solve(int it, IterationSummary* s);
  void CheckIteration(const PoseVector& before, IterationSummary* s);
  void Finish(const PoseVector& before, const Timer& timer, IterationSummary s);
  void CheckWholeRun();
  int scheduled_iterations() const { return schedule_.iterations(); }
  const PoseVector& poses() const { return result_.poses; }
  RefineResult TakeResult() { return std::move(result_); }

 private:
  static std::vector<double> PairConfidences(const std::vector<PairAlignment>& pairs, const RefineOptions& options);
  void MeasureCoplanarityNoise();
  SolverOptions IterationSolverOptions(int it, IterationSummary* s) const;
  void Log(const IterationSummary& s) const;

  const FeatureIndex& index_;
  const CameraIntrinsics& intrinsics_;
  const RefineOptions& options_;
  const RefineRun& run_;
  const int n_;
  const std::vector<double> path_;
  const WindowSchedule schedule_;
  const std::vector<double> confidence_;  // each odometry pair's (refine/local_alignment.h)
  std::vector<int> link_from_;            // each frame's odometry reference
  SiftLoopMatcher loops_;
  CorrespondenceOptions correspondence_options_;
  Constraints constraints_;
  CheckPairCache check_cache_;  // the self-check's pairs under the poses the next iteration starts from
  int first_structure_ = 0;     // the first iteration with the structural model
  double coplanarity_factor_ = 1;
  PoseVector start_;
  RefineResult result_;
};

std::vector<double> FineToCoarse::PairConfidences(const std::vector<PairAlignment>& pairs,
                                                  const RefineOptions& options) {
  std::vector<double> confidence;
  for (const PairAlignment& p : pairs) confidence.push_back(PairConfidence(p, options.local));
  return confidence;
}

FineToCoarse::FineToCoarse(const FeatureIndex& index, const std::vector<PairAlignment>& pairs, const Trajectory& t0,
                           const CameraIntrinsics& intrinsics, const RefineOptions& options, const RefineRun& run,
                           std::vector<Keyframe> keyframes)
    : index_(index),
      intrinsics_(intrinsics),
      options_(options),
      run_(run),
      n_(static_cast<int>(t0.size())),
      path_(CameraPath(t0)),
      schedule_(options.windows, path_),
      confidence_(PairConfidences(pairs, options)),
      loops_(std::move(keyframes), confidence_, options.loops),
      correspondence_options_(options.correspondences) {
  for (const Rigid3d& pose : t0.world_from_camera) result_.poses.push_back(Pose::FromRigid(pose));
  start_ = result_.poses;
  // E_L's constraints from the odometry once, E_V's from the time stamps.
  constraints_.local = LocalConstraints(pairs, options.local);
  std::vector<char> unmeasured(n_, 0);
  for (const PairAlignment& p : pairs) unmeasured[p.frame] = p.LeftToPrior();
  constraints_.steady_motion = SteadyMotionConstraints(t0.timestamps, options.steady_motion, unmeasured);
  for (const PairAlignment& p : pairs) link_from_.push_back(p.Reference());
  if (options.self_check.enabled) correspondence_options_.held_out_every = options.self_check.every;
  first_structure_ = options.structure_first_iteration;  // < 0: the first full window
  if (first_structure_ < 0) {
    first_structure_ = 0;
    while (first_structure_ < schedule_.iterations() && !schedule_.Full(first_structure_)) ++first_structure_;
  }
  MeasureCoplanarityNoise();
}

// E_H's weight from how well the views agree on their planes' tilt: measured once, from the
// initial poses, in windows of l_0 consecutive frames (where they barely drift), whatever
// the schedule (--structure-from, --no-fine-to-coarse).
void FineToCoarse::MeasureCoplanarityNoise() {
  double spread = 0;
  if (options_.structure && options_.coplanarity_noise_reference_deg > 0) {
    WindowOptions short_windows;
    short_windows.initial_frames = options_.windows.initial_frames;
    const WindowSchedule measure(short_windows, std::vector<double>(n_, 0.0));
    spread = ChildNormalSpreadDeg(BuildProxyHierarchy(measure, 0, index_, result_.poses, options_.hierarchy).structure,
                                  result_.poses);
    if (spread > 0) {
      const double ratio = options_.coplanarity_noise_reference_deg / spread;
      coplanarity_factor_ = std::min(1.0, ratio * ratio);
    }
  }
  result_.initial_child_normal_spread_deg = spread;
  result_.coplanarity_noise_factor = coplanarity_factor_;
}

bool FineToCoarse::More(int it) const {
  if (it < schedule_.iterations()) return true;
  return it < schedule_.iterations() + options_.windows.max_added_polish && !result_.iterations.empty() &&
         result_.iterations.back().rms_translation_change > options_.windows.polish_tolerance;
}

IterationSummary FineToCoarse::Start(int it) const {
  IterationSummary s;
  s.iteration = it;
  s.window_length = schedule_.Length(it);
  s.windows = static_cast<int>(schedule_.Windows(it).size());
  s.full = schedule_.Full(it);
  s.polish = schedule_.Polishing(it);
  s.local_constraints = static_cast<int>(constraints_.local.size());
  s.velocity_constraints = static_cast<int>(constraints_.steady_motion.size());
  return s;
}

// New SIFT loops first: when matches were accepted, the poses they imply (with E_L and E_I,
// no closest points: those found under the old poses would pull back) are solved to
// convergence before this iteration's correspondences are searched.
void FineToCoarse::CloseLoops(int it, IterationSummary* s) {
  s->loops = loops_.Update(schedule_, it, result_.poses, index_, intrinsics_);
  s->seconds_loops = s->loops.seconds;
  constraints_.matches = loops_.matches();
  // Only loops that disagree with the poses are placed first (the spanning tree, then the
  // converged solve); loops the poses already agree with join this iteration's one step.
  // Re-placing poses that agree would swap refined relative poses for single RANSAC
  // estimates and odometry links: measured, that moved poses by about 0.1 m in every
  // iteration and undid part of the structural model's straightening.
  const SiftLoopOptions& o = options_.loops;
  if (s->loops.accepted == 0 || !o.presolve) return;
  const bool disagree = LoopDisagreement(result_.poses, loops_.edges(), s->loops.accepted,
                                         options_.solver.rotation_lever_arm) > o.presolve_min_change ||
                        MatchError(result_.poses, constraints_.matches) > o.presolve_min_change;
  if (!disagree) return;
  Timer presolve;
  SolverOptions graph = options_.solver;
  graph.solve = SolveMode::kConverge;
  const Constraints loop_graph{{}, constraints_.local, constraints_.matches, {}, constraints_.steady_motion};
  PoseVector current = result_.poses;
  if (o.spanning_tree) result_.poses = SpanningTreePoses(result_.poses, confidence_, loops_.edges(), link_from_);
  s->presolve = SolvePoses(loop_graph, graph, &result_.poses);
  s->presolve_start = o.spanning_tree ? "tree" : "current";
  if (o.spanning_tree && o.better_start) {
    // E_I counts each pose's change from its own start, so the starts compare without it.
    SolveSummary from_current = SolvePoses(loop_graph, graph, &current);
    if (KeepSecondPresolve(s->presolve, from_current)) {
      result_.poses = std::move(current);
      s->presolve = from_current;
      s->presolve_start = "current";
    }
  }
  s->seconds_loops += presolve.Seconds();
}

// The frame pairs that share a window and can overlap, and their closest compatible
// features (E_C).
void FineToCoarse::FindCorrespondences(int it, IterationSummary* s) {
  Timer stage;
  const std::vector<FramePair> candidates =
      CandidatePairs(schedule_, it, index_, result_.poses, intrinsics_, options_.pairs);
  s->candidate_pairs = static_cast<int>(candidates.size());
  s->seconds_pairs = stage.Seconds();
  stage.Restart();
  constraints_.correspondences = f2c::FindCorrespondences(candidates, index_, result_.poses, schedule_, it, path_,
                                                          correspondence_options_, &s->correspondences);
  if (run_.tamper) run_.tamper(it, &constraints_.correspondences);
  s->seconds_correspondences = stage.Seconds();
}

// The structural model under the current poses: children, their coplanar parents per
// window, and the parents' relations.
void FineToCoarse::BuildStructure(int it, IterationSummary* s) {
  Timer stage;
  constraints_.structure = {};
  if (options_.structure && it >= first_structure_) {
    HierarchyOptions hierarchy_options = options_.hierarchy;
    if (s->polish && options_.polish_coplanar_agreement_scale > 0) {
      hierarchy_options.agreement_scale = options_.polish_coplanar_agreement_scale;
    }
    ProxyHierarchy hierarchy = BuildProxyHierarchy(schedule_, it, index_, result_.poses, hierarchy_options);
    hierarchy.structure.relations = DetectRelations(hierarchy, options_.relations, &s->relations);
    s->hierarchy = hierarchy.stats;
    s->child_normal_spread_deg = ChildNormalSpreadDeg(hierarchy.structure, result_.poses);
    constraints_.structure = std::move(hierarchy.structure);
  }
  s->seconds_structure = stage.Seconds();
}

// This iteration's weights (the schedule's, E_H's times the measured noise factor) and, in
// the polish iterations, the tighter of each polish loss and the term's own.
SolverOptions FineToCoarse::IterationSolverOptions(int it, IterationSummary* s) const {
  SolverOptions solver = options_.solver;
  const double t =
      schedule_.iterations() > 1 ? std::min(1.0, static_cast<double>(it) / (schedule_.iterations() - 1)) : 1.0;
  const double first = options_.weight_schedule == WeightSchedule::kAuthors ? 1.5 : 1.0;
  auto scheduled = [t, first](double final_weight) { return final_weight * (first + t * (1.0 - first)); };
  solver.weight_correspondence = scheduled(options_.solver.weight_correspondence);
  solver.weight_proxy = scheduled(options_.solver.weight_proxy);
  solver.weight_coplanarity = coplanarity_factor_ * scheduled(options_.solver.weight_coplanarity);
  s->coplanarity_noise_factor = coplanarity_factor_;
  solver.weight_relation = scheduled(options_.solver.weight_relation);
  s->weight_correspondence = solver.weight_correspondence;
  s->weight_proxy = solver.weight_proxy;
  s->weight_coplanarity = solver.weight_coplanarity;
  s->weight_relation = solver.weight_relation;
  // --relation-loss-scale or --coplanarity-loss-scale may already ask for a loss in every
  // iteration (0: none).
  auto tighten = [&](double polish_scale, double* scale) {
    if (s->polish && polish_scale > 0 && (*scale == 0 || polish_scale < *scale)) *scale = polish_scale;
  };
  tighten(options_.polish_relation_loss_scale_deg, &solver.relation_loss_scale_deg);
  tighten(options_.polish_coplanarity_loss_scale, &solver.coplanarity_loss_scale);
  tighten(options_.polish_local_loss_scale, &solver.measured_local_loss_scale);
  s->relation_loss_scale_deg = solver.relation_loss_scale_deg;
  s->coplanarity_loss_scale = solver.coplanarity_loss_scale;
  s->local_loss_scale = solver.measured_local_loss_scale;
  return solver;
}

// argmin of the energy over the poses and planes (optim/problem.h).
void FineToCoarse::Solve(int it, IterationSummary* s) {
  const SolverOptions solver = IterationSolverOptions(it, s);
  Timer stage;
  // Polish iterations trust the closest features alone: SIFT points (depth read at a
  // keypoint, colour and depth not always registered) are less precise than they are, and
  // by then the loops they closed are within the correspondences' reach (E_M kept there:
  // fr1/desk 0.0256 -> 0.0274 m).
  if (s->polish) constraints_.matches.clear();
  s->solve = SolvePoses(constraints_, solver, &result_.poses);
  s->seconds_solve = stage.Seconds();
}

// The self-check (refine/self_check.h): the held-out features' agreement over the scan's
// overlapping pairs before and after; an iteration that lowers it by more than the tolerance
// is undone.
void FineToCoarse::CheckIteration(const PoseVector& before, IterationSummary* s) {
  Timer stage;
  std::vector<FramePair> pairs_before = check_cache_.For(index_, before, intrinsics_, options_.pairs);
  std::vector<FramePair> pairs_after = WholeScanPairs(index_, result_.poses, intrinsics_, options_.pairs);
  std::vector<FramePair> check_pairs = UnitePairs(pairs_before, pairs_after);
  const int n_pairs = static_cast<int>(check_pairs.size());
  const double max_depth = options_.pairs.max_depth;
  SelfCheckRecord& c = s->self_check;
  c.done = true;
  std::vector<PairShare> shares_before =
      check_cache_.Shares(check_pairs, index_, before, intrinsics_, options_.self_check, max_depth);
  std::vector<PairShare> shares_after =
      SharesOfPairs(check_pairs, index_, result_.poses, intrinsics_, options_.self_check, max_depth);
  c.before = SumShares(shares_before, n_pairs);
  c.after = SumShares(shares_after, n_pairs);
  if (c.after.score > (1 + options_.self_check.tolerance) * c.before.score) {
    c.undone = true;
    ++result_.undone_iterations;
    result_.poses = before;
    check_cache_.Keep(before, std::move(pairs_before), std::move(check_pairs), std::move(shares_before));
  } else {
    check_cache_.Keep(result_.poses, std::move(pairs_after), std::move(check_pairs), std::move(shares_after));
  }
  s->seconds_check = stage.Seconds();
}

void FineToCoarse::Log(const IterationSummary& s) const {
  if (run_.quiet) return;
  spdlog::info(
      "refine {}/{}{}: windows of {:.4g} {} ({}), {} pairs, {} correspondences, {} SIFT loops (+{}), "
      "{} parents, {} relations, "
      "E_C {:.4g} -> {:.4g}, {} Ceres iterations, max change {:.3f} m / {:.2f} deg{}, {:.2f} s",
      s.iteration + 1, schedule_.iterations(), s.iteration < schedule_.iterations() ? "" : " (added polish)",
      s.window_length, options_.windows.mode == WindowMode::kPath ? "m" : "frames", s.windows, s.candidate_pairs,
      s.correspondences.total(), s.loops.pairs, s.loops.accepted, s.hierarchy.parents, s.relations.total(),
      s.solve.cost_before.count(Term::kC) ? s.solve.cost_before.at(Term::kC) : 0.0,
      s.solve.cost_after.count(Term::kC) ? s.solve.cost_after.at(Term::kC) : 0.0, s.solve.iterations,
      s.max_translation_change, s.max_rotation_change_deg,
      !s.self_check.done ? std::string()
                         : fmt::format(", check {:.4f} -> {:.4f} m{}", s.self_check.before.Rms(),
                                       s.self_check.after.Rms(), s.self_check.undone ? " (undone)" : ""),
      s.seconds);
}

void FineToCoarse::Finish(const PoseVector& before, const Timer& timer, IterationSummary s) {
  PoseChange(before, result_.poses, &s);
  s.seconds = timer.Seconds();
  Log(s);
  result_.iterations.push_back(std::move(s));
  if (run_.keep_iterations) result_.iteration_poses.push_back(result_.poses);
}

// The whole run against where it started: each iteration may raise the check by up to its
// tolerance, and so many of them by more. A run that ends further from agreeing than it
// started gives back its start.
void FineToCoarse::CheckWholeRun() {
  if (!options_.self_check.enabled || result_.iterations.empty()) return;
  SelfCheckRecord& r = result_.self_check;
  const std::vector<FramePair> pairs = UnitePairs(WholeScanPairs(index_, start_, intrinsics_, options_.pairs),
                                                  check_cache_.For(index_, result_.poses, intrinsics_, options_.pairs));
  const double max_depth = options_.pairs.max_depth;
  r.done = true;
  r.before = ScoreHeldOut(pairs, index_, start_, intrinsics_, options_.self_check, max_depth);
  r.after = SumShares(check_cache_.Shares(pairs, index_, result_.poses, intrinsics_, options_.self_check, max_depth),
                      static_cast<int>(pairs.size()));
  if (r.after.score > (1 + options_.self_check.run_tolerance) * r.before.score) {
    r.undone = true;
    result_.poses = start_;
    spdlog::warn(
        "self-check: the refinement left overlapping frames agreeing less than at its start ({:.4f} -> "
        "{:.4f} m RMS); the initial poses are kept",
        r.before.Rms(), r.after.Rms());
  }
}

}  // namespace

RefineResult RefineFineToCoarse(const FeatureIndex& index, const std::vector<PairAlignment>& pairs,
                                const Trajectory& t0, const CameraIntrinsics& intrinsics, const RefineOptions& options,
                                const RefineRun& run, std::vector<Keyframe> keyframes) {
  options.Check();
  Timer total;
  const size_t n = t0.size();
  F2C_CHECK(index.frames.size() == n && pairs.size() + 1 == n,
            "one index entry per frame, one odometry pair per frame after the first");
  FineToCoarse refine(index, pairs, t0, intrinsics, options, run, std::move(keyframes));
  // Heard by a progress listener only: each iteration has a log line of its own.
  Progress progress("refine", refine.scheduled_iterations(), /*quiet=*/true);
  for (int it = 0; refine.More(it); ++it) {
    Timer timer;
    IterationSummary s = refine.Start(it);
    const PoseVector before = refine.poses();
    refine.CloseLoops(it, &s);           // SIFT loops that now share a window
    refine.FindCorrespondences(it, &s);  // candidate pairs, closest features
    refine.BuildStructure(it, &s);       // proxies, parents, relations
    refine.Solve(it, &s);                // argmin of the energy
    if (options.self_check.enabled) refine.CheckIteration(before, &s);
    refine.Finish(before, timer, std::move(s));
    if (it < refine.scheduled_iterations()) progress.Advance();
  }
  progress.Finish();
  refine.CheckWholeRun();
  RefineResult result = refine.TakeResult();
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
