#pragma once
// Depth back-projected on a regular pixel grid, with normals from local plane fits. The grid
// (every `step`-th pixel) is the working resolution of the paper's per-image preprocessing:
// features end up >= 5 cm apart, which at 4 px per cell is 3-4 cells at 2 m, so nothing is
// lost by not looking at every pixel, and the work drops by step^2.

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <vector>

#include "f2c/geometry/intrinsics.h"
#include "f2c/util/fields.h"

namespace f2c {

struct PointGridOptions {
  int step = 4;            // pixels per grid cell (1 = every pixel)
  double min_depth = 0.3;  // metres; outside the range a cell is invalid (the authors cap at 5 m)
  double max_depth = 5.0;
  // Optional edge-preserving smoothing of the depth image before sampling (the authors filter
  // SUN3D's depth this way). Off by default; sigma_depth in metres, sigma_pixels in pixels.
  bool bilateral = false;
  double bilateral_sigma_depth = 0.05;
  double bilateral_sigma_pixels = 3.0;
  // Normals: a plane fit to the valid cells within normal_radius_pixels (image) and
  // normal_radius (3D, metres) of each cell (DESIGN.md: 0.25 m / 8 px), needing at least
  // min_normal_points of them.
  int normal_radius_pixels = 8;
  double normal_radius = 0.25;
  int min_normal_points = 6;

  template <class V>
  void Fields(V& v) {
    v.Group("Features (paper 4.1; DESIGN.md section 2)");
    F2C_FIELD(v, step, "--feature-step", AtLeast(1), "pixels per grid cell of the feature extraction");
    F2C_FIELD(v, min_depth, "", AtLeast(0), "nearest depth used for features (m)");
    F2C_FIELD(v, max_depth, "--feature-max-depth", Positive(), "farthest depth used for features (m)");
    F2C_FIELD(v, bilateral, "--bilateral", {}, "bilateral-filter depth first (noisy sensors, e.g. SUN3D)");
    F2C_FIELD(v, bilateral_sigma_depth, "", Positive(), "bilateral filter: depth sigma (m)");
    F2C_FIELD(v, bilateral_sigma_pixels, "", Positive(), "bilateral filter: spatial sigma (pixels)");
    F2C_FIELD(v, normal_radius_pixels, "--normal-radius-pixels", AtLeast(1),
              "normals: neighbours within this many pixels");
    F2C_FIELD(v, normal_radius, "--normal-radius", Positive(), "normals: neighbours within this distance (m)");
    F2C_FIELD(v, min_normal_points, "", AtLeast(3), "normals: fewest neighbours");
  }
  void Check() const;  // InputError naming the field when out of range
};

struct PointGrid {
  int width = 0, height = 0;  // cells
  int step = 1;               // pixels per cell
  // Per cell, row-major: the point in camera coordinates (metres; z = 0 where invalid), the
  // unit normal towards the camera (zero where none could be fitted), and the curvature of
  // the fit, lambda_min / (lambda_0 + lambda_1 + lambda_2): 0 on a plane, 1/3 at most.
  std::vector<Eigen::Vector3f> points;
  std::vector<Eigen::Vector3f> normals;
  std::vector<float> curvature;
  std::vector<float> residual;  // sqrt(lambda_min): RMS distance of the neighbours to the fit (m)

  int Index(int x, int y) const { return y * width + x; }
  bool Valid(int i) const { return points[i].z() > 0; }
  bool HasNormal(int i) const { return normals[i].z() != 0 || normals[i].x() != 0 || normals[i].y() != 0; }
  // The image pixel a cell samples.
  int PixelU(int x) const { return x * step + step / 2; }
  int PixelV(int y) const { return y * step + step / 2; }
  int ValidCount() const;
};

// `depth` is CV_32F metres; zero, negative, NaN and infinite values are invalid. `options` as
// checked by the caller (per frame: the feature stage checks once).
PointGrid BuildPointGrid(const cv::Mat& depth, const CameraIntrinsics& intrinsics, const PointGridOptions& options);

}  // namespace f2c
