#pragma once
// Depth-only alignment for pairs SIFT cannot align (textureless views): point-to-plane ICP
// (OpenCV rgbd's ICPOdometry, KinectFusion-style, on an image pyramid) started from the
// previous motion; and a depth-overlap score that measures any pair's alignment.

#include <opencv2/core.hpp>
#include <vector>

#include "f2c/geometry/intrinsics.h"
#include "f2c/geometry/rigid.h"

namespace f2c {

struct IcpOptions {
  double min_depth = 0.3;           // metres; pixels outside are ignored
  double max_depth = 5.0;
  double max_depth_difference = 0.07;  // correspondences further apart (metres) are dropped
  double max_points_part = 0.07;       // fraction of pixels sampled per level (OpenCV default)
  std::vector<int> iterations{7, 7, 7, 10};  // per pyramid level, fine to coarse
  double max_translation = 0.3;     // metres between frames; larger answers are rejected
  double max_rotation_deg = 30.0;   // likewise

  void Check() const;
};

// Estimates target_from_source. Returns false (and leaves *target_from_source alone) when
// ICP fails or its answer moves more than the limits.
bool AlignDepthIcp(const cv::Mat& source_depth, const cv::Mat& target_depth,
                   const CameraIntrinsics& intrinsics, const Rigid3d& initial_target_from_source,
                   const IcpOptions& options, Rigid3d* target_from_source);

struct DepthOverlap {
  double fitness = 0;  // fraction of valid source samples within `threshold` of the target's surface
  double rmse = 0;     // metres, over those
  int samples = 0;     // valid source samples that project inside the target image
};

// Projects every `stride`-th valid source pixel into the target with target_from_source and
// compares depths along the target ray.
DepthOverlap MeasureDepthOverlap(const cv::Mat& source_depth, const cv::Mat& target_depth,
                                 const CameraIntrinsics& intrinsics,
                                 const Rigid3d& target_from_source, double threshold = 0.05,
                                 int stride = 4);

}  // namespace f2c
