#pragma once
// The refinement's least-squares problem as optim/ builds it (internal to optim/): the pose
// and plane variables, each term's residual blocks, owned here, and the two ways to solve it,
// our Gauss-Newton step (optim/gauss_newton.h) or Ceres. optim/energy.h adds the terms;
// optim/problem.cc (SolvePoses) drives the solve.

#include <ceres/ceres.h>

#include <cmath>
#include <map>
#include <memory>
#include <set>
#include <unordered_map>
#include <utility>
#include <vector>

#include "f2c/optim/gauss_newton.h"
#include "f2c/optim/pair_cost.h"
#include "f2c/optim/pose.h"
#include "f2c/optim/problem.h"
#include "f2c/optim/structure_costs.h"

namespace f2c {

// A plane variable: one block (normal, offset), the offset from `reference` (optim/
// structure_costs.h): {x : normal . (x - reference) = offset}.
struct PlaneVariable {
  Eigen::Vector4d plane = Eigen::Vector4d::Zero();
  Eigen::Vector3d reference = Eigen::Vector3d::Zero();
  void Set(const Eigen::Vector3d& normal, double offset) { plane << normal, offset; }
  Eigen::Vector3d normal() const { return plane.head<3>(); }
  double* data() { return plane.data(); }
};

class PoseProblem {
 public:
  // Variables: a pose's two blocks, or a plane's one. The problem keeps their addresses.
  void AddPose(Pose* pose);
  void AddPlane(PlaneVariable* plane);
  void FixPose(Pose* pose);  // held where it is

  // A residual block of `term` (owns `cost`; the loss is owned by Loss()'s cache or null).
  void Add(Term term, ceres::CostFunction* cost, ceres::LossFunction* loss, std::vector<double*> blocks,
           bool structure = false);
  // A term of the structural model: also in the plane problem, where the poses are constant.
  void AddStructure(Term term, ceres::CostFunction* cost, ceres::LossFunction* loss, std::vector<double*> blocks) {
    Add(term, cost, loss, std::move(blocks), true);
  }
  // A batched pair block: its term's cost is its robust cost, not Ceres' (IRLS) one.
  void AddPair(Term term, PairCost* cost, std::vector<double*> blocks) {
    pair_blocks_.insert(term);
    Add(term, cost, nullptr, std::move(blocks));
  }
  // One loss per term and weight, shared by the blocks that ask for it.
  ceres::LossFunction* Loss(RobustLoss type, double scale, double weight, Term term);
  // A term's weight, least squares or through a Cauchy loss of `cauchy_scale` (0: none): the
  // factor its functor scales the residuals by, and the loss. Under a loss the weight comes
  // after it (a ScaledLoss) and the functor's factor is 1, so the scale stays in the
  // residual's own units (metres, radians).
  struct Weighting {
    double sqrt_weight;
    ceres::LossFunction* loss;
  };
  Weighting Weigh(double weight, double cauchy_scale, Term term) {
    if (cauchy_scale > 0) return {1.0, Loss(RobustLoss::kCauchy, cauchy_scale, weight, term)};
    return {std::sqrt(weight), nullptr};
  }

  // Each term's cost, 1/2 sum of robustified squares (as Ceres counts it), the blocks in
  // parallel: the cost functions are evaluated directly (no Jacobians), which reads the
  // parameters and changes nothing. Summed in order, so the numbers do not depend on the
  // threads.
  std::map<Term, double> TermCosts() const;
  std::map<Term, int> Counts() const;

  // Our Gauss-Newton steps: every residual block, or the structural model alone with the
  // poses held (planes_only).
  GaussNewtonSummary SolveGaussNewton(bool planes_only, const GaussNewtonOptions& options) const;
  // The coarse space of the poses for the step by conjugate gradients (optim/coarse_pcg.h):
  // control frames every `spacing` poses (and the last), each a rigid motion (a rotation about
  // the control's position and a translation, both in world axes); a pose's step blends its
  // two controls' motions linearly by its place between them. Each stretch of poses from one
  // control to the next is a smoother group. Planes are coarse blocks of their own.
  CoarseSpace PoseCoarseSpace(int spacing) const;
  int pose_count() const { return static_cast<int>(poses_.size()); }
  // Ceres on the same blocks.
  ceres::Solver::Summary SolveCeres(bool planes_only, const ceres::Solver::Options& options) const;

 private:
  struct Variable {
    double* x;
    int size;
    const ceres::Manifold* manifold;
    bool plane;
    bool constant = false;
  };
  void AddVariable(double* x, int size, const ceres::Manifold* manifold, bool plane);
  struct Residual : GaussNewtonResidual {
    bool structure = false;  // of the structural model: in the plane problem
  };
  ceres::EigenQuaternionManifold quaternion_;
  PlaneManifold plane_manifold_;
  std::vector<Variable> variables_;
  std::vector<Pose*> poses_;  // in the order added
  std::unordered_map<const double*, int> index_;
  std::map<std::pair<Term, double>, std::unique_ptr<ceres::LossFunction>> losses_;
  std::vector<std::unique_ptr<ceres::CostFunction>> costs_;
  std::vector<Residual> residuals_;            // in the order they were added
  std::map<Term, std::vector<size_t>> terms_;  // each term's residuals_
  std::set<Term> pair_blocks_;                 // terms of batched pair blocks
};

}  // namespace f2c
