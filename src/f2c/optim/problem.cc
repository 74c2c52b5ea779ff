#include "f2c/optim/problem.h"

#include <ceres/ceres.h>
#include <tbb/task_arena.h>

#include <mutex>
#include <nlohmann/json.hpp>

#include "f2c/optim/blas_threads.h"
#include "f2c/optim/energy.h"
#include "f2c/optim/gauss_newton.h"
#include "f2c/optim/pose_problem.h"
#include "f2c/util/timer.h"

namespace f2c {

void SolverOptions::Check() const { CheckFields(*this); }

namespace {

// Ceres' settings shared by the plane presolve and the main solve.
ceres::Solver::Options BaseSolverOptions(const SolverOptions& options) {
  ceres::Solver::Options o;
  o.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  o.sparse_linear_algebra_library_type = ceres::SUITE_SPARSE;
  o.num_threads = options.threads > 0 ? options.threads : tbb::this_task_arena::max_concurrency();
  o.function_tolerance = options.function_tolerance;
  o.logging_type = ceres::SILENT;
  return o;
}

// Our Gauss-Newton step where it is the step asked for (optim/gauss_newton.h); Ceres where
// the options ask for it, to convergence, or where the normal equations are not positive
// definite (as before our solver; from the one step's huge trust region Ceres' damping is
// negligible too, and such a step is usually not taken).
bool OwnStep(const SolverOptions& options) {
  return options.linear_solver == LinearSolver::kDirect && options.solve == SolveMode::kOneStep;
}

// The planes start where the hierarchy put them, not where E_H and E_G balance; one joint
// Gauss-Newton step from there overshoots (the step is rejected). So, with the poses held,
// the planes are first solved to convergence, in a problem of their own (E_C, E_L and E_M
// drop out, and need not be evaluated), and the joint step starts from planes in balance
// with the current poses.
void PresolvePlanes(const PoseProblem& problem, const SolverOptions& options, SolveSummary* summary) {
  if (OwnStep(options)) {
    GaussNewtonOptions planes;
    planes.max_iterations = options.plane_presolve_iterations;
    planes.function_tolerance = options.function_tolerance;
    planes.ordering = GaussNewtonOptions::Ordering::kAmd;
    const GaussNewtonSummary s = problem.SolveGaussNewton(true, planes);
    summary->plane_presolve_iterations = s.iterations;
    summary->damped_steps += s.damped;
    if (s.factorized) return;
  }
  ceres::Solver::Options planes = BaseSolverOptions(options);
  planes.max_num_iterations = options.plane_presolve_iterations;
  const ceres::Solver::Summary s = problem.SolveCeres(true, planes);
  summary->plane_presolve_iterations = static_cast<int>(s.iterations.size()) - 1;
}

// The joint solve of poses and planes: one step or to convergence.
void SolveJoint(const PoseProblem& problem, const SolverOptions& options, SolveSummary* summary) {
  if (OwnStep(options)) {
    GaussNewtonOptions step;
    step.function_tolerance = options.function_tolerance;
    CoarseSpace coarse;
    if (options.pcg_min_poses > 0 && problem.pose_count() >= options.pcg_min_poses) {
      coarse = problem.PoseCoarseSpace(options.pcg_spacing);
      step.coarse = &coarse;
    }
    const GaussNewtonSummary s = problem.SolveGaussNewton(false, step);
    summary->linear_iterations += s.linear_iterations;
    summary->factorizations += s.factorizations;
    summary->iterations = s.iterations;
    summary->damped_steps += s.damped;
    summary->termination = s.termination;
    summary->usable = true;  // a rejected step leaves the poses as they were
    if (s.factorized) return;
  }
  ceres::Solver::Options solver = BaseSolverOptions(options);
  if (options.linear_solver == LinearSolver::kCgnr) {
    solver.linear_solver_type = ceres::CGNR;
    solver.preconditioner_type = ceres::JACOBI;
    solver.max_linear_solver_iterations = options.max_linear_iterations;
  }
  solver.max_num_iterations = options.solve == SolveMode::kOneStep ? 1 : options.max_iterations;
  if (options.solve == SolveMode::kOneStep) {
    // A huge trust region makes Levenberg-Marquardt's first step the Gauss-Newton step.
    solver.initial_trust_region_radius = 1e16;
  }
  const ceres::Solver::Summary s = problem.SolveCeres(false, solver);
  summary->iterations = static_cast<int>(s.iterations.size()) - 1;
  summary->termination = ceres::TerminationTypeToString(s.termination_type);
  summary->usable = s.IsSolutionUsable();
  for (const ceres::IterationSummary& it : s.iterations) summary->linear_iterations += it.linear_solver_iterations;
}

// Unit quaternions again and, with a free gauge, the one rigid motion that puts frame 0 back
// applied to every pose.
void Reanchor(const PoseVector& previous, bool hold_first, PoseVector* poses) {
  for (Pose& p : *poses) p.rotation.normalize();
  if (hold_first) return;
  const Rigid3d world_from_solved = previous[0].ToRigid() * (*poses)[0].ToRigid().inverse();
  for (Pose& p : *poses) {
    p = Pose::FromRigid(world_from_solved * p.ToRigid());
    p.rotation.normalize();
  }
}

}  // namespace

SolveSummary SolvePoses(const Constraints& constraints, const SolverOptions& options, PoseVector* poses) {
  options.Check();
  static std::once_flag blas_once;  // optim/blas_threads.h: OpenBLAS's and OpenMP's threads compete with ours
  std::call_once(blas_once, [] {
    UseOneBlasThread();
    UseSerialOpenMp();
  });
  Timer timer;
  SolveSummary summary;
  if (poses->size() < 2) {
    summary.usable = true;
    summary.termination = "nothing to solve";
    return summary;
  }
  const PoseVector previous = *poses;
  PoseProblem problem;
  for (Pose& pose : *poses) problem.AddPose(&pose);
  const bool hold_first = options.fix_first_pose || options.weight_inertia <= 0;
  if (hold_first) problem.FixPose(&(*poses)[0]);
  Energy energy(constraints, options, previous, poses, &problem);
  energy.AddAll(/*first_free_pose=*/hold_first ? 1 : 0);

  summary.residual_blocks = problem.Counts();
  summary.cost_before = problem.TermCosts();
  if (energy.has_structure() && options.solve == SolveMode::kOneStep && options.plane_presolve_iterations > 0) {
    PresolvePlanes(problem, options, &summary);
  }
  SolveJoint(problem, options, &summary);
  summary.cost_after = problem.TermCosts();
  if (!summary.usable) *poses = previous;  // a failed solve leaves the poses as they were
  Reanchor(previous, hold_first, poses);
  summary.seconds = timer.Seconds();
  return summary;
}

namespace {

template <class T>
nlohmann::json ByTermName(const std::map<Term, T>& values) {
  nlohmann::json out = nlohmann::json::object();
  for (const auto& [term, value] : values) out[NameOf(term)] = value;
  return out;
}

}  // namespace

nlohmann::json ToJson(const SolveSummary& s) {
  return {{"cost_before", ByTermName(s.cost_before)},
          {"cost_after", ByTermName(s.cost_after)},
          {"residual_blocks", ByTermName(s.residual_blocks)},
          {"iterations", s.iterations},
          {"linear_iterations", s.linear_iterations},
          {"factorizations", s.factorizations},
          {"plane_presolve_iterations", s.plane_presolve_iterations},
          {"damped_steps", s.damped_steps},
          {"termination", s.termination},
          {"usable", s.usable},
          {"seconds", s.seconds}};
}

}  // namespace f2c
