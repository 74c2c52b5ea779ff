#include "f2c/geometry/rigid.h"

#include <fmt/format.h>

#include <Eigen/SVD>
#include <cmath>

#include "f2c/util/error.h"

namespace f2c {
namespace {

[[noreturn]] void Fail(const std::filesystem::path& path, int line, const std::string& what) {
  if (line > 0) ThrowInputError(path, line, what);
  ThrowInputError(path, what);
}

void CheckPosition(const Eigen::Vector3d& t, const std::filesystem::path& path, int line) {
  const double distance = t.stableNorm();  // norm() squares: 1e155 would print as inf
  if (distance > kMaxCoordinateMetres) {
    Fail(path, line,
         fmt::format("pose lies {:.3g} m from the origin (at most {:g} m)", distance, kMaxCoordinateMetres));
  }
}

}  // namespace

Rigid3d InterpolatePose(const Rigid3d& a, const Rigid3d& b, double u) {
  Rigid3d pose = Rigid3d::Identity();
  pose.linear() = Eigen::Quaterniond(a.linear()).slerp(u, Eigen::Quaterniond(b.linear())).toRotationMatrix();
  pose.translation() = (1 - u) * a.translation() + u * b.translation();
  return pose;
}

double RotationAngle(const Eigen::Matrix3d& rotation) {
  // atan2 of sin and cos keeps precision near 0 and pi, where acos(cos) loses half the digits.
  const Eigen::Vector3d v(rotation(2, 1) - rotation(1, 2), rotation(0, 2) - rotation(2, 0),
                          rotation(1, 0) - rotation(0, 1));
  return std::atan2(0.5 * v.norm(), 0.5 * (rotation.trace() - 1.0));
}

Rigid3d RigidFromMatrixOrThrow(const Eigen::Matrix4d& matrix, const std::filesystem::path& path, int line,
                               double tolerance) {
  if (!matrix.allFinite()) Fail(path, line, "pose is not finite (NaN or infinity)");
  CheckPosition(matrix.topRightCorner<3, 1>(), path, line);
  if ((matrix.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > tolerance) {
    Fail(path, line, "pose's bottom row is not 0 0 0 1");
  }
  const Eigen::Matrix3d r = matrix.topLeftCorner<3, 3>();
  const double orthogonality = (r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (orthogonality > tolerance || r.determinant() < 0) {
    Fail(path, line,
         fmt::format("pose is not rigid (max |R^T R - I| = {:.3g}, det R = {:.3g})", orthogonality, r.determinant()));
  }
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(r, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Rigid3d result = Rigid3d::Identity();
  result.linear() = svd.matrixU() * svd.matrixV().transpose();
  result.translation() = matrix.topRightCorner<3, 1>();
  return result;
}

Rigid3d RigidFromQuaternionOrThrow(const Eigen::Vector3d& translation, const Eigen::Vector4d& quaternion_xyzw,
                                   const std::filesystem::path& path, int line, double tolerance) {
  if (!translation.allFinite() || !quaternion_xyzw.allFinite()) {
    Fail(path, line, "pose is not finite (NaN or infinity)");
  }
  CheckPosition(translation, path, line);
  const double norm = quaternion_xyzw.norm();
  if (std::abs(norm - 1.0) > tolerance) {
    Fail(path, line, fmt::format("quaternion is not unit (norm {:.4g})", norm));
  }
  const Eigen::Quaterniond q(quaternion_xyzw[3], quaternion_xyzw[0], quaternion_xyzw[1], quaternion_xyzw[2]);
  Rigid3d result = Rigid3d::Identity();
  result.linear() = q.normalized().toRotationMatrix();
  result.translation() = translation;
  return result;
}

}  // namespace f2c
