#pragma once
// One refinement iteration's optimisation (paper §4.3): argmin_{T,P}  w_C E_C(T, C) + w_L E_L(T) +
// w_I E_I(T, P) + w_M E_M(T) + w_V E_V(T) + w_P E_P(T, P) + w_H E_H(P) + w_G E_G(P) over every
// camera pose but the first, which is held fixed (the gauge), and the plane variables P of the
// structural model (optim/structure_costs.h), when there is one. Each term's weight is a total
// shared among its residuals, as in the authors' code (DESIGN.md §2): a residual of a term with N
// residuals and relative weights v_i gets w v_i / sum(v), so the balance of the terms does not
// change with how many constraints an iteration finds. E_C residuals go through a robust loss
// (metres). E_M (SIFT matches the refinement found, beyond the paper) weighs each match w_M / n (n
// frames), not shared: a verified match counts the same however many others there are; its Cauchy
// loss (match_loss_scale) tames the rare wrong one. E_V (steady motion, beyond the paper) shares
// w_V among its triples of consecutive frames. Solved with Ceres: sparse normal Cholesky
// (SuiteSparse), poses on EigenQuaternionManifold x R^3, plane normals on SphereManifold<3>. E_P
// shares w_P among the children by their m_j, E_H w_H among the links, E_G w_G among the relations
// by w_ab, and E_I w_I / n per pose and w_I / (number of planes) per plane.

#include <map>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "f2c/optim/constraints.h"
#include "f2c/optim/pair_cost.h"
#include "f2c/optim/pose.h"
#include "f2c/util/fields.h"

namespace f2c {

// One Gauss-Newton step per refinement iteration (the authors), or Ceres to convergence.
enum class SolveMode { kOneStep, kConverge };
F2C_ENUM_NAMES(SolveMode, {{SolveMode::kOneStep, "one-step"}, {SolveMode::kConverge, "converge"}})
enum class LinearSolver { kDirect, kSparse, kCgnr };
F2C_ENUM_NAMES(LinearSolver,
               {{LinearSolver::kDirect, "direct"}, {LinearSolver::kSparse, "sparse"}, {LinearSolver::kCgnr, "cgnr"}})

struct SolverOptions {
  // Term totals. The authors' code: E_C 1500 -> 1000 over the iterations, E_L 1000, E_I 1.
  // E_L's 100 is measured with E_L on short spans only (refine/local_alignment.h):
  // at 1000 the odometry's relative transforms hold the drift the
  // correspondences would remove; at 10 they no longer keep neighbouring frames together.
  double weight_correspondence = 1000;
  double weight_local = 100;
  double weight_inertia = 1;
  double weight_match = 100;
  // E_V, steady motion (beyond the paper; optim/cost_functions.h): consecutive frames' changes of
  // velocity, linear and angular (rotations at the lever arm), as much in total as E_L. Where
  // nothing else sees a direction (a camera facing one plain wall cannot see its turn about the
  // wall's normal) or one odometry pair is wrong and E_L repeats it, E_L alone keeps T0's jolt; the
  // camera's motion is steadier than that. Measured: lower correspondence error and worst rotation
  // drift on the simulated walks, lower ATE on fr1/xyz. 0: off (the paper).
  double weight_velocity = 100;
  // The structural model's totals (E_P, E_H, E_G); the authors' code: E_S 1500 -> 1000 and
  // E_H 1500 -> 1000 over the iterations. Measured on the real sequences and walks.
  double weight_proxy = 1000;
  double weight_coplanarity = 1000;
  // E_G is weak by default: measured, a strong E_G (1000) pulls surfaces that are only nearly
  // square or parallel (furniture, the trapezoid room) and bends the scan more than it
  // straightens it. At 10 it still cost TUM fr1/xyz (0.0111 against 0.0108 m
  // without the structure) and bent a 2,001-frame walk's unrevisited stretch (0.020 m ATE
  // against 0.013); at 1 neither, while 7-Scenes redkitchen keeps part of its gain and the
  // simulated walks do not move.
  double weight_relation = 1;
  // Cauchy scale of E_L's residuals (metres; rotations at the lever arm); 0: plain least
  // squares. An odometry pair can be wrong outright (ICP turning freely along a plain wall):
  // with least squares, loops spread such an error over every pair; a robust E_L lets it
  // stay where it is.
  double local_loss_scale = 0.0;
  // Cauchy scale of E_L's measured constraints only (RelativePoseConstraint::measured; metres;
  // 0: as local_loss_scale; the tighter of the two holds for them). Constraints through an ICP
  // pair that left directions to the motion prior keep local_loss_scale: nothing else holds
  // those directions. The refinement sets it in its polish
  // iterations (refine/refine.h).
  double measured_local_loss_scale = 0.0;
  // ...and only where the constraint's weakest SIFT or tracked pair had fewer RANSAC inliers than
  // this (0: every measured constraint). Pairs with few keypoints are the ones whose turn is poorly
  // conditioned: on the simulated walks those under 50 inliers are 0.3-0.65 deg off RMS, those over
  // 0.1-0.24. On the real sequences under 0.5% of the pairs have fewer; with every measured
  // constraint through the loss, TUM fr1/xyz lost 0.0107 -> 0.0113 m and 7-Scenes redkitchen 0.0268
  // -> 0.0290: there the correspondences are noisier than the odometry.
  int measured_local_loss_max_inliers = 50;
  // Cauchy scale of E_V's residuals (metres; rotations at the lever arm); 0: least squares.
  double velocity_loss_scale = 0.0;
  // Cauchy scale of E_V's measured triples only (SteadyMotionConstraint::measured: every pair
  // in them measured every direction; metres, rotations at the lever arm; 0: as
  // velocity_loss_scale; the tighter of the two holds). A hand-held camera does jolt: where
  // the walker turns back, its turn rate changes by 2 deg or more within a frame or two,
  // which the odometry measures, and least-squares E_V bends the frames about it off the
  // truth (on the simulated walks, single frames 0.2-0.3 deg off both neighbours whose
  // odometry was right to 0.02). Through the loss the measured jolt stands. Triples over a
  // pair left to the motion prior keep velocity_loss_scale: there E_V measures what nothing
  // else does. Measured: the nine walks' worst drift
  // 0.491 / 0.503 / 0.500 -> 0.469 / 0.472 / 0.478 deg, the real sequences level.
  double measured_velocity_loss_scale = 0.02;
  double match_loss_scale = 0.05;  // metres
  // Cauchy scale of E_H's residuals (metres, tilts at the lever arm; 0: least squares, the
  // paper's): a child far off its parent pulls with 1 / (1 + (r / scale)^2) of its force. The
  // refinement sets it in its polish iterations (refine/refine.h).
  double coplanarity_loss_scale = 0.0;
  // Cauchy scale of E_G's residuals (degrees; 0: least squares). Each relation's residual is
  // about its angle off the relation (radians), so a relation that is only nearly met (a
  // corner at 84 degrees) pulls with 1 / (1 + (off / scale)^2) of the force a met one does.
  double relation_loss_scale_deg = 0.0;
  // E_L and E_I compare rotations as the displacement they cause at this distance from the
  // camera (metres per radian): a Kinect-class sensor sees surfaces at about 1-3 m.
  double rotation_lever_arm = 1.0;
  RobustLoss loss = RobustLoss::kCauchy;
  double loss_scale = 0.02;  // metres
  // kOneStep: a single Gauss-Newton step per refinement iteration, as the authors take (the
  // default: as accurate as solving to convergence here at a quarter of the time);
  // kConverge: up to max_iterations Ceres iterations.
  int max_iterations = 50;
  SolveMode solve = SolveMode::kOneStep;
  // One-step mode with the structural model: the planes alone (poses held) are first solved
  // for up to this many iterations, so the joint step starts from planes in balance (0: off).
  int plane_presolve_iterations = 3;
  double function_tolerance = 1e-6;
  // The linear solver. kDirect: one-step solves (and the plane presolve) assemble the normal
  // equations themselves and factor them by CHOLMOD (optim/gauss_newton.h): the same step as
  // Ceres' at an infinite trust region, without Ceres' per-solve set-up (measured: the
  // refinement about a fifth faster at 900 frames, a quarter at 2,001 and 5,000);
  // converge mode, or normal equations that are not
  // positive definite, fall back to kSparse (as before this solver). kSparse: Ceres with sparse Cholesky
  // (SuiteSparse). kCgnr: Ceres with conjugate gradients on the normal equations and a
  // block-Jacobi preconditioner, whose memory grows with the constraints only (a Cholesky
  // factor fills in as loops tie distant frames together).
  LinearSolver linear_solver = LinearSolver::kDirect;
  int max_linear_iterations = 100;
  // kDirect's joint step on scans of at least this many frames (0: never) by conjugate
  // gradients instead of Cholesky, preconditioned by a coarse solve with a control frame every
  // pcg_spacing frames (optim/coarse_pcg.h, PoseProblem::PoseCoarseSpace): the same step to a
  // relative residual of 1e-8, at a cost that grows with the constraints rather than with the
  // factor's fill-in.
  int pcg_min_poses = 3000;
  int pcg_spacing = 8;
  // Ceres' threads; 0: as many as the thread pool allows (register --threads). The one-step
  // solve gave byte-identical poses for 1 and 2 threads (tested).
  int threads = 0;
  // The gauge. Fixed: frame 0 is held where it is while the others move. Free: frame 0 is
  // a pose like any other (E_I holds the gauge), and after the solve every pose is moved by
  // one rigid transform that puts frame 0 back. Holding frame 0 lets every term that
  // pulls the scan as a whole (a loop, the straightening of E_G and E_H) turn it against
  // frame 0's own constraints: measured, frame 0 ended 1.3 degrees off its neighbours on a
  // simulated walk. Free needs w_I > 0 (else frame 0 is held).
  bool fix_first_pose = false;

  template <class V>
  void Fields(V& v) {
    v.Group("Refinement: energy and solver (paper 4.3)");
    F2C_FIELD(v, weight_correspondence, "--weight-correspondence", AtLeast(0), "w_C, E_C's total weight");
    F2C_FIELD(v, weight_local, "--weight-local", AtLeast(0), "w_L, E_L's total weight");
    F2C_FIELD(v, weight_inertia, "--weight-inertia", AtLeast(0), "w_I, E_I's total weight");
    F2C_FIELD(v, rotation_lever_arm, "--rotation-lever-arm", Positive(),
              "E_L/E_I compare rotations at this distance (m/rad)");
    F2C_FIELD(v, local_loss_scale, "--local-loss-scale", AtLeast(0), "Cauchy scale of E_L (m; 0: least squares)");
    F2C_FIELD(
        v, measured_local_loss_scale, "--measured-local-loss-scale", AtLeast(0),
        "Cauchy scale of E_L's pairs measured in every direction (m; 0: as --local-loss-scale; the tighter holds)");
    F2C_FIELD(v, measured_local_loss_max_inliers, "--measured-local-loss-max-inliers", AtLeast(0),
              "...only where the weakest SIFT or tracked pair on the path had fewer RANSAC inliers (0: all)");
    F2C_FIELD(v, weight_velocity, "--weight-velocity", AtLeast(0),
              "w_V, E_V's total weight (steady motion over consecutive frames; 0: off, the paper)");
    F2C_FIELD(v, velocity_loss_scale, "--velocity-loss-scale", AtLeast(0), "Cauchy scale of E_V (m; 0: least squares)");
    F2C_FIELD(v, measured_velocity_loss_scale, "--measured-velocity-loss-scale", AtLeast(0),
              "Cauchy scale of E_V's triples whose pairs measured every direction (m; 0: as --velocity-loss-scale; the "
              "tighter holds)");
    F2C_FIELD(v, weight_match, "--weight-match", AtLeast(0), "w_M: each SIFT loop match weighs w_M / frames");
    F2C_FIELD(v, match_loss_scale, "--match-loss-scale", Positive(), "Cauchy scale of E_M (m)");
    F2C_FIELD(v, loss, "--loss", {}, "robust loss of E_C: none, huber, cauchy");
    F2C_FIELD(v, loss_scale, "--loss-scale", Positive(), "its scale (m)");
    F2C_FIELD(v, max_iterations, "--solver-iterations", AtLeast(1), "Ceres iterations per refinement iteration");
    F2C_FIELD(v, solve, "--solve", {},
              "one-step: one Gauss-Newton step per iteration (the authors' code); converge: to convergence");
    F2C_FIELD(v, function_tolerance, "", Positive(), "Ceres' function tolerance (converge)");
    F2C_FIELD(v, linear_solver, "--linear-solver", {},
              "direct: our one-step Gauss-Newton, Cholesky by CHOLMOD (exact); sparse: Ceres' sparse "
              "Cholesky (exact); cgnr: Ceres' conjugate gradients (memory linear in the constraints)");
    F2C_FIELD(v, max_linear_iterations, "--linear-iterations", AtLeast(1), "cgnr: iterations per step");
    F2C_FIELD(v, pcg_min_poses, "--pcg-min-frames", AtLeast(0),
              "direct: the joint step by coarse-preconditioned conjugate gradients from this many frames (0: never)");
    F2C_FIELD(v, pcg_spacing, "--pcg-spacing", AtLeast(1),
              "...a control frame of the coarse space every this many frames");
    F2C_FIELD(v, fix_first_pose, "--fix-first-pose", {},
              "hold frame 0 during each solve (else it moves with the rest and the poses are re-anchored)");
    F2C_FIELD(v, threads, "--solver-threads", AtLeast(0), "Ceres threads (0: as --threads)");
    v.Group("Refinement: planar structure (paper 4.2-4.3)");
    F2C_FIELD(v, weight_proxy, "--weight-proxy", AtLeast(0), "w_P, E_P's total weight (children fit their images)");
    F2C_FIELD(v, weight_coplanarity, "--weight-coplanarity", AtLeast(0),
              "w_H, E_H's total weight (children coplanar with parents)");
    F2C_FIELD(v, coplanarity_loss_scale, "--coplanarity-loss-scale", AtLeast(0),
              "Cauchy scale of E_H (m; 0: least squares)");
    F2C_FIELD(v, weight_relation, "--weight-relation", AtLeast(0),
              "w_G, E_G's total weight (parallel/antiparallel/orthogonal parents)");
    F2C_FIELD(v, relation_loss_scale_deg, "--relation-loss-scale", AtLeast(0),
              "Cauchy scale of E_G on the angle off the relation (deg; 0: least squares)");
    F2C_FIELD(v, plane_presolve_iterations, "--plane-presolve-iterations", AtLeast(0),
              "one-step solves: iterations on the planes alone before the joint step (0: off)");
  }
  void Check() const;
};

// The energy's terms (above), named as run.json and the report name them; declared in the
// order of their names, so that a map over them iterates (and sums) as one over the names.
enum class Term { kC, kG, kH, kI, kL, kM, kP, kV };
F2C_ENUM_NAMES(Term, {{Term::kC, "E_C"},
                      {Term::kG, "E_G"},
                      {Term::kH, "E_H"},
                      {Term::kI, "E_I"},
                      {Term::kL, "E_L"},
                      {Term::kM, "E_M"},
                      {Term::kP, "E_P"},
                      {Term::kV, "E_V"}})

struct SolveSummary {
  // Weighted cost of each term (Ceres' 1/2 sum of robustified squares), before and after.
  std::map<Term, double> cost_before, cost_after;
  std::map<Term, int> residual_blocks;
  int iterations = 0;       // steps tried (ours), or Ceres iterations
  std::string termination;  // ours ("iteration limit", "step rejected", ...) or Ceres' termination type
  bool usable = false;
  int linear_iterations = 0;  // conjugate-gradient iterations, summed (iterative solvers)
  int factorizations = 0;     // our one-step solve's Cholesky factorizations (joint step)
  int plane_presolve_iterations = 0;
  int damped_steps = 0;  // our solver's damped retries of rejected steps, presolve and step
  double seconds = 0;
};

// Minimises the energy above, starting from and writing to `poses` (world_from_camera, one
// per frame). The poses on entry are E_I's reference.
SolveSummary SolvePoses(const Constraints& constraints, const SolverOptions& options, PoseVector* poses);

nlohmann::json ToJson(const SolveSummary& summary);

}  // namespace f2c
