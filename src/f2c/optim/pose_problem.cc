#include "f2c/optim/pose_problem.h"

#include <tbb/parallel_for.h>

#include <limits>

namespace f2c {
namespace {

std::unique_ptr<ceres::LossFunction> MakeLoss(RobustLoss loss, double scale, double weight) {
  ceres::LossFunction* robust = nullptr;
  if (loss == RobustLoss::kHuber) robust = new ceres::HuberLoss(scale);
  if (loss == RobustLoss::kCauchy) robust = new ceres::CauchyLoss(scale);
  return std::make_unique<ceres::ScaledLoss>(robust, weight, ceres::TAKE_OWNERSHIP);
}

}  // namespace

void PoseProblem::AddPose(Pose* pose) {
  AddVariable(pose->rotation_data(), 4, &quaternion_, false);
  AddVariable(pose->translation_data(), 3, nullptr, false);
}

void PoseProblem::AddPlane(PlaneVariable* plane) { AddVariable(plane->data(), 4, &plane_manifold_, true); }

void PoseProblem::FixPose(Pose* pose) {
  variables_[index_.at(pose->rotation_data())].constant = true;
  variables_[index_.at(pose->translation_data())].constant = true;
}

void PoseProblem::AddVariable(double* x, int size, const ceres::Manifold* manifold, bool plane) {
  index_[x] = static_cast<int>(variables_.size());
  variables_.push_back({x, size, manifold, plane});
}

void PoseProblem::Add(Term term, ceres::CostFunction* cost, ceres::LossFunction* loss, std::vector<double*> blocks,
                      bool structure) {
  costs_.emplace_back(cost);
  terms_[term].push_back(residuals_.size());
  Residual r;
  r.cost = cost;
  r.loss = loss;
  r.blocks = std::move(blocks);
  r.structure = structure;
  residuals_.push_back(std::move(r));
}

ceres::LossFunction* PoseProblem::Loss(RobustLoss type, double scale, double weight, Term term) {
  auto& slot = losses_[{term, weight}];
  if (!slot) slot = MakeLoss(type, scale, weight);
  return slot.get();
}

std::map<Term, double> PoseProblem::TermCosts() const {
  std::map<Term, double> costs;
  for (const auto& entry : terms_) {
    const std::vector<size_t>& list = entry.second;  // not a structured binding: the lambda captures it
    std::vector<double> block_cost(list.size(), 0.0);
    const bool batched = pair_blocks_.count(entry.first) > 0;  // its term's cost is its robust cost
    tbb::parallel_for(size_t{0}, list.size(), [&](size_t i) {
      const Residual& b = residuals_[list[i]];
      if (batched) {
        block_cost[i] = static_cast<const PairCost*>(b.cost)->RobustCost(b.blocks.data());
        return;
      }
      Eigen::VectorXd r(b.cost->num_residuals());
      if (!b.cost->Evaluate(b.blocks.data(), r.data(), nullptr)) {
        block_cost[i] = std::numeric_limits<double>::quiet_NaN();
        return;
      }
      double rho[3] = {r.squaredNorm(), 1, 0};
      if (b.loss != nullptr) b.loss->Evaluate(r.squaredNorm(), rho);
      block_cost[i] = 0.5 * rho[0];
    });
    double cost = 0;
    for (double c : block_cost) cost += c;
    costs[entry.first] = cost;
  }
  return costs;
}

std::map<Term, int> PoseProblem::Counts() const {
  std::map<Term, int> counts;
  for (const auto& [term, list] : terms_) counts[term] = static_cast<int>(list.size());
  return counts;
}

GaussNewtonSummary PoseProblem::SolveGaussNewton(bool planes_only, const GaussNewtonOptions& options) const {
  GaussNewtonProblem problem;
  std::vector<GaussNewtonResidual> residuals;
  for (const Residual& r : residuals_) {
    if (planes_only && !r.structure) continue;
    for (double* b : r.blocks) {
      if (problem.HasVariable(b)) continue;
      const Variable& v = variables_[index_.at(b)];
      problem.AddVariable(b, v.size, v.manifold, v.constant || (planes_only && !v.plane));
    }
    residuals.push_back(r);
  }
  return problem.Solve(residuals, options);
}

ceres::Solver::Summary PoseProblem::SolveCeres(bool planes_only, const ceres::Solver::Options& options) const {
  ceres::Problem::Options o;
  o.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  o.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  o.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(o);
  std::vector<char> used(variables_.size(), 0);
  for (const Residual& r : residuals_) {
    if (planes_only && !r.structure) continue;
    for (double* b : r.blocks) used[index_.at(b)] = 1;
  }
  for (size_t i = 0; i < variables_.size(); ++i) {  // in their order, as Ceres orders its columns
    const Variable& v = variables_[i];
    if (!used[i]) continue;
    problem.AddParameterBlock(v.x, v.size, const_cast<ceres::Manifold*>(v.manifold));
    if (v.constant || (planes_only && !v.plane)) problem.SetParameterBlockConstant(v.x);
  }
  for (const Residual& r : residuals_) {
    if (planes_only && !r.structure) continue;
    problem.AddResidualBlock(const_cast<ceres::CostFunction*>(r.cost), const_cast<ceres::LossFunction*>(r.loss),
                             r.blocks);
  }
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  return summary;
}

}  // namespace f2c
