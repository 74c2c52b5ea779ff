#include "f2c/optim/problem.h"

#include <ceres/ceres.h>
#include <fmt/format.h>

#include <cmath>
#include <memory>
#include <nlohmann/json.hpp>
#include <tbb/task_arena.h>

#include "f2c/optim/cost_functions.h"
#include "f2c/util/error.h"
#include "f2c/util/timer.h"

namespace f2c {

const char* RobustLossName(RobustLoss loss) {
  switch (loss) {
    case RobustLoss::kNone: return "none";
    case RobustLoss::kHuber: return "huber";
    case RobustLoss::kCauchy: return "cauchy";
  }
  return "?";
}

RobustLoss RobustLossFromName(const std::string& name) {
  for (RobustLoss loss : {RobustLoss::kNone, RobustLoss::kHuber, RobustLoss::kCauchy}) {
    if (name == RobustLossName(loss)) return loss;
  }
  ThrowInputError("--loss", fmt::format("unknown robust loss '{}' (none, huber, cauchy)", name));
}

void SolverOptions::Check() const {
  auto non_negative = [](double v, const char* name) {
    if (!(v >= 0 && std::isfinite(v))) ThrowInputError(name, fmt::format("must be >= 0, got {}", v));
  };
  non_negative(weight_correspondence, "--weight-correspondence");
  non_negative(weight_local, "--weight-local");
  non_negative(weight_inertia, "--weight-inertia");
  if (!(rotation_lever_arm > 0)) ThrowInputError("--rotation-lever-arm", "must be positive");
  if (!(loss_scale > 0)) ThrowInputError("--loss-scale", "must be positive");
  if (max_iterations < 1) ThrowInputError("--solver-iterations", "must be >= 1");
  if (!(function_tolerance > 0)) ThrowInputError("solver.function_tolerance", "must be positive");
  if (threads < 0) ThrowInputError("--solver-threads", "must be >= 0");
}

namespace {

constexpr const char* kTermC = "E_C";
constexpr const char* kTermL = "E_L";
constexpr const char* kTermI = "E_I";

std::unique_ptr<ceres::LossFunction> MakeLoss(RobustLoss loss, double scale, double weight) {
  ceres::LossFunction* robust = nullptr;
  if (loss == RobustLoss::kHuber) robust = new ceres::HuberLoss(scale);
  if (loss == RobustLoss::kCauchy) robust = new ceres::CauchyLoss(scale);
  return std::make_unique<ceres::ScaledLoss>(robust, weight, ceres::TAKE_OWNERSHIP);
}

// The problem and what it refers to: losses and the manifold outlive it here.
class PoseProblem {
 public:
  PoseProblem() : problem_(ProblemOptions()) {}

  void AddPose(Pose* pose) {
    problem_.AddParameterBlock(pose->rotation_data(), 4, &quaternion_);
    problem_.AddParameterBlock(pose->translation_data(), 3);
  }
  void FixPose(Pose* pose) {
    problem_.SetParameterBlockConstant(pose->rotation_data());
    problem_.SetParameterBlockConstant(pose->translation_data());
  }
  void Add(const std::string& term, ceres::CostFunction* cost, ceres::LossFunction* loss,
           std::vector<double*> blocks) {
    terms_[term].push_back(problem_.AddResidualBlock(cost, loss, blocks));
  }
  ceres::LossFunction* Loss(RobustLoss type, double scale, double weight) {
    auto& slot = losses_[weight];
    if (!slot) slot = MakeLoss(type, scale, weight);
    return slot.get();
  }
  std::map<std::string, double> TermCosts() {
    std::map<std::string, double> costs;
    for (auto& [term, ids] : terms_) {
      ceres::Problem::EvaluateOptions options;
      options.residual_blocks = ids;
      options.apply_loss_function = true;
      double cost = 0;
      problem_.Evaluate(options, &cost, nullptr, nullptr, nullptr);
      costs[term] = cost;
    }
    return costs;
  }
  std::map<std::string, int> Counts() const {
    std::map<std::string, int> counts;
    for (const auto& [term, ids] : terms_) counts[term] = static_cast<int>(ids.size());
    return counts;
  }
  ceres::Problem& problem() { return problem_; }

 private:
  static ceres::Problem::Options ProblemOptions() {
    ceres::Problem::Options o;
    o.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    o.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    return o;
  }
  ceres::EigenQuaternionManifold quaternion_;
  std::map<double, std::unique_ptr<ceres::LossFunction>> losses_;
  std::map<std::string, std::vector<ceres::ResidualBlockId>> terms_;
  ceres::Problem problem_;  // last: destroyed first, before what it points to
};

}  // namespace

SolveSummary SolvePoses(const std::vector<FeatureCorrespondence>& correspondences,
                        const std::vector<RelativePoseConstraint>& local, const SolverOptions& options,
                        PoseVector* poses) {
  options.Check();
  Timer timer;
  SolveSummary summary;
  const int n = static_cast<int>(poses->size());
  if (n < 2) {
    summary.usable = true;
    summary.termination = "nothing to solve";
    return summary;
  }
  const PoseVector previous = *poses;
  PoseProblem pp;
  for (Pose& pose : *poses) pp.AddPose(&pose);
  pp.FixPose(&(*poses)[0]);
  auto blocks = [&](int a, int b) {
    Pose& pa = (*poses)[a];
    Pose& pb = (*poses)[b];
    return std::vector<double*>{pa.rotation_data(), pa.translation_data(), pb.rotation_data(), pb.translation_data()};
  };

  // E_C: point-to-plane and point-to-line, each weighted w_C v_i / sum(v), robustified.
  double sum_c = 0;
  for (const FeatureCorrespondence& c : correspondences) sum_c += c.weight;
  for (const FeatureCorrespondence& c : correspondences) {
    if (options.weight_correspondence == 0 || sum_c <= 0) break;
    F2C_CHECK(c.target_frame >= 0 && c.target_frame < n && c.point_frame >= 0 && c.point_frame < n,
              "correspondence frames in range");
    const double w = options.weight_correspondence * c.weight / sum_c;
    ceres::CostFunction* cost =
        c.kind == CorrespondenceKind::kPointToPlane
            ? static_cast<ceres::CostFunction*>(new AnalyticPointToPlaneCost(
                  c.target_point.cast<double>(), c.target_direction.cast<double>(), c.point.cast<double>()))
            : new AnalyticPointToLineCost(c.target_point.cast<double>(), c.target_direction.cast<double>(),
                                          c.point.cast<double>());
    pp.Add(kTermC, cost, pp.Loss(options.loss, options.loss_scale, w), blocks(c.target_frame, c.point_frame));
  }

  // E_L: relative transforms of T0, w_L v_i / sum(v); rotations at the lever arm.
  double sum_l = 0;
  for (const RelativePoseConstraint& l : local) sum_l += l.weight;
  for (const RelativePoseConstraint& l : local) {
    if (options.weight_local == 0 || sum_l <= 0) break;
    F2C_CHECK(l.frame_a >= 0 && l.frame_a < n && l.frame_b >= 0 && l.frame_b < n, "local frames in range");
    const double s = std::sqrt(options.weight_local * l.weight / sum_l);
    pp.Add(kTermL,
           RelativePoseCost::Create(l.rotation_a_from_b, l.translation_a_from_b, s, s * options.rotation_lever_arm),
           nullptr, blocks(l.frame_a, l.frame_b));
  }

  // E_I: each pose's change in this iteration, w_I / n per pose.
  if (options.weight_inertia > 0) {
    const double s = std::sqrt(options.weight_inertia / n);
    for (int i = 1; i < n; ++i) {
      Pose& p = (*poses)[i];
      pp.Add(kTermI,
             PoseChangeCost::Create(previous[i].rotation, previous[i].translation, s, s * options.rotation_lever_arm),
             nullptr, {p.rotation_data(), p.translation_data()});
    }
  }

  summary.residual_blocks = pp.Counts();
  summary.cost_before = pp.TermCosts();
  ceres::Solver::Options solver;
  solver.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  solver.sparse_linear_algebra_library_type = ceres::SUITE_SPARSE;
  solver.num_threads = options.threads > 0 ? options.threads : tbb::this_task_arena::max_concurrency();
  solver.max_num_iterations = options.one_step ? 1 : options.max_iterations;
  solver.function_tolerance = options.function_tolerance;
  if (options.one_step) {
    // A huge trust region makes Levenberg-Marquardt's first step the Gauss-Newton step.
    solver.initial_trust_region_radius = 1e16;
  }
  solver.logging_type = ceres::SILENT;
  ceres::Solver::Summary ceres_summary;
  ceres::Solve(solver, &pp.problem(), &ceres_summary);
  summary.cost_after = pp.TermCosts();
  summary.iterations = static_cast<int>(ceres_summary.iterations.size()) - 1;
  summary.termination = ceres::TerminationTypeToString(ceres_summary.termination_type);
  summary.usable = ceres_summary.IsSolutionUsable();
  if (!summary.usable) *poses = previous;  // a failed solve leaves the poses as they were
  for (Pose& p : *poses) p.rotation.normalize();
  summary.seconds = timer.Seconds();
  return summary;
}

nlohmann::json ToJson(const SolverOptions& o) {
  return {{"weight_correspondence", o.weight_correspondence},
          {"weight_local", o.weight_local},
          {"weight_inertia", o.weight_inertia},
          {"rotation_lever_arm", o.rotation_lever_arm},
          {"loss", RobustLossName(o.loss)},
          {"loss_scale", o.loss_scale},
          {"max_iterations", o.max_iterations},
          {"one_step", o.one_step},
          {"function_tolerance", o.function_tolerance},
          {"threads", o.threads}};
}

nlohmann::json ToJson(const SolveSummary& s) {
  return {{"cost_before", s.cost_before}, {"cost_after", s.cost_after}, {"residual_blocks", s.residual_blocks},
          {"ceres_iterations", s.iterations}, {"termination", s.termination}, {"usable", s.usable},
          {"seconds", s.seconds}};
}

}  // namespace f2c
