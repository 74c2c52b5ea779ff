#include "f2c/optim/pose.h"

namespace f2c {

Pose Pose::FromRigid(const Rigid3d& transform) {
  Pose pose;
  pose.rotation = Eigen::Quaterniond(transform.linear()).normalized();
  pose.translation = transform.translation();
  return pose;
}

Rigid3d Pose::ToRigid() const {
  Rigid3d transform = Rigid3d::Identity();
  transform.linear() = rotation.normalized().toRotationMatrix();
  transform.translation() = translation;
  return transform;
}

}  // namespace f2c
