#pragma once
// Rigid transform between two sets of matched 3D points by RANSAC (3-point samples), then a
// least-squares refit (Umeyama, no scale) on the inliers.

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "f2c/geometry/rigid.h"
#include "f2c/util/fields.h"

namespace f2c {

struct RansacOptions {
  double inlier_threshold = 0.05;  // metres; the authors' and Xiao et al.'s value
  int max_iterations = 2000;
  // Stop early once a sample this likely to be all-inlier has been drawn.
  double confidence = 0.999;
  // Refit on inliers, re-collect inliers, repeat: this many times.
  int refit_rounds = 3;
  // Final refinement: iteratively reweighted least squares over the inliers with Cauchy
  // weights 1 / (1 + (r / robust_scale)^2), so the few-centimetre errors that the 5 cm
  // consensus threshold admits (depth noise grows with z^2) pull less than good points.
  // 0 disables it.
  double robust_scale = 0.01;  // metres
  int robust_iterations = 10;
  // Last, maximum likelihood under the depth sensor's noise, which is anisotropic: a point
  // is uncertain along its ray by sigma_z = depth_noise_a + depth_noise_b z^2 (Kinect-class
  // sensors, after Nguyen et al. 2012) and across it by bearing_sigma radians (keypoint
  // localisation). Gauss-Newton on SE(3) over the inliers, each residual R a + t - b
  // weighted by (C_b + R C_a R^T)^-1, with Cauchy weights at anisotropic_scale of that
  // Mahalanobis distance. 0 iterations: off (here, the generic default; the odometry's pairs
  // use it, odometry/odometry.h).
  int anisotropic_iterations = 0;
  double bearing_sigma = 0.0015;  // radians (0.8 px at f = 525)
  double depth_noise_a = 0.0012;  // metres
  double depth_noise_b = 0.0019;  // 1 / metre
  double anisotropic_scale = 3.0;

  template <class V>
  void Fields(V& v) {
    v.Group("Odometry (T0)");
    F2C_FIELD(v, inlier_threshold, "--ransac-threshold", Positive(), "RANSAC inlier distance (m)");
    F2C_FIELD(v, max_iterations, "--ransac-iterations", AtLeast(1), "RANSAC iteration cap");
    v.Field(confidence, "confidence", "", Bounds{.min = 0, .max = 1, .min_open = true, .max_open = true},
            "stop once a sample this likely all-inlier was drawn");
    F2C_FIELD(v, refit_rounds, "", AtLeast(0), "refit on inliers this many times");
    F2C_FIELD(v, robust_scale, "--robust-scale", AtLeast(0),
              "Cauchy scale (m) of the final reweighted refit on RANSAC inliers (0: off)");
    F2C_FIELD(v, robust_iterations, "", AtLeast(0), "iterations of that refit");
    F2C_FIELD(v, anisotropic_iterations, "--ransac-anisotropic", AtLeast(0),
              "Gauss-Newton steps of a ray-aware (depth noise along the ray) refit after RANSAC; 0: off");
    F2C_FIELD(v, bearing_sigma, "", Positive(), "keypoint direction noise (rad)");
    F2C_FIELD(v, depth_noise_a, "", AtLeast(0), "depth noise a + b z^2: a (m)");
    F2C_FIELD(v, depth_noise_b, "", AtLeast(0), "...b (1/m)");
    F2C_FIELD(v, anisotropic_scale, "", Positive(), "Cauchy scale of the ray-aware refit (Mahalanobis)");
  }
  void Check() const;

  // These options with the ray-aware refit in `iterations` Gauss-Newton steps.
  static RansacOptions WithRayAwareRefit(int iterations) {
    RansacOptions o;
    o.anisotropic_iterations = iterations;
    return o;
  }
};

// The anisotropic maximum-likelihood refinement alone (see RansacOptions), from `initial`.
Rigid3d RefineRigidAnisotropic(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b,
                               const std::vector<int>& indices, const Rigid3d& initial, const RansacOptions& options);

struct RansacResult {
  Rigid3d b_from_a = Rigid3d::Identity();
  std::vector<int> inliers;  // indices into the matches
  double inlier_rmse = 0;    // metres
  int iterations = 0;
  // The fit's information (RigidFitInformation over the inliers); zero without inliers.
  Eigen::Matrix<double, 6, 6> information = Eigen::Matrix<double, 6, 6>::Zero();
};

// How precisely the matches fix b_from_a: the Fisher information J^T W J of the ray-aware
// fit under RansacOptions' depth noise model (W = (C_b + R C_a R^T)^-1 per match, no robust
// weights), at b_from_a, for a left perturbation b_from_a -> exp(w, v) b_from_a in b's
// coordinates, ordered (w radians, v metres). Its inverse is the fit's covariance under that
// model (checked by sampling, ransac_test.cc).
Eigen::Matrix<double, 6, 6> RigidFitInformation(const std::vector<Eigen::Vector3d>& a,
                                                const std::vector<Eigen::Vector3d>& b, const std::vector<int>& indices,
                                                const Rigid3d& b_from_a, const RansacOptions& options);

// Finds b_from_a maximising |{i : |b_from_a * a[i] - b[i]| < threshold}|. `seed` fixes the
// random samples, so the same input gives the same answer. Needs >= 3 matches; with fewer,
// returns identity and no inlier.
RansacResult EstimateRigidRansac(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b,
                                 const RansacOptions& options, uint64_t seed);

// Least-squares rigid fit b ~ T a over the given indices (all if empty).
Rigid3d FitRigid(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b,
                 const std::vector<int>& indices);
// Weighted least-squares rigid fit (weighted Kabsch): minimises sum w_i |T a_i - b_i|^2 over
// `indices`, one weight each.
Rigid3d FitRigidWeighted(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b,
                         const std::vector<int>& indices, const std::vector<double>& weights);

}  // namespace f2c
