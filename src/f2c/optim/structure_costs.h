#pragma once
// The residuals of the paper's planar structure error E_S = w_P E_P + w_H E_H + w_G E_G
// (§4.3, "Planar Structure Error"), as templated functors for ceres::AutoDiffCostFunction.
// A plane is one variable block of four numbers (n, e): a unit normal n and an offset e from
// a fixed reference point x_0 of the plane's own (its centre when the iteration began), on
// PlaneManifold (the sphere times the line): the plane {x : n . (x - x_0) = e}, in world
// coordinates, so d = n . x_0 + e in the usual form n . x = d. Measured from the origin
// instead, a small turn of the normal swings the plane by its distance from the origin times
// the angle, and one Gauss-Newton step overshoots (Ceres rejects it); about the plane's
// centre the problem is near-linear. One block rather than two (normal, offset): half the
// plane variables, each one node of the graph the normal equations are ordered on
// (optim/gauss_newton.h). Poses are as in
// optim/cost_functions.h (x_world = R(q) x_camera + t). Residuals are unweighted: metres, or
// unit-vector differences; optim/problem.cc applies each term's weight.

#include <ceres/autodiff_cost_function.h>
#include <ceres/manifold.h>
#include <ceres/product_manifold.h>
#include <ceres/sphere_manifold.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace f2c {

// A plane variable's manifold: (n, e) with |n| = 1.
using PlaneManifold = ceres::ProductManifold<ceres::SphereManifold<3>, ceres::EuclideanManifold<1>>;

// E_P, one per-image proxy (a child) against the features of its frame that support it:
//   E_cp(P_j, T[k] F) = sum_i (n . (R x_i + t) - d)^2        x_i: the members, camera coords
// With the plane in camera coordinates, h = (R^T n, n . t - d), each term is (h_n . x_i +
// h_d)^2, and over m members with centroid c and (population) covariance Sigma the sum is
// exactly
//   m ((h_n . c + h_d)^2 + h_n^T Sigma h_n)  =  m |(h_n . c + h_d, S h_n)|^2,  S^T S = Sigma.
// So the residuals are r = (h_n . c + h_d, S h_n) (metres), the root-mean-square distance of
// the members to the plane, and the problem weighs them by the proxy's share m_j of the
// paper's sum m_j = 100 n: the paper's subsample in expectation, without its sampling noise,
// in four residuals whatever the proxy's size.
struct ProxyFitCost {
  ProxyFitCost(const Eigen::Vector3d& centroid, const Eigen::Matrix3d& sqrt_covariance,
               const Eigen::Vector3d& reference = Eigen::Vector3d::Zero())
      : centroid_(centroid), sqrt_covariance_(sqrt_covariance), reference_(reference) {}

  template <typename T>
  bool operator()(const T* rotation, const T* translation, const T* plane, T* residual) const {
    const Eigen::Map<const Eigen::Quaternion<T>> q(rotation);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t(translation);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> n(plane);
    const Eigen::Matrix<T, 3, 1> h_n = q.conjugate() * n;
    const T h_d = n.dot(t - reference_.cast<T>()) - plane[3];
    residual[0] = h_n.dot(centroid_.cast<T>()) + h_d;
    const Eigen::Matrix<T, 3, 1> s = sqrt_covariance_.cast<T>() * h_n;
    residual[1] = s[0];
    residual[2] = s[1];
    residual[3] = s[2];
    return true;
  }

  // `reference`: the plane variable's x_0 (zero: the offset is d, from the origin).
  static ceres::CostFunction* Create(const Eigen::Vector3d& centroid, const Eigen::Matrix3d& sqrt_covariance,
                                     const Eigen::Vector3d& reference = Eigen::Vector3d::Zero()) {
    return new ceres::AutoDiffCostFunction<ProxyFitCost, 4, 4, 3, 4>(
        new ProxyFitCost(centroid, sqrt_covariance, reference));
  }

 private:
  Eigen::Vector3d centroid_;
  Eigen::Matrix3d sqrt_covariance_;
  Eigen::Vector3d reference_;
};

// S with S^T S = Sigma for a symmetric positive semi-definite Sigma (eigenvalues clamped at 0).
Eigen::Matrix3d SqrtCovariance(const Eigen::Matrix3d& covariance);

// E_H's E_cp(parent, child): how far a child proxy is from being coplanar with its parent.
// With a the child's anchor (its centroid in world coordinates when the hierarchy was built,
// also the child's reference point) and p = a - (n_c . a - d_c) n_c = a + e_c n_c its foot on
// the child's plane (d = n . x_0 + e for both planes):
//   r[0]    = n_p . p - d_p               the child's centre off the parent's plane (metres)
//   r[1..3] = lever (n_c - n_p)           the normals' difference, at a lever arm (metres)
// Zero exactly when the planes coincide (same normal, and the child's centre on the parent).
// All residuals are multiplied by `scale` (the square root of the link's weight).
struct CoplanarityCost {
  CoplanarityCost(const Eigen::Vector3d& anchor, double lever_arm, double scale, const Eigen::Vector3d& child_reference,
                  const Eigen::Vector3d& parent_reference)
      : anchor_(anchor), lever_(lever_arm), scale_(scale), child_ref_(child_reference), parent_ref_(parent_reference) {}

  template <typename T>
  bool operator()(const T* child, const T* parent, T* residual) const {
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> n_c(child);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> n_p(parent);
    const Eigen::Matrix<T, 3, 1> a = anchor_.cast<T>();
    const T d_c = n_c.dot(child_ref_.cast<T>()) + child[3];
    const T d_p = n_p.dot(parent_ref_.cast<T>()) + parent[3];
    const Eigen::Matrix<T, 3, 1> p = a - (n_c.dot(a) - d_c) * n_c;
    residual[0] = T(scale_) * (n_p.dot(p) - d_p);
    for (int i = 0; i < 3; ++i) residual[1 + i] = T(scale_ * lever_) * (n_c[i] - n_p[i]);
    return true;
  }

  // References zero: offsets are d, from the origin.
  static ceres::CostFunction* Create(const Eigen::Vector3d& anchor, double lever_arm, double scale = 1,
                                     const Eigen::Vector3d& child_reference = Eigen::Vector3d::Zero(),
                                     const Eigen::Vector3d& parent_reference = Eigen::Vector3d::Zero()) {
    return new ceres::AutoDiffCostFunction<CoplanarityCost, 4, 4, 4>(
        new CoplanarityCost(anchor, lever_arm, scale, child_reference, parent_reference));
  }

 private:
  Eigen::Vector3d anchor_;
  double lever_, scale_;
  Eigen::Vector3d child_ref_, parent_ref_;
};

// E_G, a relation between two parent proxies' normals (the paper's three cases):
//   parallel      r = n_a - n_b            (3 residuals)
//   antiparallel  r = n_a + n_b            (3)
//   orthogonal    r = n_a . n_b            (1)
// multiplied by `scale` (the square root of the relation's weight). The blocks are planes;
// only their normals enter.
struct ParallelCost {
  ParallelCost(double sign, double scale) : sign_(sign), scale_(scale) {}
  template <typename T>
  bool operator()(const T* plane_a, const T* plane_b, T* residual) const {
    for (int i = 0; i < 3; ++i) residual[i] = T(scale_) * (plane_a[i] - T(sign_) * plane_b[i]);
    return true;
  }
  // sign +1: parallel; -1: antiparallel.
  static ceres::CostFunction* Create(double sign, double scale = 1) {
    return new ceres::AutoDiffCostFunction<ParallelCost, 3, 4, 4>(new ParallelCost(sign, scale));
  }

 private:
  double sign_, scale_;
};

struct OrthogonalCost {
  explicit OrthogonalCost(double scale) : scale_(scale) {}
  template <typename T>
  bool operator()(const T* plane_a, const T* plane_b, T* residual) const {
    residual[0] = T(scale_) * (plane_a[0] * plane_b[0] + plane_a[1] * plane_b[1] + plane_a[2] * plane_b[2]);
    return true;
  }
  static ceres::CostFunction* Create(double scale = 1) {
    return new ceres::AutoDiffCostFunction<OrthogonalCost, 1, 4, 4>(new OrthogonalCost(scale));
  }

 private:
  double scale_;
};

// E_I for a plane (the paper's E_I sums pose and plane changes): its change in this
// iteration, r = (s_n (n - n_0), s_e (e - e_0)). The offset e is from the plane's own centre,
// so e - e_0 is how far the plane moved there, whatever its distance from the world origin.
struct PlaneChangeCost {
  PlaneChangeCost(const Eigen::Vector3d& normal, double offset, double s_normal, double s_offset)
      : normal_(normal), offset_(offset), s_n_(s_normal), s_e_(s_offset) {}
  template <typename T>
  bool operator()(const T* plane, T* residual) const {
    for (int i = 0; i < 3; ++i) residual[i] = T(s_n_) * (plane[i] - T(normal_[i]));
    residual[3] = T(s_e_) * (plane[3] - T(offset_));
    return true;
  }
  static ceres::CostFunction* Create(const Eigen::Vector3d& normal, double offset, double s_normal, double s_offset) {
    return new ceres::AutoDiffCostFunction<PlaneChangeCost, 4, 4>(
        new PlaneChangeCost(normal, offset, s_normal, s_offset));
  }

 private:
  Eigen::Vector3d normal_;
  double offset_, s_n_, s_e_;
};

}  // namespace f2c
