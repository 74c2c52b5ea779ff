#include "f2c/odometry/depth_alignment.h"

#include <cmath>
#include <opencv2/rgbd.hpp>

#include "f2c/util/error.h"

namespace f2c {

void IcpOptions::Check() const {
  if (!(min_depth >= 0 && max_depth > min_depth)) ThrowInputError("icp depth range", "need 0 <= min < max");
  if (!(max_depth_difference > 0)) ThrowInputError("icp.max_depth_difference", "must be positive");
  if (!(max_points_part > 0 && max_points_part <= 1)) ThrowInputError("icp.max_points_part", "must be in (0, 1]");
  if (iterations.empty()) ThrowInputError("icp.iterations", "needs at least one pyramid level");
  if (!(max_translation > 0) || !(max_rotation_deg > 0)) ThrowInputError("icp limits", "must be positive");
}

bool AlignDepthIcp(const cv::Mat& source_depth, const cv::Mat& target_depth,
                   const CameraIntrinsics& k, const Rigid3d& initial_target_from_source,
                   const IcpOptions& options, Rigid3d* target_from_source) {
  const cv::Mat camera = (cv::Mat_<float>(3, 3) << k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1);
  cv::rgbd::ICPOdometry icp(camera, static_cast<float>(options.min_depth),
                            static_cast<float>(options.max_depth),
                            static_cast<float>(options.max_depth_difference),
                            static_cast<float>(options.max_points_part), options.iterations);
  icp.setMaxTranslation(options.max_translation);
  icp.setMaxRotation(options.max_rotation_deg);
  cv::Mat init(4, 4, CV_64F);
  const Eigen::Matrix4d m0 = initial_target_from_source.matrix();
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) init.at<double>(r, c) = m0(r, c);
  }
  cv::Mat rt;
  bool ok = false;
  try {
    // OpenCV: dst_p = Rt * src_p, i.e. Rt is target_from_source.
    ok = icp.compute(cv::Mat(), source_depth, cv::Mat(), cv::Mat(), target_depth, cv::Mat(), rt, init);
  } catch (const cv::Exception&) {
    ok = false;  // too few valid pixels for a pyramid level, etc.
  }
  if (!ok || rt.empty()) return false;
  Eigen::Matrix4d m;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) m(r, c) = rt.at<double>(r, c);
  }
  if (!m.allFinite()) return false;
  target_from_source->matrix() = m;
  return true;
}

DepthOverlap MeasureDepthOverlap(const cv::Mat& source_depth, const cv::Mat& target_depth,
                                 const CameraIntrinsics& k, const Rigid3d& target_from_source,
                                 double threshold, int stride) {
  DepthOverlap overlap;
  int inside = 0, agree = 0;
  double sum = 0;
  const Eigen::Matrix3f r = target_from_source.linear().cast<float>();
  const Eigen::Vector3f t = target_from_source.translation().cast<float>();
  for (int v = 0; v < source_depth.rows; v += stride) {
    const float* row = source_depth.ptr<float>(v);
    for (int u = 0; u < source_depth.cols; u += stride) {
      const float z = row[u];
      if (!(z > 0)) continue;
      const Eigen::Vector3f p((u - k.cx) * z / k.fx, (v - k.cy) * z / k.fy, z);
      const Eigen::Vector3f q = r * p + t;
      if (q.z() <= 0) continue;
      const int tu = static_cast<int>(std::lround(k.fx * q.x() / q.z() + k.cx));
      const int tv = static_cast<int>(std::lround(k.fy * q.y() / q.z() + k.cy));
      if (tu < 0 || tv < 0 || tu >= target_depth.cols || tv >= target_depth.rows) continue;
      const float zt = target_depth.at<float>(tv, tu);
      if (!(zt > 0)) continue;
      ++inside;
      const double e = std::abs(zt - q.z());
      if (e < threshold) {
        ++agree;
        sum += e * e;
      }
    }
  }
  overlap.samples = inside;
  overlap.fitness = inside > 0 ? static_cast<double>(agree) / inside : 0.0;
  overlap.rmse = agree > 0 ? std::sqrt(sum / agree) : 0.0;
  return overlap;
}

}  // namespace f2c
