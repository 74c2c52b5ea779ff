#pragma once
// Dense photometric alignment along chosen directions of motion: what the intensity images
// measure where the depth measures nothing (a mottled wall's slides and its turn about its
// normal; docs/odometry.md).
//
// With the reference's grey image I_r and depth, its pixels u_i back-projected to points p_i,
// and the frame's grey image I_f, the reference_from_frame transform T is refined by
// minimising
//
//   E(s, b) = sum_i rho( I_f(pi(T(s)^-1 p_i)) - I_r(u_i) - b ),   T(s) = exp(B s) T_0,
//
// where B (6 x m) holds the directions of motion to refine (left increments (w L, v) of T:
// rotation scaled by the lever L, then translation), b is a global brightness offset (auto
// exposure), rho is Huber's loss, and pi the pinhole projection. T_0's other directions stay
// as they are. Gauss-Newton, coarse to fine over Gaussian-blurred copies of both images
// (sigma = blur_sigmas[level] pixels, reference pixels every `strides[level]`), with the
// frame's image gradient at the projected point (forward-additive Lucas-Kanade):
//
//   d r_i / d(w, v) = grad I_f^T J_pi(q_i) R_0^T [ [p_i]_x , -I ],   q_i = T_0^-1 p_i.

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <vector>

#include "f2c/geometry/intrinsics.h"
#include "f2c/geometry/rigid.h"
#include "f2c/util/fields.h"

namespace f2c {

struct PhotometricOptions {
  // Coarse to fine: blur (pixels) and the reference pixels' spacing per level. Measured on
  // the simulated apartment's mottled plaster (47 pairs started 1.4 deg and 7 cm off along
  // the free directions): sigmas 4, 2 with strides 8, 4 end 0.004 deg and 0.06 mm from the
  // truth in 20 ms a pair, as close as sigmas 4, 2, 1 with strides 4, 2, 2 in 75 ms.
  std::vector<double> blur_sigmas{4.0, 2.0};
  std::vector<int> strides{8, 4};
  int iterations = 10;  // Gauss-Newton steps per level at most
  double huber = 10.0;  // grey levels; larger residuals (occlusion, specularity) count linearly

  template <class V>
  void Fields(V& v) {
    v.Group("Keyframe odometry");
    F2C_FIELD(v, blur_sigmas, "", {}, "photometric fallback: Gaussian blur per level, coarse to fine (px)");
    F2C_FIELD(v, strides, "", {}, "photometric fallback: reference pixel spacing per level");
    F2C_FIELD(v, iterations, "", AtLeast(1), "photometric fallback: Gauss-Newton steps per level");
    F2C_FIELD(v, huber, "", Positive(), "photometric fallback: Huber scale (grey levels)");
  }
  void Check() const;
};

struct PhotometricResult {
  bool ok = false;
  double rmse_before = 0, rmse_after = 0;  // grey levels, over the finest level's samples
  int samples = 0;                         // finest level
};

// The left increment (w L, v) as a transform: rotation by the vector w = (w L) / lever, then
// translation by v (the units of B above and of ConstrainToGeometry).
Rigid3d ExpScaled(const Eigen::Matrix<double, 6, 1>& scaled, double lever);

// Refines *reference_from_frame (T_0 in, T out) along the columns of `directions`; `lever` is
// L. Grey images 8-bit, depth CV_32F metres, all of one size. Leaves *reference_from_frame
// alone and returns ok = false when there is nothing to align (no samples project into the
// frame) or the photometric error grows.
PhotometricResult AlignPhotometric(const cv::Mat& reference_gray, const cv::Mat& reference_depth,
                                   const cv::Mat& frame_gray, const CameraIntrinsics& intrinsics,
                                   const Eigen::Matrix<double, 6, Eigen::Dynamic>& directions, double lever,
                                   const PhotometricOptions& options, Rigid3d* reference_from_frame);

}  // namespace f2c
