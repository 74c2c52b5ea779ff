#include "f2c/optim/problem.h"

#include <ceres/ceres.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <set>
#include <unordered_map>
#include <nlohmann/json.hpp>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "f2c/optim/blas_threads.h"
#include "f2c/optim/cost_functions.h"
#include "f2c/optim/gauss_newton.h"
#include "f2c/optim/structure_costs.h"
#include "f2c/util/error.h"
#include "f2c/util/timer.h"

namespace f2c {

void SolverOptions::Check() const { CheckFields(*this); }

namespace {

constexpr Term kTermC = Term::kC;
constexpr Term kTermL = Term::kL;
constexpr Term kTermV = Term::kV;
constexpr Term kTermI = Term::kI;
constexpr Term kTermM = Term::kM;
constexpr Term kTermP = Term::kP;
constexpr Term kTermH = Term::kH;
constexpr Term kTermG = Term::kG;

// A term's Cauchy scale where some of its constraints have a scale of their own (0: none):
// the tighter of the two holds for those.
double TighterLossScale(double scale, double own) { return own > 0 && (scale == 0 || own < scale) ? own : scale; }

// A plane variable: one block (normal, offset), the offset from `reference` (optim/
// structure_costs.h): {x : normal . (x - reference) = offset}.
struct PlaneVariable {
  Eigen::Vector4d plane = Eigen::Vector4d::Zero();
  Eigen::Vector3d reference = Eigen::Vector3d::Zero();
  void Set(const Eigen::Vector3d& normal, double offset) { plane << normal, offset; }
  Eigen::Vector3d normal() const { return plane.head<3>(); }
  double* data() { return plane.data(); }
};

// Items 0..count-1 grouped by key(i): the groups in increasing key order, each holding
// make(i) in increasing i (what a std::map of vectors would hold, without its tree walk per
// item: a stable sort of the indices).
template <typename KeyOf, typename Make>
auto GroupByKey(size_t count, KeyOf key, Make make) {
  using Key = decltype(key(size_t{0}));
  using Value = decltype(make(size_t{0}));
  std::vector<std::pair<Key, size_t>> order(count);
  for (size_t i = 0; i < count; ++i) order[i] = {key(i), i};
  std::stable_sort(order.begin(), order.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<std::pair<Key, std::vector<Value>>> groups;
  for (const auto& [k, i] : order) {
    if (groups.empty() || groups.back().first != k) groups.emplace_back(k, std::vector<Value>{});
    groups.back().second.push_back(make(i));
  }
  return groups;
}

std::unique_ptr<ceres::LossFunction> MakeLoss(RobustLoss loss, double scale, double weight) {
  ceres::LossFunction* robust = nullptr;
  if (loss == RobustLoss::kHuber) robust = new ceres::HuberLoss(scale);
  if (loss == RobustLoss::kCauchy) robust = new ceres::CauchyLoss(scale);
  return std::make_unique<ceres::ScaledLoss>(robust, weight, ceres::TAKE_OWNERSHIP);
}

// The problem: its variables and residual blocks, owned here, solved by our Gauss-Newton
// step (optim/gauss_newton.h) or handed to Ceres.
class PoseProblem {
 public:
  void AddPose(Pose* pose) {
    AddVariable(pose->rotation_data(), 4, &quaternion_, false);
    AddVariable(pose->translation_data(), 3, nullptr, false);
  }
  void AddPlane(PlaneVariable* plane) { AddVariable(plane->data(), 4, &plane_manifold_, true); }
  void FixPose(Pose* pose) {
    variables_[index_.at(pose->rotation_data())].constant = true;
    variables_[index_.at(pose->translation_data())].constant = true;
  }
  void Add(Term term, ceres::CostFunction* cost, ceres::LossFunction* loss, std::vector<double*> blocks,
           bool structure = false) {
    costs_.emplace_back(cost);
    terms_[term].push_back(residuals_.size());
    Residual r;
    r.cost = cost;
    r.loss = loss;
    r.blocks = std::move(blocks);
    r.structure = structure;
    residuals_.push_back(std::move(r));
  }
  // A term of the structural model: also in the plane problem, where the poses are constant.
  void AddStructure(Term term, ceres::CostFunction* cost, ceres::LossFunction* loss, std::vector<double*> blocks) {
    Add(term, cost, loss, std::move(blocks), true);
  }
  // A batched pair block: its term's cost is its robust cost, not Ceres' (IRLS) one.
  void AddPair(Term term, PairCost* cost, std::vector<double*> blocks) {
    pair_blocks_.insert(term);
    Add(term, cost, nullptr, std::move(blocks));
  }
  ceres::LossFunction* Loss(RobustLoss type, double scale, double weight, Term term) {
    auto& slot = losses_[{term, weight}];
    if (!slot) slot = MakeLoss(type, scale, weight);
    return slot.get();
  }
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
  std::map<Term, double> TermCosts() const {
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
  std::map<Term, int> Counts() const {
    std::map<Term, int> counts;
    for (const auto& [term, list] : terms_) counts[term] = static_cast<int>(list.size());
    return counts;
  }

  // Our Gauss-Newton steps: every residual block, or the structural model alone with the
  // poses held (planes_only).
  GaussNewtonSummary SolveGaussNewton(bool planes_only, const GaussNewtonOptions& options) const {
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
  // Ceres on the same blocks.
  ceres::Solver::Summary SolveCeres(bool planes_only, const ceres::Solver::Options& options) const {
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

 private:
  struct Variable {
    double* x;
    int size;
    const ceres::Manifold* manifold;
    bool plane;
    bool constant = false;
  };
  void AddVariable(double* x, int size, const ceres::Manifold* manifold, bool plane) {
    index_[x] = static_cast<int>(variables_.size());
    variables_.push_back({x, size, manifold, plane});
  }
  struct Residual : GaussNewtonResidual {
    bool structure = false;  // of the structural model: in the plane problem
  };
  ceres::EigenQuaternionManifold quaternion_;
  PlaneManifold plane_manifold_;
  std::vector<Variable> variables_;
  std::unordered_map<const double*, int> index_;
  std::map<std::pair<Term, double>, std::unique_ptr<ceres::LossFunction>> losses_;
  std::vector<std::unique_ptr<ceres::CostFunction>> costs_;
  std::vector<Residual> residuals_;            // in the order they were added
  std::map<Term, std::vector<size_t>> terms_;  // each term's residuals_
  std::set<Term> pair_blocks_;                 // terms of batched pair blocks
};

}  // namespace

// Ceres' settings shared by the plane presolve and the main solve.
static ceres::Solver::Options BaseSolverOptions(const SolverOptions& options) {
  ceres::Solver::Options o;
  o.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  o.sparse_linear_algebra_library_type = ceres::SUITE_SPARSE;
  o.num_threads = options.threads > 0 ? options.threads : tbb::this_task_arena::max_concurrency();
  o.function_tolerance = options.function_tolerance;
  o.logging_type = ceres::SILENT;
  return o;
}

SolveSummary SolvePoses(const Constraints& constraints, const SolverOptions& options, PoseVector* poses) {
  const std::vector<FeatureCorrespondence>& correspondences = constraints.correspondences;
  const std::vector<RelativePoseConstraint>& local = constraints.local;
  options.Check();
  static std::once_flag blas_once;  // optim/blas_threads.h: OpenBLAS's and OpenMP's threads compete with ours
  std::call_once(blas_once, [] {
    UseOneBlasThread();
    UseSerialOpenMp();
  });
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
  const bool hold_first = options.fix_first_pose || options.weight_inertia <= 0;
  const int first_free = hold_first ? 1 : 0;  // the first pose the solve may move
  if (hold_first) pp.FixPose(&(*poses)[0]);
  auto blocks = [&](int a, int b) {
    Pose& pa = (*poses)[a];
    Pose& pb = (*poses)[b];
    return std::vector<double*>{pa.rotation_data(), pa.translation_data(), pb.rotation_data(), pb.translation_data()};
  };

  // E_C: point-to-plane and point-to-line, each weighted w_C v_i / sum(v), robustified; one
  // residual block per ordered frame pair (optim/pair_cost.h).
  using PairKey = std::pair<int, int>;
  std::vector<std::pair<PairKey, std::vector<PairConstraint>>> by_pair;
  double sum_c = 0;
  for (const FeatureCorrespondence& c : correspondences) sum_c += c.weight;
  if (options.weight_correspondence > 0 && sum_c > 0) {
    for (const FeatureCorrespondence& c : correspondences) {
      F2C_CHECK(c.target_frame >= 0 && c.target_frame < n && c.point_frame >= 0 && c.point_frame < n,
                "correspondence frames in range");
    }
    by_pair = GroupByKey(
        correspondences.size(),
        [&](size_t i) {
          return PairKey{correspondences[i].target_frame, correspondences[i].point_frame};
        },
        [&](size_t i) {
          const FeatureCorrespondence& c = correspondences[i];
          PairConstraint pc;
          pc.kind = c.kind == CorrespondenceKind::kPointToPlane ? ConstraintKind::kPointToPlane
                                                                : ConstraintKind::kPointToLine;
          pc.weight = options.weight_correspondence * c.weight / sum_c;
          pc.target_point = c.target_point.cast<double>();
          pc.target_direction = c.target_direction.cast<double>();
          pc.point = c.point.cast<double>();
          return pc;
        });
  }
  for (auto& [key, list] : by_pair) {
    const std::vector<double*> b = blocks(key.first, key.second);
    pp.AddPair(kTermC, new PairCost(std::move(list), options.loss, options.loss_scale, b.data()), b);
  }

  // E_L: relative transforms of T0, w_L v_i / sum(v); rotations at the lever arm, or each
  // constraint whitened by its own information.
  double sum_l = 0;
  for (const RelativePoseConstraint& l : local) sum_l += l.weight;
  for (const RelativePoseConstraint& l : local) {
    if (options.weight_local == 0 || sum_l <= 0) break;
    F2C_CHECK(l.frame_a >= 0 && l.frame_a < n && l.frame_b >= 0 && l.frame_b < n, "local frames in range");
    const bool weak =
        options.measured_local_loss_max_inliers == 0 || l.weakest_inliers < options.measured_local_loss_max_inliers;
    const double scale = l.measured && weak
                             ? TighterLossScale(options.local_loss_scale, options.measured_local_loss_scale)
                             : options.local_loss_scale;
    const auto [s, loss] = pp.Weigh(options.weight_local * l.weight / sum_l, scale, kTermL);
    ceres::CostFunction* cost =
        l.whitened()
            ? RelativePoseCost::Create(l.rotation_a_from_b, l.translation_a_from_b, s * l.sqrt_information)
            : RelativePoseCost::Create(l.rotation_a_from_b, l.translation_a_from_b, s, s * options.rotation_lever_arm);
    pp.Add(kTermL, cost, loss, blocks(l.frame_a, l.frame_b));
  }

  // E_V: steady motion over consecutive frames, w_V / (number of triples) each; rotations
  // at the lever arm.
  const std::vector<SteadyMotionConstraint>& steady = constraints.steady_motion;
  const double w_v = steady.empty() ? 0.0 : options.weight_velocity / static_cast<double>(steady.size());
  for (const SteadyMotionConstraint& v : steady) {
    if (w_v == 0) break;
    F2C_CHECK(v.frame_a >= 0 && v.frame_a < n && v.frame_b >= 0 && v.frame_b < n && v.frame_c >= 0 && v.frame_c < n,
              "steady-motion frames in range");
    Pose& pa = (*poses)[v.frame_a];
    Pose& pb = (*poses)[v.frame_b];
    Pose& pc = (*poses)[v.frame_c];
    std::vector<double*> b{pa.rotation_data(),    pa.translation_data(), pb.rotation_data(),
                           pb.translation_data(), pc.rotation_data(),    pc.translation_data()};
    const double scale = v.measured
                             ? TighterLossScale(options.velocity_loss_scale, options.measured_velocity_loss_scale)
                             : options.velocity_loss_scale;
    const auto [s, loss] = pp.Weigh(w_v * v.weight, scale, kTermV);
    pp.Add(kTermV, SteadyMotionCost::Create(v.scale_ab, v.scale_bc, s, s * options.rotation_lever_arm), loss,
           std::move(b));
  }

  // E_M: SIFT matches, w_M / n each, robustified, batched per frame pair.
  by_pair.clear();
  if (options.weight_match > 0) {
    const std::vector<PointMatch>& matches = constraints.matches;
    for (const PointMatch& m : matches) {
      F2C_CHECK(m.frame_a >= 0 && m.frame_a < n && m.frame_b >= 0 && m.frame_b < n, "match frames in range");
    }
    by_pair = GroupByKey(
        matches.size(),
        [&](size_t i) {
          return PairKey{matches[i].frame_a, matches[i].frame_b};
        },
        [&](size_t i) {
          PairConstraint pc;
          pc.kind = ConstraintKind::kPointToPoint;
          pc.weight = options.weight_match / n;
          pc.target_point = matches[i].point_a.cast<double>();
          pc.point = matches[i].point_b.cast<double>();
          return pc;
        });
  }
  for (auto& [key, list] : by_pair) {
    const std::vector<double*> b = blocks(key.first, key.second);
    pp.AddPair(kTermM, new PairCost(std::move(list), RobustLoss::kCauchy, options.match_loss_scale, b.data()), b);
  }

  // The structural model. Children start where their frame's pose puts the image's plane
  // (E_P starts at the image's own fit residual); parents where the hierarchy fitted them.
  // Without E_P children would float free of their frames, so w_P = 0 turns it all off.
  const StructureConstraints& structure = constraints.structure;
  std::vector<PlaneVariable> children(structure.children.size()), parents(structure.parents.size());
  const bool use_structure = !structure.empty() && options.weight_proxy > 0;
  if (use_structure) {
    double sum_p = 0;
    for (const ChildProxy& c : structure.children) sum_p += c.share;
    for (size_t i = 0; i < children.size(); ++i) {
      const ChildProxy& c = structure.children[i];
      F2C_CHECK(c.frame >= 0 && c.frame < n, "child proxy frame in range");
      Pose& pose = (*poses)[c.frame];
      const Eigen::Vector3d normal = (pose.rotation * c.normal.cast<double>()).normalized();
      children[i].reference = pose.rotation * c.centroid.cast<double>() + pose.translation;
      children[i].Set(normal, c.offset + normal.dot(pose.translation) - normal.dot(children[i].reference));
      pp.AddPlane(&children[i]);
      // E_P: w_P m_j / sum(m) times the members' mean squared distance.
      const double s = std::sqrt(options.weight_proxy * c.share / sum_p);
      pp.AddStructure(kTermP,
                      ProxyFitCost::Create(c.centroid.cast<double>(), s * SqrtCovariance(c.covariance.cast<double>()),
                                           children[i].reference),
                      nullptr, {pose.rotation_data(), pose.translation_data(), children[i].data()});
    }
    for (size_t i = 0; i < parents.size(); ++i) {
      const Eigen::Vector3d normal = structure.parents[i].normal.normalized();
      parents[i].reference = structure.parents[i].centre;
      parents[i].Set(normal, structure.parents[i].offset - normal.dot(parents[i].reference));
      pp.AddPlane(&parents[i]);
    }
    // E_H: w_H a v / sum(v) per link (a: the link's agreement with its siblings).
    double sum_h = 0;
    for (const CoplanarLink& l : structure.links) sum_h += l.weight;
    for (const CoplanarLink& l : structure.links) {
      if (options.weight_coplanarity == 0 || sum_h <= 0) break;
      F2C_CHECK(l.child >= 0 && l.child < static_cast<int>(children.size()) && l.parent >= 0 &&
                    l.parent < static_cast<int>(parents.size()),
                "coplanarity link in range");
      PlaneVariable& c = children[l.child];
      PlaneVariable& p = parents[l.parent];
      const auto [s, loss] =
          pp.Weigh(options.weight_coplanarity * l.weight * l.agreement / sum_h, options.coplanarity_loss_scale, kTermH);
      pp.AddStructure(kTermH,
                      CoplanarityCost::Create(l.anchor, options.rotation_lever_arm, s, c.reference, p.reference), loss,
                      {c.data(), p.data()});
    }
    // E_G: w_G w_ab / sum(w) per relation.
    double sum_g = 0;
    for (const PlaneRelation& r : structure.relations) sum_g += r.weight;
    for (const PlaneRelation& r : structure.relations) {
      if (options.weight_relation == 0 || sum_g <= 0) break;
      F2C_CHECK(r.parent_a >= 0 && r.parent_a < static_cast<int>(parents.size()) && r.parent_b >= 0 &&
                    r.parent_b < static_cast<int>(parents.size()) && r.parent_a != r.parent_b,
                "relation parents in range");
      const auto [s, loss] =
          pp.Weigh(options.weight_relation * r.weight / sum_g, options.relation_loss_scale_deg * M_PI / 180, kTermG);
      ceres::CostFunction* cost = r.type == RelationType::kOrthogonal
                                      ? OrthogonalCost::Create(s)
                                      : ParallelCost::Create(r.type == RelationType::kParallel ? 1.0 : -1.0, s);
      pp.AddStructure(kTermG, cost, loss, {parents[r.parent_a].data(), parents[r.parent_b].data()});
    }
  }

  // E_I: each pose's change in this iteration, w_I / n per pose; each plane's, w_I / planes.
  if (options.weight_inertia > 0) {
    const double s = std::sqrt(options.weight_inertia / n);
    for (int i = first_free; i < n; ++i) {
      Pose& p = (*poses)[i];
      pp.Add(kTermI,
             PoseChangeCost::Create(previous[i].rotation, previous[i].translation, s, s * options.rotation_lever_arm),
             nullptr, {p.rotation_data(), p.translation_data()});
    }
    if (use_structure && !parents.empty()) {
      // Parents only: children follow their frames through E_P (an inertia of their own
      // would hold the frames back).
      const double sp = std::sqrt(options.weight_inertia / static_cast<double>(parents.size()));
      for (size_t i = 0; i < parents.size(); ++i) {
        PlaneVariable& v = parents[i];
        pp.AddStructure(kTermI, PlaneChangeCost::Create(v.normal(), v.plane[3], sp * options.rotation_lever_arm, sp),
                        nullptr, {v.data()});
      }
    }
  }

  summary.residual_blocks = pp.Counts();
  summary.cost_before = pp.TermCosts();
  // The planes start where the hierarchy put them, not where E_H and E_G balance; one joint
  // Gauss-Newton step from there overshoots (the step is rejected). So, with the poses held,
  // the planes are first solved to convergence, in a problem of their own (E_C, E_L and E_M
  // drop out, and need not be evaluated), and the joint step starts from planes in balance
  // with the current poses.
  // Our Gauss-Newton step where it is the step asked for (optim/gauss_newton.h); Ceres where
  // the options ask for it, to convergence, or where the normal equations are not positive
  // definite (as before our solver; from the one step's huge trust region Ceres' damping is
  // negligible too, and such a step is usually not taken).
  const bool own = options.linear_solver == LinearSolver::kDirect && options.solve == SolveMode::kOneStep;
  if (use_structure && options.solve == SolveMode::kOneStep && options.plane_presolve_iterations > 0) {
    bool done = false;
    if (own) {
      GaussNewtonOptions planes;
      planes.max_iterations = options.plane_presolve_iterations;
      planes.function_tolerance = options.function_tolerance;
      planes.ordering = GaussNewtonOptions::Ordering::kAmd;
      const GaussNewtonSummary s = pp.SolveGaussNewton(true, planes);
      summary.plane_presolve_iterations = s.iterations;
      summary.damped_steps += s.damped;
      done = s.factorized;
    }
    if (!done) {
      ceres::Solver::Options planes = BaseSolverOptions(options);
      planes.max_num_iterations = options.plane_presolve_iterations;
      const ceres::Solver::Summary s = pp.SolveCeres(true, planes);
      summary.plane_presolve_iterations = static_cast<int>(s.iterations.size()) - 1;
    }
  }
  bool solved = false;
  if (own) {
    GaussNewtonOptions step;
    step.function_tolerance = options.function_tolerance;
    const GaussNewtonSummary s = pp.SolveGaussNewton(false, step);
    solved = s.factorized;
    summary.iterations = s.iterations;
    summary.damped_steps += s.damped;
    summary.termination = s.termination;
    summary.usable = true;  // a rejected step leaves the poses as they were
  }
  if (!solved) {
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
    const ceres::Solver::Summary s = pp.SolveCeres(false, solver);
    summary.iterations = static_cast<int>(s.iterations.size()) - 1;
    summary.termination = ceres::TerminationTypeToString(s.termination_type);
    summary.usable = s.IsSolutionUsable();
    for (const ceres::IterationSummary& it : s.iterations) summary.linear_iterations += it.linear_solver_iterations;
  }
  summary.cost_after = pp.TermCosts();
  if (!summary.usable) *poses = previous;  // a failed solve leaves the poses as they were
  for (Pose& p : *poses) p.rotation.normalize();
  if (!hold_first) {
    // Re-anchor: the one rigid motion that puts frame 0 back, applied to every pose.
    const Rigid3d world_from_solved = previous[0].ToRigid() * (*poses)[0].ToRigid().inverse();
    for (Pose& p : *poses) {
      p = Pose::FromRigid(world_from_solved * p.ToRigid());
      p.rotation.normalize();
    }
  }
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
          {"plane_presolve_iterations", s.plane_presolve_iterations},
          {"damped_steps", s.damped_steps},
          {"termination", s.termination},
          {"usable", s.usable},
          {"seconds", s.seconds}};
}

}  // namespace f2c
