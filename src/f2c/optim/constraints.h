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

// E_L: the relative transform a_from_b that T0 holds between frames a and b, and how much
// it is trusted (relative weight within E_L, > 0).
struct RelativePoseConstraint {
  int32_t frame_a = 0;
  int32_t frame_b = 0;
  Eigen::Quaterniond rotation_a_from_b = Eigen::Quaterniond::Identity();
  Eigen::Vector3d translation_a_from_b = Eigen::Vector3d::Zero();
  double weight = 1;
};

// E_M (beyond the paper): a SIFT match between two frames the refinement re-matched (a loop
// or a bridge over weak odometry), verified by RANSAC: the same surface point seen in both.
struct PointMatch {
  int32_t frame_a = 0;
  int32_t frame_b = 0;
  Eigen::Vector3f point_a = Eigen::Vector3f::Zero();
  Eigen::Vector3f point_b = Eigen::Vector3f::Zero();
};

// Everything one iteration's energy is built from.
struct Constraints {
  std::vector<FeatureCorrespondence> correspondences;  // E_C
  std::vector<RelativePoseConstraint> local;           // E_L
  std::vector<PointMatch> matches;                     // E_M
};

}  // namespace f2c
