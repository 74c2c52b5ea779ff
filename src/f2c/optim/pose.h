#pragma once
// A camera pose in the form Ceres optimises: a unit quaternion and a translation, each its own
// parameter block (as COLMAP's Rigid3d and Ceres' pose_graph_3d example). The quaternion's
// coefficients are in Eigen's order (x, y, z, w), so ceres::EigenQuaternionManifold keeps it
// on the unit sphere. The transform is named like every other: a Pose holding
// world_from_camera maps camera coordinates to world coordinates.
//
// Why a second pose type beside Rigid3d (geometry/rigid.h, an Eigen::Isometry3d, which the
// readers, odometry, fusion and evaluation use): the solver needs each pose as two parameter
// blocks of its own, a unit quaternion (4 numbers on a 3-dimensional manifold) and a
// translation, stored where Ceres and our Gauss-Newton step can write them; an Isometry3d
// holds a 3x3 matrix, which no manifold keeps a rotation. Poses are Pose inside optim/ and
// refine/ (the refinement's state) and Rigid3d everywhere else; they are converted where the
// refinement starts and ends (RefineFineToCoarse, pipeline/register.cc) and where refine/
// transforms points (ToRigid).

#include <Eigen/Geometry>
#include <vector>

#include "f2c/geometry/rigid.h"

namespace f2c {

struct Pose {
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();

  static Pose FromRigid(const Rigid3d& transform);
  Rigid3d ToRigid() const;
  // Ceres parameter blocks.
  double* rotation_data() { return rotation.coeffs().data(); }
  double* translation_data() { return translation.data(); }
};

using PoseVector = std::vector<Pose, Eigen::aligned_allocator<Pose>>;

}  // namespace f2c
