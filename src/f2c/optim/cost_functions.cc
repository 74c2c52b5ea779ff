#include "f2c/optim/cost_functions.h"

namespace f2c {
namespace {

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

// Writes a Jacobian block (Ceres: row-major).
template <typename Derived>
void Store(const Eigen::MatrixBase<Derived>& value, double* out) {
  constexpr int kRows = Derived::RowsAtCompileTime, kCols = Derived::ColsAtCompileTime;
  Eigen::Map<Eigen::Matrix<double, kRows, kCols, kCols == 1 ? Eigen::ColMajor : Eigen::RowMajor>> map(out);
  map = value;
}

}  // namespace

bool AnalyticPointToPlaneCost::Evaluate(double const* const* parameters, double* residuals,
                                        double** jacobians) const {
  // r = n_a . (M(q_a)^T y - p_a) = m . y - n_a . p_a with y = Rot(q_b, p_b) + t_b - t_a and
  // m = M(q_a) n_a. So dr/dt_b = m^T = -dr/dt_a, dr/dq_b = m^T dRot(q_b, p_b)/dq_b and
  // dr/dq_a = y^T dRot(q_a, n_a)/dq_a.
  const double* q_a = parameters[0];
  const Eigen::Map<const Eigen::Vector3d> t_a(parameters[1]);
  const double* q_b = parameters[2];
  const Eigen::Map<const Eigen::Vector3d> t_b(parameters[3]);
  const Eigen::Vector3d m = RotationPolynomial(q_a) * normal_in_a_;
  const Eigen::Vector3d y = RotationPolynomial(q_b) * point_in_b_ + t_b - t_a;
  residuals[0] = m.dot(y) - normal_in_a_.dot(point_in_a_);
  if (jacobians == nullptr) return true;
  if (jacobians[0]) Store(y.transpose() * RotationDerivative(q_a, normal_in_a_), jacobians[0]);
  if (jacobians[1]) Store(-m.transpose(), jacobians[1]);
  if (jacobians[2]) Store(m.transpose() * RotationDerivative(q_b, point_in_b_), jacobians[2]);
  if (jacobians[3]) Store(m.transpose(), jacobians[3]);
  return true;
}

bool AnalyticPointToLineCost::Evaluate(double const* const* parameters, double* residuals,
                                       double** jacobians) const {
  // r = (z - p_a) x d_a = -[d_a]x (z - p_a) with z = M(q_a)^T y, y as above. dz/dy = M(q_a)^T;
  // z = Rot(conj q_a, y), so dz/du_a = -dRot/du at conj q_a and dz/dw_a = dRot/dw there.
  const double* q_a = parameters[0];
  const Eigen::Map<const Eigen::Vector3d> t_a(parameters[1]);
  const double* q_b = parameters[2];
  const Eigen::Map<const Eigen::Vector3d> t_b(parameters[3]);
  const Eigen::Matrix3d m_a_transpose = RotationPolynomial(q_a).transpose();
  const Eigen::Vector3d y = RotationPolynomial(q_b) * point_in_b_ + t_b - t_a;
  const Eigen::Vector3d z = m_a_transpose * y;
  Store((z - point_in_a_).cross(direction_in_a_), residuals);
  if (jacobians == nullptr) return true;
  const Eigen::Matrix3d dr_dz = -Skew(direction_in_a_);
  const Eigen::Matrix3d dr_dy = dr_dz * m_a_transpose;
  if (jacobians[0]) {
    const double conj[4] = {-q_a[0], -q_a[1], -q_a[2], q_a[3]};
    Matrix34 dz = RotationDerivative(conj, y);
    dz.leftCols<3>() *= -1;
    Store(dr_dz * dz, jacobians[0]);
  }
  if (jacobians[1]) Store(-dr_dy, jacobians[1]);
  if (jacobians[2]) Store(dr_dy * RotationDerivative(q_b, point_in_b_), jacobians[2]);
  if (jacobians[3]) Store(dr_dy, jacobians[3]);
  return true;
}

}  // namespace f2c
