#pragma once
// Steps shared by the consecutive-pair odometry (odometry.cc) and the keyframe odometry
// (keyframe_odometry.cc); not part of the library's interface.

#include <atomic>
#include <opencv2/core.hpp>

#include "f2c/io/sequence.h"
#include "f2c/odometry/odometry.h"

namespace f2c::internal {

// Per-stage CPU seconds summed over threads, added atomically.
struct StageClock {
  std::atomic<double> decode{0}, sift{0}, matching{0}, ransac{0}, icp{0}, fitness{0}, hashing{0}, track{0};
  std::atomic<int> sift_frames{0};
};

// SIFT + RANSAC. Leaves method = kMotionPrior when there are too few inliers, for the
// fallback to resolve.
PairAlignment AlignSift(const SiftFeatures& prev, const SiftFeatures& curr, const OdometryOptions& options,
                        uint64_t seed, StageClock* clock);

// Sets pair->fitness and overlap_rmse: frame k's depth against its reference's.
void ScoreOverlap(const cv::Mat& depth_prev, const cv::Mat& depth_curr, const CameraIntrinsics& k,
                  const OdometryOptions& options, StageClock* clock, PairAlignment* pair);

// Whether a SIFT (or tracked) answer needs checking against ICP.
bool NeedsFallback(const PairAlignment& pair, const OdometryOptions& options);

// A frame's depth (metres) and grey image (8-bit; may be empty: depth alone is used).
struct FrameImages {
  cv::Mat depth, gray;
};

// Depth ICP from `previous_motion` (refined by intensity where the depth leaves motions
// free); keeps whichever of the pair's answer, ICP's and the previous motion the
// depth images agree with most (see odometry.cc). prior_age: PriorAge of the pair, which
// widens the prior's uncertainty in the ICP answer's information (MeasuredInformation).
void ApplyFallback(const FrameImages& prev, const FrameImages& curr, const CameraIntrinsics& k,
                   const OdometryOptions& options, const Rigid3d& previous_motion, int prior_age, StageClock* clock,
                   PairAlignment* pair);

// Depth in metres and the colour image in grey.
void DecodeFrame(const RgbdSequence& seq, int index, StageClock* clock, cv::Mat* depth, cv::Mat* gray);
SiftFeatures DescribeFrame(const cv::Mat& gray, const cv::Mat& depth, const CameraIntrinsics& k,
                           const OdometryOptions& options, StageClock* clock);

// T0[reference] * reference_from_frame, re-orthonormalised (thousands of products drift off
// SO(3) in the last digits).
Rigid3d ChainPose(const Rigid3d& world_from_reference, const Rigid3d& reference_from_frame);

// Fills odometry->timings from the clock.
void CopyTimings(const StageClock& clock, OdometryTimings* timings);

}  // namespace f2c::internal
