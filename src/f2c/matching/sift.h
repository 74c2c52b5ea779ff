#pragma once
// SIFT keypoints in the colour image that have valid depth, lifted to 3D (paper §4.1,
// "Aligning Adjacent Images": detect SIFT in colour, prune those without valid depth,
// assign 3D positions to the rest).

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <vector>

#include "f2c/geometry/intrinsics.h"
#include "f2c/util/fields.h"

namespace f2c {

struct SiftOptions {
  // OpenCV SIFT parameters (Lowe's defaults). 0 features = keep all.
  int max_features = 0;
  int octave_layers = 3;
  double contrast_threshold = 0.04;
  double edge_threshold = 10.0;
  double sigma = 1.6;
  // Detect on the image shrunk by this factor (1 = full resolution) and scale keypoints back.
  // Default 2: on fr1/xyz and redkitchen T0 kept its accuracy at ~3x the speed.
  // OpenCV's SIFT doubles its input for the first octave; shrinking by 2 skips exactly that
  // finest octave, about 4x less work, at the cost of the smallest-scale keypoints.
  int downscale = 2;
  // Keypoints keep only depth in [min_depth, max_depth] metres (Kinect-class sensors are
  // unreliable outside; the authors cap at 5 m).
  double min_depth = 0.3;
  double max_depth = 5.0;
  // A keypoint on a depth discontinuity has no single depth: drop it when the 3x3
  // neighbourhood's depths spread by more than this fraction of the centre depth.
  double max_depth_spread = 0.05;

  template <class V>
  void Fields(V& v) {
    v.Group("Odometry (T0)");
    F2C_FIELD(v, max_features, "", AtLeast(0), "SIFT keypoints kept (0: all)");
    F2C_FIELD(v, octave_layers, "", AtLeast(1), "OpenCV SIFT octave layers");
    F2C_FIELD(v, contrast_threshold, "", Positive(), "OpenCV SIFT contrast threshold");
    F2C_FIELD(v, edge_threshold, "", Positive(), "OpenCV SIFT edge threshold");
    F2C_FIELD(v, sigma, "", Positive(), "OpenCV SIFT sigma");
    F2C_FIELD(v, downscale, "--sift-downscale", Between(1, 8),
              "detect SIFT on the colour image shrunk by this factor (faster, coarser)");
    F2C_FIELD(v, min_depth, "--min-depth", AtLeast(0), "nearest valid depth (m)");
    F2C_FIELD(v, max_depth, "--max-depth", Positive(), "farthest valid depth (m)");
    F2C_FIELD(v, max_depth_spread, "", Positive(),
              "keypoints on depth edges: largest 3x3 depth spread (share of depth)");
  }
  void Check() const;  // InputError naming the field when out of range
};

struct SiftFeatures {
  std::vector<Eigen::Vector3d> points_in_camera;  // metres
  std::vector<cv::Point2f> pixels;
  cv::Mat descriptors;  // CV_32F, one row per point
  int detected = 0;     // keypoints before the depth test
  size_t size() const { return points_in_camera.size(); }
};

// `gray` is 8-bit single channel, `depth` CV_32F metres (0 = invalid), same size.
SiftFeatures ExtractSiftWithDepth(const cv::Mat& gray, const cv::Mat& depth, const CameraIntrinsics& intrinsics,
                                  const SiftOptions& options);

// The depth of a keypoint at `pixel`: the nearest pixel's, when it is within
// [min_depth, max_depth] and its 3x3 neighbourhood spreads by at most max_depth_spread of it
// (not on a depth edge). False otherwise.
bool KeypointDepth(const cv::Mat& depth, const cv::Point2f& pixel, const SiftOptions& options, float* z);

// Lowe's ratio test: each point of `query` is matched to its nearest neighbour in `train`
// (L2 on descriptors) when that is closer than `ratio` times the second nearest. When fewer
// than `relax_below_matches` pass, the test is redone with `relaxed_ratio` (the authors: 0.55,
// relaxed to 0.8 below 50 matches). Returns index pairs (query, train) in query order.
struct SiftMatch {
  int query = 0;
  int train = 0;
};
std::vector<SiftMatch> MatchSiftRatio(const SiftFeatures& query, const SiftFeatures& train, double ratio,
                                      double relaxed_ratio, int relax_below_matches);

}  // namespace f2c
