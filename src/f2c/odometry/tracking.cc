#include "f2c/odometry/tracking.h"

#include <opencv2/video/tracking.hpp>

#include "f2c/util/error.h"

namespace f2c {

void TrackOptions::Check() const {
  CheckFields(*this);
  if (window % 2 == 0) ThrowInputError("--track-window", fmt::format("must be odd, got {}", window));
}

TrackingKeyframe MakeTrackingKeyframe(int frame, const cv::Mat& gray, cv::Mat depth, SiftFeatures sift,
                                      const TrackOptions& options) {
  TrackingKeyframe k;
  k.frame = frame;
  k.sift = std::move(sift);
  cv::buildOpticalFlowPyramid(gray, k.pyramid, cv::Size(options.window, options.window), options.pyramid_levels);
  k.depth = std::move(depth);
  k.gray = gray;
  return k;
}

TrackedPoints TrackKeypoints(const TrackingKeyframe& keyframe, const cv::Mat& gray, const cv::Mat& depth,
                             const CameraIntrinsics& intrinsics, const Rigid3d& keyframe_from_frame_guess,
                             const SiftOptions& depth_rules, const TrackOptions& options) {
  TrackedPoints out;
  const size_t n = keyframe.sift.size();
  if (n == 0) return out;
  const Rigid3d frame_from_keyframe = keyframe_from_frame_guess.inverse();
  std::vector<cv::Point2f> from, to;
  std::vector<int> index;
  from.reserve(n);
  to.reserve(n);
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d p = frame_from_keyframe * keyframe.sift.points_in_camera[i];
    if (p.z() <= 0.05) continue;  // behind the predicted camera
    const Eigen::Vector2d uv = intrinsics.Project(p);
    if (uv.x() < 0 || uv.y() < 0 || uv.x() > gray.cols - 1 || uv.y() > gray.rows - 1) continue;
    from.push_back(keyframe.sift.pixels[i]);
    to.emplace_back(static_cast<float>(uv.x()), static_cast<float>(uv.y()));
    index.push_back(static_cast<int>(i));
  }
  if (from.empty()) return out;
  const std::vector<cv::Point2f> start = to;
  std::vector<uchar> status;
  std::vector<float> error;
  const cv::Size window(options.window, options.window);
  const cv::TermCriteria stop(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, options.max_lk_iterations,
                              options.lk_epsilon);
  cv::calcOpticalFlowPyrLK(keyframe.pyramid, gray, from, to, status, error, window, options.pyramid_levels, stop,
                           cv::OPTFLOW_USE_INITIAL_FLOW);
  std::vector<uchar> back_status(status.size(), 1);
  std::vector<cv::Point2f> back;
  if (options.max_forward_backward > 0) {
    back = from;
    std::vector<float> back_error;
    cv::calcOpticalFlowPyrLK(gray, keyframe.pyramid, to, back, back_status, back_error, window, options.pyramid_levels,
                             stop, cv::OPTFLOW_USE_INITIAL_FLOW);
  }
  const double max_correction2 = options.max_correction * options.max_correction;
  const double max_fb2 = options.max_forward_backward * options.max_forward_backward;
  for (size_t j = 0; j < from.size(); ++j) {
    if (!status[j]) continue;
    const cv::Point2f d = to[j] - start[j];
    if (d.dot(d) > max_correction2) continue;
    if (options.max_forward_backward > 0) {
      const cv::Point2f fb = back[j] - from[j];
      if (!back_status[j] || fb.dot(fb) > max_fb2) continue;
    }
    ++out.tracked;
    float z = 0;
    if (!KeypointDepth(depth, to[j], depth_rules, &z)) continue;
    out.keyframe.push_back(keyframe.sift.points_in_camera[index[j]]);
    out.frame.push_back(intrinsics.Unproject(to[j].x, to[j].y, z));
  }
  return out;
}

}  // namespace f2c
