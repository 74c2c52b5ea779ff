#include "f2c/optim/cost_functions.h"

namespace f2c {

using Matrix34 = Eigen::Matrix<double, 3, 4, Eigen::RowMajor>;

Eigen::Matrix3d Skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d s;
  s << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return s;
}

// Eigen's q * v is the polynomial Rot(q, v) = v + 2 w (u x v) + 2 u x (u x v) = M(q) v with
// M(q) = I + 2 w [u]x + 2 [u]x^2 (a rotation for unit q). M(conj q) = M(q)^T for any q.
Eigen::Matrix3d RotationPolynomial(const double* q) {
  const Eigen::Matrix3d s = Skew(Eigen::Vector3d(q[0], q[1], q[2]));
  return Eigen::Matrix3d::Identity() + 2 * q[3] * s + 2 * s * s;
}

// d Rot(q, v) / d(x, y, z, w).
Matrix34 RotationDerivative(const double* q, const Eigen::Vector3d& v) {
  const Eigen::Map<const Eigen::Vector3d> u(q);
  Matrix34 d;
  d.leftCols<3>() =
      -2 * q[3] * Skew(v) + 2 * (u.dot(v) * Eigen::Matrix3d::Identity() + u * v.transpose() - 2 * v * u.transpose());
  d.col(3) = 2 * u.cross(v);
  return d;
}

void EvaluateConstraint(ConstraintKind kind, const PosePair& poses, const Eigen::Vector3d& target_point,
                        const Eigen::Vector3d& target_direction, const Eigen::Vector3d& point, bool jacobians,
                        ConstraintRows* out) {
  const Eigen::Map<const Eigen::Vector3d> t_a(poses.t_a), t_b(poses.t_b);
  out->jacobian.setZero();
  switch (kind) {
    case ConstraintKind::kPointToPlane: {
      // r = n_a . (M(q_a)^T y - p_a) = m . y - n_a . p_a with y = Rot(q_b, p_b) + t_b - t_a and
      // m = M(q_a) n_a. So dr/dt_b = m^T = -dr/dt_a, dr/dq_b = m^T dRot(q_b, p_b)/dq_b and
      // dr/dq_a = y^T dRot(q_a, n_a)/dq_a.
      out->rows = 1;
      const Eigen::Vector3d m = poses.m_a * target_direction;
      const Eigen::Vector3d y = poses.m_b * point + t_b - t_a;
      out->residual[0] = m.dot(y) - target_direction.dot(target_point);
      if (!jacobians) return;
      out->jacobian.block<1, 4>(0, 0) = y.transpose() * RotationDerivative(poses.q_a, target_direction);
      out->jacobian.block<1, 3>(0, 4) = -m.transpose();
      out->jacobian.block<1, 4>(0, 7) = m.transpose() * RotationDerivative(poses.q_b, point);
      out->jacobian.block<1, 3>(0, 11) = m.transpose();
      return;
    }
    case ConstraintKind::kPointToLine: {
      // r = (z - p_a) x d_a = -[d_a]x (z - p_a) with z = M(q_a)^T y, y as above. dz/dy = M(q_a)^T;
      // z = Rot(conj q_a, y), so dz/du_a = -dRot/du at conj q_a and dz/dw_a = dRot/dw there.
      out->rows = 3;
      const Eigen::Vector3d y = poses.m_b * point + t_b - t_a;
      const Eigen::Vector3d z = poses.m_a.transpose() * y;
      out->residual.head<3>() = (z - target_point).cross(target_direction);
      if (!jacobians) return;
      const Eigen::Matrix3d dr_dz = -Skew(target_direction);
      const Eigen::Matrix3d dr_dy = dr_dz * poses.m_a.transpose();
      const double conj[4] = {-poses.q_a[0], -poses.q_a[1], -poses.q_a[2], poses.q_a[3]};
      Matrix34 dz = RotationDerivative(conj, y);
      dz.leftCols<3>() *= -1;
      out->jacobian.block<3, 4>(0, 0) = dr_dz * dz;
      out->jacobian.block<3, 3>(0, 4) = -dr_dy;
      out->jacobian.block<3, 4>(0, 7) = dr_dy * RotationDerivative(poses.q_b, point);
      out->jacobian.block<3, 3>(0, 11) = dr_dy;
      return;
    }
    case ConstraintKind::kPointToPoint: {
      // r = Rot(q_a, p_a) + t_a - Rot(q_b, p_b) - t_b.
      out->rows = 3;
      out->residual.head<3>() = poses.m_a * target_point + t_a - poses.m_b * point - t_b;
      if (!jacobians) return;
      out->jacobian.block<3, 4>(0, 0) = RotationDerivative(poses.q_a, target_point);
      out->jacobian.block<3, 3>(0, 4) = Eigen::Matrix3d::Identity();
      out->jacobian.block<3, 4>(0, 7) = -RotationDerivative(poses.q_b, point);
      out->jacobian.block<3, 3>(0, 11) = -Eigen::Matrix3d::Identity();
      return;
    }
  }
}

PosePair::PosePair(double const* const* parameters)
    : q_a(parameters[0]),
      t_a(parameters[1]),
      q_b(parameters[2]),
      t_b(parameters[3]),
      m_a(RotationPolynomial(parameters[0])),
      m_b(RotationPolynomial(parameters[2])) {}

}  // namespace f2c
