#pragma once
// The constraints of one refinement iteration as plain data (refine/ detects them, optim/
// turns them into residual blocks). Points and directions are in their frame's camera
// coordinates, so a constraint does not change when poses do.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

namespace f2c {

// E_C: a feature of frame `point_frame` corresponds to the closest compatible feature of
// frame `target_frame`: a plane (point + normal) or an edge (point + unit direction).
enum class CorrespondenceKind : uint8_t { kPointToPlane, kPointToLine };

struct FeatureCorrespondence {
  int32_t target_frame = 0;  // frame a of the cost functors: its plane or line
  int32_t point_frame = 0;   // frame b: its point
  CorrespondenceKind kind = CorrespondenceKind::kPointToPlane;
  uint8_t feature_type = 0;  // FeatureType of the target feature (for statistics)
  float weight = 1;          // relative weight within E_C (the feature type's)
  Eigen::Vector3f target_point = Eigen::Vector3f::Zero();
  Eigen::Vector3f target_direction = Eigen::Vector3f::Zero();  // normal (planes) or edge direction
  Eigen::Vector3f point = Eigen::Vector3f::Zero();
};

// RelativePoseConstraint::weakest_inliers where no SIFT or tracked pair lies on the path.
inline constexpr int32_t kNoInlierCount = 1 << 30;

// E_L: the relative transform a_from_b that T0 holds between frames a and b, and how much
// it is trusted (relative weight within E_L, > 0). `measured`: every odometry pair on the
// path between a and b measured every direction of its motion (SIFT, tracking, or ICP that
// left nothing to the prediction), so the correspondences see what it says and may outvote it.
struct RelativePoseConstraint {
  int32_t frame_a = 0;
  int32_t frame_b = 0;
  Eigen::Quaterniond rotation_a_from_b = Eigen::Quaterniond::Identity();
  Eigen::Vector3d translation_a_from_b = Eigen::Vector3d::Zero();
  double weight = 1;
  bool measured = true;
  // The fewest RANSAC inliers of a SIFT or tracked pair on that path (ICP pairs count as
  // dense); kNoInlierCount where there is none.
  int32_t weakest_inliers = kNoInlierCount;
  // Where the odometry measured every pair on the path (refine/local_alignment.h): M of
  // RelativePoseCost (optim/cost_functions.h), a square root of the error's information
  // scaled to be dimensionless (a typical pair's translation rows near the identity), which
  // replaces the lever arm; `weight` still multiplies it. Zero: the scalar form.
  Eigen::Matrix<double, 6, 6> sqrt_information = Eigen::Matrix<double, 6, 6>::Zero();
  bool whitened() const { return !sqrt_information.isZero(); }
};

// E_V (beyond the paper): frames a, b, c consecutive in time, whose motion should be steady.
// scale_ab, scale_bc turn each increment into a velocity in units of a reference interval
// (reference dt / dt; refine/steady_motion.h).
struct SteadyMotionConstraint {
  int32_t frame_a = 0;
  int32_t frame_b = 0;
  int32_t frame_c = 0;
  double scale_ab = 1;
  double scale_bc = 1;
  double weight = 1;  // relative to the other triples (refine/steady_motion.h)
  // False where one of its odometry pairs left directions to the motion prior: there E_V is
  // the only measurement of those directions (SolverOptions::measured_velocity_loss_scale).
  bool measured = true;
};

// E_M (beyond the paper): a SIFT match between two frames the refinement re-matched (a loop
// or a bridge over weak odometry), verified by RANSAC: the same surface point seen in both.
struct PointMatch {
  int32_t frame_a = 0;
  int32_t frame_b = 0;
  Eigen::Vector3f point_a = Eigen::Vector3f::Zero();
  Eigen::Vector3f point_b = Eigen::Vector3f::Zero();
};

// The planar structural model (paper §4.2-4.3, E_S = w_P E_P + w_H E_H + w_G E_G).
// A child is a per-image proxy: a plane variable tied to its frame's supporting features
// (E_P), given by the plane the image fit and the moments of its members, in its camera's
// coordinates. A parent is a plane variable of its own, initialised in world coordinates
// from the coplanar children it clusters; links tie children to parents (E_H) and relations
// tie parents to each other (E_G).
struct ChildProxy {
  int32_t frame = 0;
  Eigen::Vector3f normal = Eigen::Vector3f::UnitZ();  // camera coordinates, unit
  float offset = 0;                                   // plane {x : normal . x = offset}
  Eigen::Vector3f centroid = Eigen::Vector3f::Zero();
  Eigen::Matrix3f covariance = Eigen::Matrix3f::Zero();  // of the members (m^2)
  float share = 1;                                       // relative weight within E_P: the proxy's m_j (its inliers)
};

struct PlaneEstimate {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // world coordinates, unit
  double offset = 0;                                  // the plane {x : normal . x = offset}
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();   // a point near the plane's middle
};

struct CoplanarLink {
  int32_t child = 0;
  int32_t parent = 0;
  Eigen::Vector3d anchor = Eigen::Vector3d::Zero();  // the child's centroid, world, when clustered
  float weight = 1;                                  // relative weight within E_H
  // How well the child agrees with its parent's other children, in (0, 1]: multiplies the
  // link's weight without entering E_H's normalising sum (refine/hierarchy.h).
  float agreement = 1;
};

enum class RelationType : uint8_t { kParallel = 0, kAntiparallel, kOrthogonal };
constexpr int kRelationTypeCount = 3;
const char* RelationTypeName(RelationType type);

struct PlaneRelation {
  int32_t parent_a = 0;
  int32_t parent_b = 0;
  RelationType type = RelationType::kParallel;
  float weight = 1;  // w_ab = exp(-(theta - theta_0)^2 / (2 sigma^2)), relative within E_G
};

struct StructureConstraints {
  std::vector<ChildProxy> children;
  std::vector<PlaneEstimate> parents;
  std::vector<CoplanarLink> links;       // E_H
  std::vector<PlaneRelation> relations;  // E_G
  bool empty() const { return children.empty(); }
};

// Everything one iteration's energy is built from.
struct Constraints {
  std::vector<FeatureCorrespondence> correspondences;  // E_C
  std::vector<RelativePoseConstraint> local;           // E_L
  std::vector<PointMatch> matches;                     // E_M
  StructureConstraints structure;                      // E_P, E_H, E_G
  std::vector<SteadyMotionConstraint> steady_motion;   // E_V
};

}  // namespace f2c
