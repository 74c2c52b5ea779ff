#pragma once
// Rigid transform between two sets of matched 3D points by RANSAC (3-point samples), then a
// least-squares refit (Umeyama, no scale) on the inliers.

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "f2c/geometry/rigid.h"

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

  void Check() const;
};

struct RansacResult {
  Rigid3d b_from_a = Rigid3d::Identity();
  std::vector<int> inliers;  // indices into the matches
  double inlier_rmse = 0;    // metres
  int iterations = 0;
};

// Finds b_from_a maximising |{i : |b_from_a * a[i] - b[i]| < threshold}|. `seed` fixes the
// random samples, so the same input gives the same answer. Needs >= 3 matches; with fewer,
// returns identity and no inlier.
RansacResult EstimateRigidRansac(const std::vector<Eigen::Vector3d>& a,
                                 const std::vector<Eigen::Vector3d>& b, const RansacOptions& options,
                                 uint64_t seed);

// Least-squares rigid fit b ~ T a over the given indices (all if empty).
Rigid3d FitRigid(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b,
                 const std::vector<int>& indices);
// Weighted least-squares rigid fit (weighted Kabsch): minimises sum w_i |T a_i - b_i|^2 over
// `indices`, one weight each.
Rigid3d FitRigidWeighted(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b,
                         const std::vector<int>& indices, const std::vector<double>& weights);

}  // namespace f2c
