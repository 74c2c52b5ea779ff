#pragma once
// The residuals of the refinement's energy (paper §4.3), as small templated functors for
// ceres::AutoDiffCostFunction. Poses are world_from_camera as optimised (optim/pose.h): a
// quaternion block q (Eigen order x, y, z, w) and a translation block t, so
//   x_world = R(q) x_camera + t.
// Residuals are the unweighted errors in metres (and radians where a rotation is compared);
// the problem builder (optim/problem.h) applies each term's weight and robust loss.

#include <ceres/autodiff_cost_function.h>
#include <ceres/rotation.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace f2c {

// Frame a's coordinates of a point given in frame b's: R_a^T (R_b p_b + t_b - t_a).
template <typename T>
Eigen::Matrix<T, 3, 1> PointFromBIntoA(const T* rotation_a, const T* translation_a, const T* rotation_b,
                                       const T* translation_b, const Eigen::Vector3d& point_in_b) {
  const Eigen::Map<const Eigen::Quaternion<T>> q_a(rotation_a);
  const Eigen::Map<const Eigen::Quaternion<T>> q_b(rotation_b);
  const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t_a(translation_a);
  const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t_b(translation_b);
  const Eigen::Matrix<T, 3, 1> point_in_world = q_b * point_in_b.cast<T>() + t_b;
  return q_a.conjugate() * (point_in_world - t_a);
}

// E_C for planar features (paper §4.3, "Feature Correspondence Error"):
//   r = n_a . (p_b - p_a)
// with p_a, n_a frame a's feature and p_b frame b's, all in world coordinates. Rotations keep
// dot products, so it is evaluated in frame a: r = n_a . (R_a^T (R_b p_b + t_b - t_a) - p_a).
// One residual, metres.
struct PointToPlaneCost {
  PointToPlaneCost(const Eigen::Vector3d& point_in_a, const Eigen::Vector3d& normal_in_a,
                   const Eigen::Vector3d& point_in_b)
      : point_in_a_(point_in_a), normal_in_a_(normal_in_a), point_in_b_(point_in_b) {}

  template <typename T>
  bool operator()(const T* rotation_a, const T* translation_a, const T* rotation_b, const T* translation_b,
                  T* residual) const {
    const Eigen::Matrix<T, 3, 1> p_b =
        PointFromBIntoA(rotation_a, translation_a, rotation_b, translation_b, point_in_b_);
    residual[0] = normal_in_a_.cast<T>().dot(p_b - point_in_a_.cast<T>());
    return true;
  }

  static ceres::CostFunction* Create(const Eigen::Vector3d& point_in_a, const Eigen::Vector3d& normal_in_a,
                                     const Eigen::Vector3d& point_in_b) {
    return new ceres::AutoDiffCostFunction<PointToPlaneCost, 1, 4, 3, 4, 3>(
        new PointToPlaneCost(point_in_a, normal_in_a, point_in_b));
  }

 private:
  Eigen::Vector3d point_in_a_, normal_in_a_, point_in_b_;
};

// E_C for edge features (paper §4.3): the distance of p_b from the line through p_a along
// frame a's unit edge direction d_a,
//   r = (p_b - p_a) x d_a       (three residuals; |r| is the distance, metres)
// evaluated in frame a as above (a rotation of the cross product keeps its length).
struct PointToLineCost {
  PointToLineCost(const Eigen::Vector3d& point_in_a, const Eigen::Vector3d& direction_in_a,
                  const Eigen::Vector3d& point_in_b)
      : point_in_a_(point_in_a), direction_in_a_(direction_in_a), point_in_b_(point_in_b) {}

  template <typename T>
  bool operator()(const T* rotation_a, const T* translation_a, const T* rotation_b, const T* translation_b,
                  T* residual) const {
    const Eigen::Matrix<T, 3, 1> p_b =
        PointFromBIntoA(rotation_a, translation_a, rotation_b, translation_b, point_in_b_);
    const Eigen::Matrix<T, 3, 1> r = (p_b - point_in_a_.cast<T>()).cross(direction_in_a_.cast<T>());
    residual[0] = r[0];
    residual[1] = r[1];
    residual[2] = r[2];
    return true;
  }

  static ceres::CostFunction* Create(const Eigen::Vector3d& point_in_a, const Eigen::Vector3d& direction_in_a,
                                     const Eigen::Vector3d& point_in_b) {
    return new ceres::AutoDiffCostFunction<PointToLineCost, 3, 4, 3, 4, 3>(
        new PointToLineCost(point_in_a, direction_in_a, point_in_b));
  }

 private:
  Eigen::Vector3d point_in_a_, direction_in_a_, point_in_b_;
};

// The misalignment of two rigid transforms, E_t of the paper's E_L: with the measured
// a_from_b = (q_m, t_m) and the estimate a_from_b = T_a^-1 T_b = (q_a^-1 q_b, q_a^-1 (t_b - t_a)),
//   e[0..2] = t_est - t_m                           metres, in a's coordinates
//   e[3..5] = 2 vec(q_m^-1 q_est)                   radians for small errors (|.| = 2 sin(angle/2)),
//                                                   in b's coordinates
//   r = M e
// M is a square root of the constraint's information (M^T M), upper triangular where it
// comes from the odometry's fit (refine/local_alignment.h); the scalar form
// M = diag(s_t, s_t, s_t, s_r, s_r, s_r) takes square roots of the weights (s_r converts
// radians to the units the energy compares them in, metres at a lever arm of s_r / s_t).
struct RelativePoseCost {
  using Matrix6d = Eigen::Matrix<double, 6, 6>;
  RelativePoseCost(const Eigen::Quaterniond& measured_rotation_a_from_b,
                   const Eigen::Vector3d& measured_translation_a_from_b, const Matrix6d& sqrt_information)
      : rotation_inverse_(measured_rotation_a_from_b.conjugate()),
        translation_(measured_translation_a_from_b),
        sqrt_information_(sqrt_information) {}

  template <typename T>
  bool operator()(const T* rotation_a, const T* translation_a, const T* rotation_b, const T* translation_b,
                  T* residual) const {
    const Eigen::Map<const Eigen::Quaternion<T>> q_a(rotation_a);
    const Eigen::Map<const Eigen::Quaternion<T>> q_b(rotation_b);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t_a(translation_a);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t_b(translation_b);
    const Eigen::Quaternion<T> q_a_inverse = q_a.conjugate();
    const Eigen::Matrix<T, 3, 1> t_est = q_a_inverse * (t_b - t_a);
    const Eigen::Quaternion<T> delta = rotation_inverse_.cast<T>() * (q_a_inverse * q_b);
    Eigen::Matrix<T, 6, 1> e;
    e.template head<3>() = t_est - translation_.cast<T>();
    e.template tail<3>() = T(2.0) * delta.vec();
    Eigen::Map<Eigen::Matrix<T, 6, 1>> r(residual);
    r = sqrt_information_.cast<T>() * e;
    return true;
  }

  static ceres::CostFunction* Create(const Eigen::Quaterniond& measured_rotation_a_from_b,
                                     const Eigen::Vector3d& measured_translation_a_from_b,
                                     const Matrix6d& sqrt_information) {
    return new ceres::AutoDiffCostFunction<RelativePoseCost, 6, 4, 3, 4, 3>(
        new RelativePoseCost(measured_rotation_a_from_b, measured_translation_a_from_b, sqrt_information));
  }
  static ceres::CostFunction* Create(const Eigen::Quaterniond& measured_rotation_a_from_b,
                                     const Eigen::Vector3d& measured_translation_a_from_b,
                                     double sqrt_weight_translation, double sqrt_weight_rotation) {
    Matrix6d m = Matrix6d::Zero();
    m.diagonal() << sqrt_weight_translation, sqrt_weight_translation, sqrt_weight_translation, sqrt_weight_rotation,
        sqrt_weight_rotation, sqrt_weight_rotation;
    return Create(measured_rotation_a_from_b, measured_translation_a_from_b, m);
  }

 private:
  Eigen::Quaterniond rotation_inverse_;
  Eigen::Vector3d translation_;
  Matrix6d sqrt_information_;
};

// E_V, steady motion (beyond the paper): three poses a, b, c consecutive in time should move
// at a steady velocity. With each turn as a rotation vector in the earlier frame's
// coordinates (log(q_a^-1 q_b), log(q_b^-1 q_c)) and each step in the world,
//   r[0..2] = s_t (f_bc (t_c - t_b) - f_ab (t_b - t_a))                 metres
//   r[3..5] = s_r (f_bc log(q_b^-1 q_c) - f_ab log(q_a^-1 q_b))         radians
// f_ab, f_bc scale each increment to a velocity per reference interval (dt_reference / dt),
// so a dropped frame does not read as a jolt. Zero for any constant linear and angular velocity
// (a screw motion), also across intervals of different lengths.
struct SteadyMotionCost {
  SteadyMotionCost(double scale_ab, double scale_bc, double sqrt_weight_translation, double sqrt_weight_rotation)
      : f_ab_(scale_ab), f_bc_(scale_bc), s_t_(sqrt_weight_translation), s_r_(sqrt_weight_rotation) {}

  template <typename T>
  bool operator()(const T* rotation_a, const T* translation_a, const T* rotation_b, const T* translation_b,
                  const T* rotation_c, const T* translation_c, T* residual) const {
    const Eigen::Map<const Eigen::Quaternion<T>> q_a(rotation_a);
    const Eigen::Map<const Eigen::Quaternion<T>> q_b(rotation_b);
    const Eigen::Map<const Eigen::Quaternion<T>> q_c(rotation_c);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t_a(translation_a);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t_b(translation_b);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t_c(translation_c);
    const Eigen::Matrix<T, 3, 1> turn_ab = RotationVector<T>(q_a.conjugate() * q_b);
    const Eigen::Matrix<T, 3, 1> turn_bc = RotationVector<T>(q_b.conjugate() * q_c);
    for (int i = 0; i < 3; ++i) {
      residual[i] = T(s_t_) * (T(f_bc_) * (t_c[i] - t_b[i]) - T(f_ab_) * (t_b[i] - t_a[i]));
      residual[3 + i] = T(s_r_) * (T(f_bc_) * turn_bc[i] - T(f_ab_) * turn_ab[i]);
    }
    return true;
  }

  static ceres::CostFunction* Create(double scale_ab, double scale_bc, double sqrt_weight_translation,
                                     double sqrt_weight_rotation) {
    return new ceres::AutoDiffCostFunction<SteadyMotionCost, 6, 4, 3, 4, 3, 4, 3>(
        new SteadyMotionCost(scale_ab, scale_bc, sqrt_weight_translation, sqrt_weight_rotation));
  }

 private:
  // The rotation vector (axis times angle) of a unit quaternion, by Ceres'
  // QuaternionToAngleAxis (order w, x, y, z; it takes the short way round for w < 0 and has
  // exact derivatives at zero).
  template <typename T>
  static Eigen::Matrix<T, 3, 1> RotationVector(const Eigen::Quaternion<T>& q) {
    const T wxyz[4] = {q.w(), q.x(), q.y(), q.z()};
    Eigen::Matrix<T, 3, 1> v;
    ceres::QuaternionToAngleAxis(wxyz, v.data());
    return v;
  }

  double f_ab_, f_bc_, s_t_, s_r_;
};

// E_M, SIFT matches (beyond the paper): the two sightings of one point, in the world,
//   r = (R_a p_a + t_a) - (R_b p_b + t_b)        three residuals, metres.
struct PointToPointCost {
  PointToPointCost(const Eigen::Vector3d& point_in_a, const Eigen::Vector3d& point_in_b)
      : point_in_a_(point_in_a), point_in_b_(point_in_b) {}

  template <typename T>
  bool operator()(const T* rotation_a, const T* translation_a, const T* rotation_b, const T* translation_b,
                  T* residual) const {
    const Eigen::Map<const Eigen::Quaternion<T>> q_a(rotation_a);
    const Eigen::Map<const Eigen::Quaternion<T>> q_b(rotation_b);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t_a(translation_a);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t_b(translation_b);
    const Eigen::Matrix<T, 3, 1> r = (q_a * point_in_a_.cast<T>() + t_a) - (q_b * point_in_b_.cast<T>() + t_b);
    residual[0] = r[0];
    residual[1] = r[1];
    residual[2] = r[2];
    return true;
  }

  static ceres::CostFunction* Create(const Eigen::Vector3d& point_in_a, const Eigen::Vector3d& point_in_b) {
    return new ceres::AutoDiffCostFunction<PointToPointCost, 3, 4, 3, 4, 3>(
        new PointToPointCost(point_in_a, point_in_b));
  }

 private:
  Eigen::Vector3d point_in_a_, point_in_b_;
};

// E_I, inertia (paper §4.3): a pose's change from its value in the previous iteration (q_p, t_p),
//   r[0..2] = s_t (t - t_p)          r[3..5] = s_r 2 vec(q_p^-1 q)
// (the paper compares Euler angles; for the small changes this term sees, 2 vec(q_p^-1 q) is
// the rotation vector of the change to first order, and it has no gimbal lock).
struct PoseChangeCost {
  PoseChangeCost(const Eigen::Quaterniond& previous_rotation, const Eigen::Vector3d& previous_translation,
                 double sqrt_weight_translation, double sqrt_weight_rotation)
      : rotation_inverse_(previous_rotation.conjugate()),
        translation_(previous_translation),
        s_t_(sqrt_weight_translation),
        s_r_(sqrt_weight_rotation) {}

  template <typename T>
  bool operator()(const T* rotation, const T* translation, T* residual) const {
    const Eigen::Map<const Eigen::Quaternion<T>> q(rotation);
    const Eigen::Quaternion<T> delta = rotation_inverse_.cast<T>() * q;
    for (int i = 0; i < 3; ++i) {
      residual[i] = T(s_t_) * (translation[i] - T(translation_[i]));
      residual[3 + i] = T(2.0 * s_r_) * delta.vec()[i];
    }
    return true;
  }

  static ceres::CostFunction* Create(const Eigen::Quaterniond& previous_rotation,
                                     const Eigen::Vector3d& previous_translation, double sqrt_weight_translation,
                                     double sqrt_weight_rotation) {
    return new ceres::AutoDiffCostFunction<PoseChangeCost, 6, 4, 3>(
        new PoseChangeCost(previous_rotation, previous_translation, sqrt_weight_translation, sqrt_weight_rotation));
  }

 private:
  Eigen::Quaterniond rotation_inverse_;
  Eigen::Vector3d translation_;
  double s_t_, s_r_;
};

}  // namespace f2c

namespace f2c {

// The residual kernels of E_C and E_M with hand-written Jacobians (by the ambient coordinates,
// like AutoDiff; Ceres applies the quaternion manifold), used by the batched pair blocks
// (optim/pair_cost.h). They are about 10x faster than the AutoDiff functors above, which stay
// as their specification: tests check that values and Jacobians agree exactly. With
// Rot(q, v) = v + 2 w (u x v) + 2 u x (u x v), q = (u, w):
//   dRot/dw = 2 (u x v)      dRot/du = -2 w [v]x + 2 ((u . v) I + u v^T - 2 v u^T)
// exact for any q, as AutoDiff differentiates the same polynomial.
enum class ConstraintKind : uint8_t { kPointToPlane, kPointToLine, kPointToPoint };

// The two poses of a constraint, with M(q) = the rotation polynomial Eigen evaluates for q * v.
struct PosePair {
  explicit PosePair(double const* const* parameters);  // q_a, t_a, q_b, t_b
  const double *q_a, *t_a, *q_b, *t_b;
  Eigen::Matrix3d m_a, m_b;
};

// One constraint's residual (1 or 3 rows, unweighted) and its Jacobian by (q_a, t_a, q_b, t_b)
// as 14 columns. Point-to-point (E_M): r = Rot(q_a) p_a + t_a - Rot(q_b) p_b - t_b, with
// target_point = p_a, point = p_b (target_direction unused).
struct ConstraintRows {
  int rows = 0;
  Eigen::Vector3d residual = Eigen::Vector3d::Zero();
  Eigen::Matrix<double, 3, 14> jacobian;
};
void EvaluateConstraint(ConstraintKind kind, const PosePair& poses, const Eigen::Vector3d& target_point,
                        const Eigen::Vector3d& target_direction, const Eigen::Vector3d& point, bool jacobians,
                        ConstraintRows* out);

// Rotation helpers of the kernels: Rot(q, v) = M(q) v = v + 2 w (u x v) + 2 u x (u x v), its
// derivative by (x, y, z, w), and the cross-product matrix.
Eigen::Matrix3d RotationPolynomial(const double* q);
Eigen::Matrix<double, 3, 4, Eigen::RowMajor> RotationDerivative(const double* q, const Eigen::Vector3d& v);
Eigen::Matrix3d Skew(const Eigen::Vector3d& v);

}  // namespace f2c
