#pragma once
// Test helpers (gtest): random poses, residuals of a cost function, and its Jacobians
// checked against central differences and Ceres' GradientChecker.

#include <ceres/gradient_checker.h>
#include <ceres/manifold.h>
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <random>
#include <vector>

#include "f2c/optim/pose.h"

namespace f2c {

// A pose with a uniformly random rotation and a standard-normal translation.
inline Pose RandomPose(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Pose pose;
  pose.rotation = Eigen::Quaterniond(n(rng), n(rng), n(rng), n(rng)).normalized();
  pose.translation = Eigen::Vector3d(n(rng), n(rng), n(rng));
  return pose;
}

inline std::vector<double> Residuals(const ceres::CostFunction& cost, std::vector<double*> blocks) {
  std::vector<double> r(cost.num_residuals());
  EXPECT_TRUE(cost.Evaluate(blocks.data(), r.data(), nullptr));
  return r;
}

// The AutoDiff Jacobian of every block equals central differences of the residuals over the
// block's ambient coordinates (step h), and Ceres' GradientChecker agrees on the manifold.
inline void ExpectJacobiansMatch(const ceres::CostFunction& cost, std::vector<double*> blocks,
                                 const std::vector<const ceres::Manifold*>& manifolds) {
  const int m = cost.num_residuals();
  const std::vector<int32_t>& sizes = cost.parameter_block_sizes();
  std::vector<std::vector<double>> jacobians(sizes.size());
  std::vector<double*> jacobian_ptrs;
  for (size_t b = 0; b < sizes.size(); ++b) {
    jacobians[b].resize(m * sizes[b]);
    jacobian_ptrs.push_back(jacobians[b].data());
  }
  std::vector<double> r(m);
  ASSERT_TRUE(cost.Evaluate(blocks.data(), r.data(), jacobian_ptrs.data()));
  const double h = 1e-6;
  for (size_t b = 0; b < sizes.size(); ++b) {
    for (int k = 0; k < sizes[b]; ++k) {
      const double saved = blocks[b][k];
      blocks[b][k] = saved + h;
      const std::vector<double> plus = Residuals(cost, blocks);
      blocks[b][k] = saved - h;
      const std::vector<double> minus = Residuals(cost, blocks);
      blocks[b][k] = saved;
      for (int i = 0; i < m; ++i) {
        EXPECT_NEAR(jacobians[b][i * sizes[b] + k], (plus[i] - minus[i]) / (2 * h), 1e-7)
            << "block " << b << " coordinate " << k << " residual " << i;
      }
    }
  }
  // GradientChecker compares the residuals with and without Jacobians exactly relative to
  // their size, which rounding defeats where they vanish: probe at a generic point near by.
  std::vector<std::vector<double>> moved(sizes.size());
  std::vector<double*> moved_ptrs;
  for (size_t b = 0; b < sizes.size(); ++b) {
    moved[b].assign(blocks[b], blocks[b] + sizes[b]);
    for (int k = 0; k < sizes[b]; ++k) moved[b][k] += 0.05 * std::sin(1.0 + 3.0 * b + k);
    // Blocks on a manifold here are unit vectors (quaternion coefficients, plane normals).
    if (manifolds[b] != nullptr) Eigen::Map<Eigen::VectorXd>(moved[b].data(), sizes[b]).normalize();
    moved_ptrs.push_back(moved[b].data());
  }
  ceres::NumericDiffOptions options;
  ceres::GradientChecker checker(&cost, &manifolds, options);
  ceres::GradientChecker::ProbeResults results;
  EXPECT_TRUE(checker.Probe(moved_ptrs.data(), 1e-7, &results)) << results.error_log;
}

}  // namespace f2c
