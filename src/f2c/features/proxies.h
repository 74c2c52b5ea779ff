#pragma once
// Per-image planar proxies by agglomerative clustering (paper §4.1, "Creating Planar
// Proxies"). Every grid cell with a normal starts as its own cluster; neighbouring cells are
// considered in order of how well their normals agree (most similar first), and their
// clusters merge when the clusters' planes agree:
//   angle(N_a, N_b) <= max_normal_angle                   (N = mean normal of a cluster)
//   |N_a . (c_b - c_a)| <= max_distance, and the same from b's side   (c = centroid)
//   sqrt(N^T Sigma N) <= max_rms_a + max_rms_b z^2        (the merged cluster's RMS
//                                                          distance to its mean plane; z the
//                                                          merged centroid's depth)
// The last condition follows the depth noise of structured-light sensors (it grows with
// z^2), and stops a chain of small merges from bending a cluster around a curved surface.
// Only cells whose local fit is flat (curvature <= max_curvature) take part. Clusters of at
// least min_points cells and min_width across become proxies, refitted by PCA.

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "f2c/features/point_grid.h"

namespace f2c {

struct ProxyOptions {
  int min_points = 10;                         // cells (DESIGN.md: >= 10 points per cluster)
  double max_distance = 0.1;                   // metres (DESIGN.md)
  double max_normal_angle = 0.7853981633974483;  // radians, pi/4 (DESIGN.md)
  double max_rms_a = 0.005;                    // metres
  double max_rms_b = 0.004;                    // metres per square metre of depth
  // Only flat cells join clusters; otherwise the blended normals of cells on creases and
  // contours grow strips along them. A cell is flat when its curvature is at most
  // max_curvature, or when its fit residual is explained by the sensor's depth noise:
  // residual <= flat_noise_ratio sigma(z), sigma(z) = sensor_sigma_a + sensor_sigma_b (z - 0.4)^2
  // (Kinect v1 / Xtion, Nguyen et al. 2012). Noise-free depth needs only the first test.
  double max_curvature = 0.02;
  double sensor_sigma_a = 0.0012;  // metres
  double sensor_sigma_b = 0.0019;  // metres per square metre
  double flat_noise_ratio = 1.5;
  // Robust refit: members farther from their proxy's plane than trim_sigmas robust standard
  // deviations (1.4826 MAD, at least min_trim_sigma metres) are dropped and the plane refitted,
  // up to trim_iterations times (cells of a neighbouring surface that joined at a crease).
  double trim_sigmas = 3.0;
  double min_trim_sigma = 0.001;
  int trim_iterations = 2;
  // A proxy must be a surface, not a line of points: its second principal axis at least
  // this standard deviation (metres).
  double min_width = 0.01;

  void Check() const;  // InputError naming the field when out of range
};

// Whether a cell's neighbourhood is flat by the tests above (a normal, and curvature <=
// max_curvature or residual <= flat_noise_ratio sigma(z)), and how flat, in [0, 1]: the
// larger of 1 - curvature / max_curvature and 1 - residual / (flat_noise_ratio sigma(z)).
// Proxies are built from flat cells, and plane features sampled on them.
bool IsFlat(const PointGrid& grid, int cell, const ProxyOptions& options);
float Flatness(const PointGrid& grid, int cell, const ProxyOptions& options);

struct PlanarProxy {
  Eigen::Vector3f normal = Eigen::Vector3f::Zero();  // unit, towards the camera
  float offset = 0;                                  // the plane is {x : normal . x = offset}
  Eigen::Vector3f centroid = Eigen::Vector3f::Zero();
  Eigen::Matrix3f covariance = Eigen::Matrix3f::Zero();  // of the member points (m^2)
  Eigen::Vector2f extent = Eigen::Vector2f::Zero();  // half-lengths along the in-plane principal axes (m)
  float rms = 0;                                     // RMS distance of the members to the plane (m)
  int32_t inliers = 0;                               // member cells

  float Distance(const Eigen::Vector3f& x) const { return normal.dot(x) - offset; }
};

struct ProxySegmentation {
  std::vector<PlanarProxy> proxies;  // largest first
  std::vector<int32_t> labels;       // per grid cell: proxy index, or -1
};

ProxySegmentation ExtractProxies(const PointGrid& grid, const ProxyOptions& options);

}  // namespace f2c
