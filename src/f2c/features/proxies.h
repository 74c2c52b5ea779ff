#pragma once
// Per-image planar proxies by agglomerative clustering (paper §4.1, "Creating Planar
// Proxies"). Every grid cell with a normal starts as its own cluster; neighbouring cells are
// considered in order of how well their normals agree (most similar first), and their
// clusters merge when the clusters' planes agree:
//   angle(N_a, N_b) <= max_normal_angle_deg               (N = mean normal of a cluster)
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
#include "f2c/util/fields.h"

namespace f2c {

struct ProxyOptions {
  int min_points = 10;               // cells (DESIGN.md: >= 10 points per cluster)
  double max_distance = 0.1;         // metres (DESIGN.md)
  double max_normal_angle_deg = 45;  // DESIGN.md
  double max_rms_a = 0.005;          // metres
  double max_rms_b = 0.004;          // metres per square metre of depth
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
  // Each proxy's depth-noise covariance (PlanarProxy::noise): the members' mean of sigma(z)^2
  // along their rays (the model above) plus bearing_noise times the range across them,
  // scaled to the proxy's own noise by the smallest mu of n^T Sigma n / n^T N n (Sigma the
  // members' covariance). 0 where sigma(z) = 0.
  double bearing_noise = 0.0015;  // radians (as the odometry's ray-aware RANSAC refit)

  template <class V>
  void Fields(V& v) {
    v.Group("Features (paper 4.1; DESIGN.md section 2)");
    F2C_FIELD(v, min_points, "--proxy-min-points", AtLeast(3), "smallest planar proxy (grid cells)");
    F2C_FIELD(v, max_distance, "--proxy-max-distance", Positive(),
              "clusters merge when their planes are this close (m)");
    v.Field(max_normal_angle_deg, "max_normal_angle_deg", "--proxy-max-angle",
            Bounds{.min = 0, .max = 90, .min_open = true, .max_open = true}, "...and their normals this close (deg)");
    F2C_FIELD(v, max_rms_a, "", Positive(), "a plane's largest RMS residual a + b z^2: a (m)");
    F2C_FIELD(v, max_rms_b, "", AtLeast(0), "...b (m per m^2)");
    F2C_FIELD(v, max_curvature, "", Positive(), "largest curvature of a planar cluster");
    F2C_FIELD(v, sensor_sigma_a, "--depth-noise-a", AtLeast(0),
              "sensor depth noise sigma(z) = a + b (z - 0.4)^2 (m; Kinect v1 defaults; 0 and 0 for noise-free depth)");
    F2C_FIELD(v, sensor_sigma_b, "--depth-noise-b", AtLeast(0), "...its b (m per m^2)");
    F2C_FIELD(v, flat_noise_ratio, "", AtLeast(0), "flat clusters: residual within this many sensor sigmas");
    F2C_FIELD(v, trim_sigmas, "", Positive(), "trimming: points beyond this many sigmas");
    F2C_FIELD(v, min_trim_sigma, "", Positive(), "trimming: smallest sigma (m)");
    F2C_FIELD(v, trim_iterations, "", AtLeast(0), "trimming rounds");
    F2C_FIELD(v, min_width, "", AtLeast(0), "narrowest proxy (m)");
    F2C_FIELD(v, bearing_noise, "", Positive(),
              "a proxy's noise estimate: a point's noise across its ray (radians x range)");
  }
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
  // The part of `covariance` that is depth noise, estimated: mu N (ProxyOptions::bearing_noise).
  // Noise along the rays turns the least-squares plane above towards them by about
  // sigma^2 / lambda (lambda: the spread along the turn), up to degrees on distant, oblique
  // walls; covariance - noise is the members' spread without it, whose smallest eigenvector
  // is the plane without that turn (the structural model's E_P uses it, docs/refinement.md).
  Eigen::Matrix3f noise = Eigen::Matrix3f::Zero();
  Eigen::Vector2f extent = Eigen::Vector2f::Zero();  // half-lengths along the in-plane principal axes (m)
  float rms = 0;                                     // RMS distance of the members to the plane (m)
  int32_t inliers = 0;                               // member cells

  float Distance(const Eigen::Vector3f& x) const { return normal.dot(x) - offset; }
};

struct ProxySegmentation {
  std::vector<PlanarProxy> proxies;  // largest first
  std::vector<int32_t> labels;       // per grid cell: proxy index, or -1
};

// Per frame: `options` as checked by the caller (the feature stage checks once).
ProxySegmentation ExtractProxies(const PointGrid& grid, const ProxyOptions& options);

}  // namespace f2c
