#pragma once
// Keyframe tracking (keyframe odometry, docs/odometry.md): the keyframe's SIFT keypoints are
// followed into a later frame by pyramidal Lucas-Kanade optical flow, each started where the
// predicted motion puts it, and the frame's depth at the tracked pixel gives the 3D point:
//
//   u_f = KLT(I_key, I_f, u_key; start = pi(f_from_key_predicted * p_key))
//   p_f = unproject(u_f, D_f(u_f))          (KeypointDepth's tests: range, no depth edge)
//
// The pairs (p_key, p_f) go to the same 3D RANSAC as SIFT matches. A frame tracked this way
// needs no SIFT of its own: the keyframe's keypoints serve every frame aligned to it, and LK
// costs a few milliseconds where SIFT costs 15.

#include <opencv2/core.hpp>
#include <vector>

#include "f2c/geometry/intrinsics.h"
#include "f2c/geometry/rigid.h"
#include "f2c/matching/sift.h"
#include "f2c/util/fields.h"

namespace f2c {

struct TrackOptions {
  int window = 21;         // LK window (pixels, odd)
  int pyramid_levels = 3;  // levels above the image (OpenCV's maxLevel)
  int max_lk_iterations = 30;
  double lk_epsilon = 0.01;  // pixels
  // A track whose start (the prediction) and end differ by more than this (pixels) is
  // dropped: LK converging that far off is usually on a different, similar patch.
  double max_correction = 40;
  // Forward-backward check: the tracked point tracked back must land within this distance
  // (pixels) of the keypoint; 0: off (RANSAC alone rejects bad tracks).
  double max_forward_backward = 0;

  template <class V>
  void Fields(V& v) {
    v.Group("Keyframe odometry");
    F2C_FIELD(v, window, "--track-window", AtLeast(5), "Lucas-Kanade window (pixels, odd)");
    F2C_FIELD(v, pyramid_levels, "--track-levels", Between(0, 8), "Lucas-Kanade pyramid levels above the image");
    F2C_FIELD(v, max_lk_iterations, "", AtLeast(1), "Lucas-Kanade iterations");
    F2C_FIELD(v, lk_epsilon, "", Positive(), "Lucas-Kanade convergence (pixels)");
    F2C_FIELD(v, max_correction, "", Positive(),
              "tracks moved farther than this from the prediction are dropped (pixels)");
    F2C_FIELD(v, max_forward_backward, "--track-forward-backward", AtLeast(0),
              "drop tracks that do not return within this many pixels (0: no check)");
  }
  void Check() const;
};

// What tracking needs of a keyframe, prepared once and reused for every frame tracked from it.
struct TrackingKeyframe {
  int frame = -1;
  SiftFeatures sift;             // keypoints (pixels) and their 3D points
  std::vector<cv::Mat> pyramid;  // cv::buildOpticalFlowPyramid of its grey image
  cv::Mat depth;                 // metres
  cv::Mat gray;                  // 8-bit (the depth fallback's photometric alignment)
};

TrackingKeyframe MakeTrackingKeyframe(int frame, const cv::Mat& gray, cv::Mat depth, SiftFeatures sift,
                                      const TrackOptions& options);

struct TrackedPoints {
  std::vector<Eigen::Vector3d> keyframe, frame;  // matched 3D points, camera coordinates
  int tracked = 0;                               // keypoints LK followed (before the depth test)
};

// Tracks `keyframe`'s keypoints into the frame (`gray` 8-bit, `depth` metres), starting each
// where `keyframe_from_frame_guess` predicts it. `depth_rules` are the SIFT options' depth
// tests, so tracked points obey what keypoints do.
TrackedPoints TrackKeypoints(const TrackingKeyframe& keyframe, const cv::Mat& gray, const cv::Mat& depth,
                             const CameraIntrinsics& intrinsics, const Rigid3d& keyframe_from_frame_guess,
                             const SiftOptions& depth_rules, const TrackOptions& options);

}  // namespace f2c
