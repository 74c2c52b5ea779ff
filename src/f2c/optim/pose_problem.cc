#include "f2c/optim/pose_problem.h"

#include <tbb/parallel_for.h>

#include <limits>

#include "f2c/util/error.h"

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
  poses_.push_back(pose);
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

// A control's rigid motion (omega, v): the rotation omega (world axes, about the control's
// position c) and the translation v. A pose (R, t) that moves with it turns R <- Exp(omega) R,
// whose step on EigenQuaternionManifold (q <- [cos|d|, sin|d| d/|d|] q) is d = omega / 2, and
// t <- t + v + omega x (t - c).
CoarseSpace PoseProblem::PoseCoarseSpace(int spacing) const {
  F2C_CHECK(spacing >= 1, "a control every spacing >= 1 poses");
  CoarseSpace space;
  const int n = static_cast<int>(poses_.size());
  if (n < 2) return space;
  std::vector<int> controls;
  for (int i = 0; i < n; i += spacing) controls.push_back(i);
  if (controls.back() != n - 1) controls.push_back(n - 1);
  space.block_sizes.assign(controls.size(), 6);
  const int segments = static_cast<int>(controls.size()) - 1;
  for (int i = 0; i < n; ++i) {
    const int k = std::min(i / spacing, segments - 1);
    const double t = static_cast<double>(i - controls[k]) / (controls[k + 1] - controls[k]);
    Pose* pose = poses_[i];
    std::vector<CoarseBasis>& rotation = space.basis[pose->rotation_data()];
    std::vector<CoarseBasis>& translation = space.basis[pose->translation_data()];
    for (int end = 0; end < 2; ++end) {
      const double w = end == 0 ? 1 - t : t;
      if (w <= 0) continue;
      const int control = k + end;
      Eigen::MatrixXd r = Eigen::MatrixXd::Zero(3, 6);
      r.leftCols<3>() = 0.5 * w * Eigen::Matrix3d::Identity();
      rotation.push_back({control, r});
      const Eigen::Vector3d arm = pose->translation - poses_[controls[control]]->translation;
      Eigen::MatrixXd m(3, 6);
      m.leftCols<3>() << 0, arm.z(), -arm.y(), -arm.z(), 0, arm.x(), arm.y(), -arm.x(),
          0;  // omega x arm = -[arm]x omega
      m.leftCols<3>() *= w;
      m.rightCols<3>() = w * Eigen::Matrix3d::Identity();
      translation.push_back({control, m});
    }
    space.group[pose->rotation_data()] = k;
    space.group[pose->translation_data()] = k;
  }
  return space;
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
