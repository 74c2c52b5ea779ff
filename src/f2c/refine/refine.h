#pragma once
// The fine-to-coarse refinement (paper §4.2, Algorithm 1), from T0. RefineFineToCoarse
// (refine.cc) is this loop, one named step per line:
//
//   for i in 0 .. iterations-1:                      windows of l_i frames, l_{i+1} = 2 l_i
//     CloseLoops:          M = SIFT matches of keyframe pairs that now share a window,
//                          verified; poses re-placed first where they disagree (beyond the
//                          paper; refine/sift_loops.h)
//     FindCorrespondences: pairs = CandidatePairs(windows_i, poses)  frames that can overlap
//                          C_i = closest compatible features of each pair (E_C)
//     BuildStructure:      H = ProxyHierarchy(windows_i, poses)  children, coplanar parents
//                          G = DetectRelations(H)  parallel / antiparallel / orthogonal
//     Solve:               poses, planes = argmin w_C E_C + w_L E_L + w_I E_I + w_M E_M
//                            + w_V E_V + w_P E_P + w_H E_H + w_G E_G   (optim/problem.h)
//     CheckIteration:      held-out features' agreement before and after; an iteration
//                          that lowers it is undone (beyond the paper; refine/self_check.h)
//   then added polish iterations while the poses still move, and CheckWholeRun.
//
// E_L's constraints come from the odometry once (refine/local_alignment.h), E_V's from the
// time stamps (refine/steady_motion.h). Everything is
// rebuilt from the current poses each iteration, seeded, so the result does not depend on
// the thread count.

#include <functional>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "f2c/features/feature_set.h"
#include "f2c/odometry/odometry.h"
#include "f2c/optim/problem.h"
#include "f2c/refine/correspondences.h"
#include "f2c/refine/feature_index.h"
#include "f2c/refine/hierarchy.h"
#include "f2c/refine/local_alignment.h"
#include "f2c/refine/pairs.h"
#include "f2c/refine/relations.h"
#include "f2c/refine/self_check.h"
#include "f2c/refine/sift_loops.h"
#include "f2c/refine/steady_motion.h"
#include "f2c/refine/windows.h"
#include "f2c/util/fields.h"

namespace f2c {

enum class WeightSchedule { kConstant, kAuthors };
F2C_ENUM_NAMES(WeightSchedule, {{WeightSchedule::kConstant, "constant"}, {WeightSchedule::kAuthors, "authors"}})

struct RefineOptions {
  WindowOptions windows;
  FeatureIndexOptions features;
  PairOptions pairs;
  CorrespondenceOptions correspondences;
  LocalAlignmentOptions local;
  SteadyMotionOptions steady_motion;
  SiftLoopOptions loops;
  SolverOptions solver;
  SelfCheckOptions self_check;
  // The planar structural model (E_P, E_H, E_G), on by default as in the paper;
  // register --no-structure is its ablation. Measured: it lowers rotation
  // drift and correspondence error on every simulated walk and on the 5,000-frame walk,
  // helps 7-Scenes redkitchen (0.0283 -> 0.0262 m ATE), is level on TUM fr1/xyz (0.0108 m)
  // and costs about 1.8x the refinement's time (still 5-9 ms per frame on 2 cores).
  bool structure = true;
  HierarchyOptions hierarchy;
  RelationOptions relations;
  // The structure from this iteration on; < 0: from the first iteration whose window holds
  // the whole scan (after the loops the growing windows find).
  int structure_first_iteration = 0;
  // kAuthors: the authors' linear weight schedule, each of E_C, E_P, E_H and E_G at 1.5 times
  // its solver weight in the first iteration, moving linearly to it in the last (their 1500
  // -> 1000); kConstant: the solver weights throughout.
  WeightSchedule weight_schedule = WeightSchedule::kConstant;
  // E_H's noise, measured: before the first iteration, in windows of l_0 frames under the
  // initial poses, the RMS angle between the children's normals and their parents'
  // (ChildNormalSpreadDeg) says how well this sensor's views of one surface agree on its
  // tilt, and E_H's weight is multiplied by
  // min(1, (this reference / that angle)^2) for the rest of the run (0: off). w_H was chosen
  // where views agree to this angle (the simulated Kinect noise); a real sensor's depth bias
  // makes them disagree more, and E_H then pulls the poses towards that bias.
  double coplanarity_noise_reference_deg = 0.25;
  // E_G in the polish iterations, beyond the paper: through a Cauchy loss of this scale on the
  // angle off the relation (deg; 0: as in the schedule's iterations, --relation-loss-scale;
  // when that asks for a tighter loss everywhere, the tighter one holds).
  // By then windows have held the whole scan and removed the drift the data can see, so a
  // relation still degrees off is more likely the room's own angle than drift: with the loss
  // it pulls where nearly met and fades where not (a room 6 deg off square stays so). In the
  // schedule's iterations relations keep the paper's full pull, which straightens the
  // drift. Measured: the off-square rooms' wall angles come
  // closer to the truth than without the structure, redkitchen keeps part of E_G's gain
  // (0.0003 of 0.0007 m over three seeds; 1 deg gives up all of it), the simulated walks do
  // not move beyond the seed's spread.
  double polish_relation_loss_scale_deg = 3;
  // E_H in the polish iterations, beyond the paper: through a Cauchy loss of this scale (metres; 0:
  // as in the schedule's iterations, --coplanarity-loss-scale; the tighter of the two holds). An
  // image can fit one proxy across two parallel surfaces a few centimetres apart (a wall and the
  // next one behind it); under least squares such a child turns its frame through its tilt (1.4-1.7
  // deg on the simulator) and, more, its centimetres of offset from its parent. Through the loss it
  // lets go, while children that agree with their parent pull as before. Measured, 5 mm lowered the
  // apartment walks' worst drift (0.87 -> 0.66 deg) and redkitchen's ATE, but raised a 5,000-frame
  // walk's correspondence error (0.0074 -> 0.0085 m), so it stayed off. With E_L's weakly tracked
  // links through their own loss (polish_local_loss_scale) that cost is gone (0.0071 -> 0.0072 m),
  // and it is on by default: the nine walks' worst drift 0.77 -> 0.67 deg (the scene means' mean),
  // their correspondence RMSE 0.0064 -> 0.0060 m, fr1/xyz 0.0107 -> 0.0108 m (level with
  // --no-structure), redkitchen 0.0265 -> 0.0262.
  double polish_coplanarity_loss_scale = 0.005;
  // E_H's agreement with the siblings (HierarchyOptions::agreement_scale, k) in the polish
  // iterations, beyond the paper (0: as in the others, --coplanar-agreement-scale). A child
  // centimetres off a parent whose other children agree to millimetres (a proxy fitted across
  // a wall jog) lets go, while a parent whose children all spread keeps every link's pull.
  // Measured, k = 3: the apartment walks' worst drift 0.87 ->
  // 0.77 deg and correspondence RMSE 0.0072 -> 0.0064 m, the real sequences, the walks that
  // chose nothing and a 5,000-frame walk's correspondence RMSE level. A tighter k gains more
  // on the walks with a wall jog but costs the 5,000-frame walk (k = 2: 0.0074 -> 0.0078 m,
  // k = 1.5: 0.0092), and so does the weighting in every iteration (k = 2: 0.0091 m): in the
  // schedule's iterations weakly tracked frames are still misplaced, and their children
  // look like the jog's.
  double polish_coplanar_agreement_scale = 3;
  // E_L in the polish iterations, beyond the paper: its constraints measured in every direction
  // through a weakly tracked pair (SolverOptions::measured_local_loss_scale and
  // measured_local_loss_max_inliers, fewer than 50 RANSAC inliers) go through a Cauchy loss of this
  // scale (metres, rotations at the lever arm; 0: as in the others). By then the poses are placed,
  // and a pair whose few keypoints sat on one object can be a degree off while the correspondences
  // of every frame around it agree; E_L repeats it in each link through it, so under least squares
  // nothing outvotes it. In the schedule's iterations the same loss would drop links that must
  // still pull. Measured: the nine walks' worst drift 0.87 -> 0.77 deg (scene means' mean), their
  // correspondence RMSE, the walks that chose nothing and the real sequences level or better, a
  // 5,000-frame walk's correspondence RMSE 0.0074 -> 0.0071 m but its worst drift 1.81 -> 2.27 deg
  // (one weakly textured stretch).
  double polish_local_loss_scale = 0.01;

  template <class V>
  void Fields(V& v) {
    F2C_NESTED(v, windows);
    F2C_NESTED(v, features);
    F2C_NESTED(v, pairs);
    F2C_NESTED(v, correspondences);
    v.Group("Refinement: energy and solver (paper 4.3)");
    F2C_FIELD(v, weight_schedule, "--weight-schedule", {},
              "constant: the solver weights throughout; authors: E_C's, E_P's, E_H's and E_G's first weight 1.5 times "
              "their last, as the authors' 1500 -> 1000");
    F2C_NESTED(v, local);
    F2C_NESTED(v, steady_motion);
    F2C_NESTED(v, solver);
    v.Group("Refinement: planar structure (paper 4.2-4.3)");
    F2C_FIELD(v, structure, "--structure,!--no-structure", {},
              "the planar structural model E_P, E_H, E_G (--no-structure: the paper's ablation)");
    F2C_FIELD(v, structure_first_iteration, "--structure-from", AnyFinite(),
              "the structure from this iteration on (< 0: from the first whose window holds the whole scan)");
    F2C_FIELD(
        v, coplanarity_noise_reference_deg, "--coplanarity-noise-reference", AtLeast(0),
        "w_H times min(1, (this / the children's normal spread in windows of l_0 frames at the start)^2) (deg; 0: "
        "off)");
    F2C_FIELD(v, polish_relation_loss_scale_deg, "--polish-relation-loss-scale", AtLeast(0),
              "Cauchy scale of E_G in the polish iterations (deg; 0: as in the others; the tighter of it and "
              "--relation-loss-scale)");
    F2C_FIELD(v, polish_coplanarity_loss_scale, "--polish-coplanarity-loss-scale", AtLeast(0),
              "Cauchy scale of E_H in the polish iterations (m; 0: as in the others; the tighter of it and "
              "--coplanarity-loss-scale)");
    F2C_FIELD(v, polish_coplanar_agreement_scale, "--polish-coplanar-agreement-scale", AtLeast(0),
              "E_H's sibling agreement k in the polish iterations (0: as in the others, --coplanar-agreement-scale)");
    F2C_FIELD(v, polish_local_loss_scale, "--polish-local-loss-scale", AtLeast(0),
              "Cauchy scale of E_L's weakly tracked, fully measured links in the polish iterations (m; 0: as in "
              "the others, --measured-local-loss-scale)");
    F2C_NESTED(v, hierarchy);
    F2C_NESTED(v, relations);
    F2C_NESTED(v, loops);
    F2C_NESTED(v, self_check);
  }
  void Check() const;  // InputError naming the option when out of range
};

struct IterationSummary {
  int iteration = 0;
  double window_length = 0;  // frames, or metres in path mode
  int windows = 0;
  bool full = false;    // one window holds the scan
  bool polish = false;  // a polish iteration (the schedule's last ones, and those added)
  int candidate_pairs = 0;
  CorrespondenceStats correspondences;
  SiftLoopStats loops;
  int local_constraints = 0;
  int velocity_constraints = 0;  // E_V's triples
  double weight_correspondence = 0;
  double weight_proxy = 0, weight_coplanarity = 0, weight_relation = 0;
  double relation_loss_scale_deg = 0;   // E_G's Cauchy scale this iteration (0: least squares)
  double coplanarity_loss_scale = 0;    // E_H's (metres)
  double local_loss_scale = 0;          // E_L's weakly tracked, measured links' (metres)
  double child_normal_spread_deg = 0;   // with the structure: ChildNormalSpreadDeg, this iteration's windows
  double coplanarity_noise_factor = 1;  // w_H's factor from the measured spread
  HierarchyStats hierarchy;
  RelationStats relations;
  SolveSummary presolve;       // when new SIFT loops were accepted (termination empty otherwise)
  std::string presolve_start;  // where the kept presolve started: "tree" or "current"
  SolveSummary solve;
  double max_translation_change = 0;  // metres, over all poses
  double max_rotation_change_deg = 0;
  double rms_translation_change = 0;  // metres, RMS over the poses
  double rms_rotation_change_deg = 0;
  SelfCheckRecord self_check;
  double seconds_pairs = 0, seconds_correspondences = 0, seconds_loops = 0, seconds_structure = 0, seconds_solve = 0,
         seconds_check = 0, seconds = 0;
};

struct RefineResult {
  PoseVector poses;  // world_from_camera per frame
  std::vector<IterationSummary> iterations;
  std::vector<PoseVector> iteration_poses;  // after each iteration, when asked
  // With the structure and a noise reference: the children's normal spread in windows of l_0
  // frames under the initial poses (degrees), and the factor it gave w_H.
  double initial_child_normal_spread_deg = 0;
  double coplanarity_noise_factor = 1;
  int undone_iterations = 0;  // iterations the self-check did not take
  // The self-check of the whole run: the initial poses against the final ones; undone: the
  // final ones agreed less (by more than the tolerance), and `poses` are the initial ones.
  SelfCheckRecord self_check;
  double seconds = 0;
};

struct RefineRun {
  bool quiet = false;            // no per-iteration log line
  bool keep_iterations = false;  // fill RefineResult::iteration_poses
  // For tests: called with each iteration's correspondences before the solve, to make an
  // iteration go wrong on purpose (the self-check's test).
  std::function<void(int iteration, std::vector<FeatureCorrespondence>*)> tamper;
};

// The compact per-frame features and their k-d trees (parallel over frames).
FeatureIndex BuildFeatureIndex(const FeatureSet& features, const FeatureIndexOptions& options);

// `pairs` and `t0` are the odometry's (pairs[k-1] aligns frame k to k-1); `index` has one
// entry per frame; `keyframes` the SIFT of keyframes (refine/keyframes.h), empty for none
// (then no E_M).
RefineResult RefineFineToCoarse(const FeatureIndex& index, const std::vector<PairAlignment>& pairs,
                                const Trajectory& t0, const CameraIntrinsics& intrinsics, const RefineOptions& options,
                                const RefineRun& run = {}, std::vector<Keyframe> keyframes = {});

// Camera path from the first frame to each frame (metres).
std::vector<double> CameraPath(const Trajectory& trajectory);

// The loops' presolve from two starts (SiftLoopOptions::better_start): whether to keep the
// solve from `second` over the one from `first`. Kept: the lower E_L + E_M + E_V after the
// solve, usable only; E_I is left out, since it counts each pose's change from that solve's
// own start, so the two starts' E_I do not compare. A tie keeps `first`.
bool KeepSecondPresolve(const SolveSummary& first, const SolveSummary& second);

nlohmann::json ToJson(const IterationSummary& summary);

}  // namespace f2c
