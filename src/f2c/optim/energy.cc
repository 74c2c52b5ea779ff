#include "f2c/optim/energy.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "f2c/optim/cost_functions.h"
#include "f2c/util/error.h"

namespace f2c {
namespace {

// A term's Cauchy scale where some of its constraints have a scale of their own (0: none):
// the tighter of the two holds for those.
double TighterLossScale(double scale, double own) { return own > 0 && (scale == 0 || own < scale) ? own : scale; }

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

using PairKey = std::pair<int, int>;

}  // namespace

Energy::Energy(const Constraints& constraints, const SolverOptions& options, const PoseVector& previous,
               PoseVector* poses, PoseProblem* problem)
    : constraints_(constraints),
      options_(options),
      previous_(previous),
      poses_(*poses),
      problem_(*problem),
      n_(static_cast<int>(poses->size())) {}

std::vector<double*> Energy::PairBlocks(int a, int b) {
  Pose& pa = poses_[a];
  Pose& pb = poses_[b];
  return {pa.rotation_data(), pa.translation_data(), pb.rotation_data(), pb.translation_data()};
}

// E_C: point-to-plane and point-to-line, each weighted w_C v_i / sum(v), robustified; one
// residual block per ordered frame pair (optim/pair_cost.h).
void Energy::AddCorrespondences() {
  const std::vector<FeatureCorrespondence>& correspondences = constraints_.correspondences;
  double sum_c = 0;
  for (const FeatureCorrespondence& c : correspondences) sum_c += c.weight;
  if (options_.weight_correspondence <= 0 || sum_c <= 0) return;
  for (const FeatureCorrespondence& c : correspondences) {
    F2C_CHECK(c.target_frame >= 0 && c.target_frame < n_ && c.point_frame >= 0 && c.point_frame < n_,
              "correspondence frames in range");
  }
  auto by_pair = GroupByKey(
      correspondences.size(),
      [&](size_t i) {
        return PairKey{correspondences[i].target_frame, correspondences[i].point_frame};
      },
      [&](size_t i) {
        const FeatureCorrespondence& c = correspondences[i];
        PairConstraint pc;
        pc.kind =
            c.kind == CorrespondenceKind::kPointToPlane ? ConstraintKind::kPointToPlane : ConstraintKind::kPointToLine;
        pc.weight = options_.weight_correspondence * c.weight / sum_c;
        pc.target_point = c.target_point.cast<double>();
        pc.target_direction = c.target_direction.cast<double>();
        pc.point = c.point.cast<double>();
        return pc;
      });
  for (auto& [key, list] : by_pair) {
    const std::vector<double*> b = PairBlocks(key.first, key.second);
    problem_.AddPair(Term::kC, new PairCost(std::move(list), options_.loss, options_.loss_scale, b.data()), b);
  }
}

// E_L: relative transforms of T0, w_L v_i / sum(v); rotations at the lever arm, or each
// constraint whitened by its own information.
void Energy::AddLocal() {
  const std::vector<RelativePoseConstraint>& local = constraints_.local;
  double sum_l = 0;
  for (const RelativePoseConstraint& l : local) sum_l += l.weight;
  if (options_.weight_local == 0 || sum_l <= 0) return;
  for (const RelativePoseConstraint& l : local) {
    F2C_CHECK(l.frame_a >= 0 && l.frame_a < n_ && l.frame_b >= 0 && l.frame_b < n_, "local frames in range");
    const bool weak =
        options_.measured_local_loss_max_inliers == 0 || l.weakest_inliers < options_.measured_local_loss_max_inliers;
    const double scale = l.measured && weak
                             ? TighterLossScale(options_.local_loss_scale, options_.measured_local_loss_scale)
                             : options_.local_loss_scale;
    const auto [s, loss] = problem_.Weigh(options_.weight_local * l.weight / sum_l, scale, Term::kL);
    ceres::CostFunction* cost =
        l.whitened()
            ? RelativePoseCost::Create(l.rotation_a_from_b, l.translation_a_from_b, s * l.sqrt_information)
            : RelativePoseCost::Create(l.rotation_a_from_b, l.translation_a_from_b, s, s * options_.rotation_lever_arm);
    problem_.Add(Term::kL, cost, loss, PairBlocks(l.frame_a, l.frame_b));
  }
}

// E_V: steady motion over consecutive frames, w_V / (number of triples) each; rotations at
// the lever arm.
void Energy::AddSteadyMotion() {
  const std::vector<SteadyMotionConstraint>& steady = constraints_.steady_motion;
  const double w_v = steady.empty() ? 0.0 : options_.weight_velocity / static_cast<double>(steady.size());
  if (w_v == 0) return;
  for (const SteadyMotionConstraint& v : steady) {
    F2C_CHECK(v.frame_a >= 0 && v.frame_a < n_ && v.frame_b >= 0 && v.frame_b < n_ && v.frame_c >= 0 && v.frame_c < n_,
              "steady-motion frames in range");
    Pose& pa = poses_[v.frame_a];
    Pose& pb = poses_[v.frame_b];
    Pose& pc = poses_[v.frame_c];
    std::vector<double*> b{pa.rotation_data(),    pa.translation_data(), pb.rotation_data(),
                           pb.translation_data(), pc.rotation_data(),    pc.translation_data()};
    const double scale = v.measured
                             ? TighterLossScale(options_.velocity_loss_scale, options_.measured_velocity_loss_scale)
                             : options_.velocity_loss_scale;
    const auto [s, loss] = problem_.Weigh(w_v * v.weight, scale, Term::kV);
    problem_.Add(Term::kV, SteadyMotionCost::Create(v.scale_ab, v.scale_bc, s, s * options_.rotation_lever_arm), loss,
                 std::move(b));
  }
}

// E_M: SIFT matches, w_M / n each, robustified, batched per frame pair.
void Energy::AddMatches() {
  if (options_.weight_match <= 0) return;
  const std::vector<PointMatch>& matches = constraints_.matches;
  for (const PointMatch& m : matches) {
    F2C_CHECK(m.frame_a >= 0 && m.frame_a < n_ && m.frame_b >= 0 && m.frame_b < n_, "match frames in range");
  }
  auto by_pair = GroupByKey(
      matches.size(),
      [&](size_t i) {
        return PairKey{matches[i].frame_a, matches[i].frame_b};
      },
      [&](size_t i) {
        PairConstraint pc;
        pc.kind = ConstraintKind::kPointToPoint;
        pc.weight = options_.weight_match / n_;
        pc.target_point = matches[i].point_a.cast<double>();
        pc.point = matches[i].point_b.cast<double>();
        return pc;
      });
  for (auto& [key, list] : by_pair) {
    const std::vector<double*> b = PairBlocks(key.first, key.second);
    problem_.AddPair(Term::kM, new PairCost(std::move(list), RobustLoss::kCauchy, options_.match_loss_scale, b.data()),
                     b);
  }
}

// The structural model. Children start where their frame's pose puts the image's plane
// (E_P starts at the image's own fit residual); parents where the hierarchy fitted them.
// Without E_P children would float free of their frames, so w_P = 0 turns it all off.
void Energy::AddStructure() {
  const StructureConstraints& structure = constraints_.structure;
  use_structure_ = !structure.empty() && options_.weight_proxy > 0;
  if (!use_structure_) return;
  children_.resize(structure.children.size());
  parents_.resize(structure.parents.size());
  double sum_p = 0;
  for (const ChildProxy& c : structure.children) sum_p += c.share;
  for (size_t i = 0; i < children_.size(); ++i) {
    const ChildProxy& c = structure.children[i];
    F2C_CHECK(c.frame >= 0 && c.frame < n_, "child proxy frame in range");
    Pose& pose = poses_[c.frame];
    const Eigen::Vector3d normal = (pose.rotation * c.normal.cast<double>()).normalized();
    children_[i].reference = pose.rotation * c.centroid.cast<double>() + pose.translation;
    children_[i].Set(normal, c.offset + normal.dot(pose.translation) - normal.dot(children_[i].reference));
    problem_.AddPlane(&children_[i]);
    // E_P: w_P m_j / sum(m) times the members' mean squared distance.
    const double s = std::sqrt(options_.weight_proxy * c.share / sum_p);
    problem_.AddStructure(Term::kP,
                          ProxyFitCost::Create(c.centroid.cast<double>(),
                                               s * SqrtCovariance(c.covariance.cast<double>()), children_[i].reference),
                          nullptr, {pose.rotation_data(), pose.translation_data(), children_[i].data()});
  }
  for (size_t i = 0; i < parents_.size(); ++i) {
    const Eigen::Vector3d normal = structure.parents[i].normal.normalized();
    parents_[i].reference = structure.parents[i].centre;
    parents_[i].Set(normal, structure.parents[i].offset - normal.dot(parents_[i].reference));
    problem_.AddPlane(&parents_[i]);
  }
  // E_H: w_H a v / sum(v) per link (a: the link's agreement with its siblings).
  double sum_h = 0;
  for (const CoplanarLink& l : structure.links) sum_h += l.weight;
  for (const CoplanarLink& l : structure.links) {
    if (options_.weight_coplanarity == 0 || sum_h <= 0) break;
    F2C_CHECK(l.child >= 0 && l.child < static_cast<int>(children_.size()) && l.parent >= 0 &&
                  l.parent < static_cast<int>(parents_.size()),
              "coplanarity link in range");
    PlaneVariable& c = children_[l.child];
    PlaneVariable& p = parents_[l.parent];
    const auto [s, loss] = problem_.Weigh(options_.weight_coplanarity * l.weight * l.agreement / sum_h,
                                          options_.coplanarity_loss_scale, Term::kH);
    problem_.AddStructure(Term::kH,
                          CoplanarityCost::Create(l.anchor, options_.rotation_lever_arm, s, c.reference, p.reference),
                          loss, {c.data(), p.data()});
  }
  // E_G: w_G w_ab / sum(w) per relation.
  double sum_g = 0;
  for (const PlaneRelation& r : structure.relations) sum_g += r.weight;
  for (const PlaneRelation& r : structure.relations) {
    if (options_.weight_relation == 0 || sum_g <= 0) break;
    F2C_CHECK(r.parent_a >= 0 && r.parent_a < static_cast<int>(parents_.size()) && r.parent_b >= 0 &&
                  r.parent_b < static_cast<int>(parents_.size()) && r.parent_a != r.parent_b,
              "relation parents in range");
    const auto [s, loss] = problem_.Weigh(options_.weight_relation * r.weight / sum_g,
                                          options_.relation_loss_scale_deg * M_PI / 180, Term::kG);
    ceres::CostFunction* cost = r.type == RelationType::kOrthogonal
                                    ? OrthogonalCost::Create(s)
                                    : ParallelCost::Create(r.type == RelationType::kParallel ? 1.0 : -1.0, s);
    problem_.AddStructure(Term::kG, cost, loss, {parents_[r.parent_a].data(), parents_[r.parent_b].data()});
  }
}

// E_I: each pose's change in this solve, w_I / n per pose; each parent plane's, w_I / parents.
// Children follow their frames through E_P (an inertia of their own would hold the frames
// back).
void Energy::AddInertia(int first_free) {
  if (options_.weight_inertia <= 0) return;
  const double s = std::sqrt(options_.weight_inertia / n_);
  for (int i = first_free; i < n_; ++i) {
    Pose& p = poses_[i];
    problem_.Add(
        Term::kI,
        PoseChangeCost::Create(previous_[i].rotation, previous_[i].translation, s, s * options_.rotation_lever_arm),
        nullptr, {p.rotation_data(), p.translation_data()});
  }
  if (!use_structure_ || parents_.empty()) return;
  const double sp = std::sqrt(options_.weight_inertia / static_cast<double>(parents_.size()));
  for (PlaneVariable& v : parents_) {
    problem_.AddStructure(Term::kI,
                          PlaneChangeCost::Create(v.normal(), v.plane[3], sp * options_.rotation_lever_arm, sp),
                          nullptr, {v.data()});
  }
}

}  // namespace f2c
