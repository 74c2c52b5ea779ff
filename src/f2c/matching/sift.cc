#include "f2c/matching/sift.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include "f2c/util/error.h"

namespace f2c {

void SiftOptions::Check() const {
  CheckFields(*this);
  if (!(max_depth > min_depth)) {
    ThrowInputError("--max-depth", fmt::format("must be greater than --min-depth ({}), got {}", min_depth, max_depth));
  }
}

SiftFeatures ExtractSiftWithDepth(const cv::Mat& gray, const cv::Mat& depth,
                                  const CameraIntrinsics& intrinsics, const SiftOptions& options) {
  F2C_CHECK(gray.type() == CV_8UC1 && depth.type() == CV_32FC1 && gray.size() == depth.size(),
            "gray 8UC1 and depth 32FC1 of one size");
  auto sift = cv::SIFT::create(options.max_features, options.octave_layers,
                               options.contrast_threshold, options.edge_threshold, options.sigma);
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
  if (options.downscale > 1) {
    cv::Mat small;
    cv::resize(gray, small, cv::Size(), 1.0 / options.downscale, 1.0 / options.downscale, cv::INTER_AREA);
    sift->detectAndCompute(small, cv::noArray(), keypoints, descriptors);
    // Pixel centres: x_full = (x_small + 0.5) * s - 0.5.
    for (cv::KeyPoint& kp : keypoints) {
      kp.pt = (kp.pt + cv::Point2f(0.5f, 0.5f)) * static_cast<float>(options.downscale) - cv::Point2f(0.5f, 0.5f);
    }
  } else {
    sift->detectAndCompute(gray, cv::noArray(), keypoints, descriptors);
  }

  SiftFeatures features;
  features.detected = static_cast<int>(keypoints.size());
  std::vector<int> kept;
  for (int i = 0; i < static_cast<int>(keypoints.size()); ++i) {
    float z = 0;
    if (!KeypointDepth(depth, keypoints[i].pt, options, &z)) continue;
    features.points_in_camera.push_back(intrinsics.Unproject(keypoints[i].pt.x, keypoints[i].pt.y, z));
    features.pixels.push_back(keypoints[i].pt);
    kept.push_back(i);
  }
  features.descriptors.create(static_cast<int>(kept.size()), descriptors.cols, CV_32F);
  for (size_t r = 0; r < kept.size(); ++r) descriptors.row(kept[r]).copyTo(features.descriptors.row(static_cast<int>(r)));
  return features;
}

bool KeypointDepth(const cv::Mat& depth, const cv::Point2f& pixel, const SiftOptions& options, float* z) {
  const int u = static_cast<int>(std::lround(pixel.x));
  const int v = static_cast<int>(std::lround(pixel.y));
  if (u < 1 || v < 1 || u >= depth.cols - 1 || v >= depth.rows - 1) return false;
  const float centre = depth.at<float>(v, u);
  if (!(centre >= options.min_depth && centre <= options.max_depth)) return false;
  float lo = centre, hi = centre;
  for (int dv = -1; dv <= 1; ++dv) {
    for (int du = -1; du <= 1; ++du) {
      const float d = depth.at<float>(v + dv, u + du);
      lo = std::min(lo, d);
      hi = std::max(hi, d);
    }
  }
  if (lo <= 0 || hi - lo > options.max_depth_spread * centre) return false;
  *z = centre;
  return true;
}

std::vector<SiftMatch> MatchSiftRatio(const SiftFeatures& query, const SiftFeatures& train, double ratio,
                                      double relaxed_ratio, int relax_below_matches) {
  std::vector<SiftMatch> matches;
  if (query.size() < 2 || train.size() < 2) return matches;
  cv::BFMatcher matcher(cv::NORM_L2);
  std::vector<std::vector<cv::DMatch>> knn;
  matcher.knnMatch(query.descriptors, train.descriptors, knn, 2);
  auto collect = [&](double r) {
    matches.clear();
    for (const auto& m : knn) {
      if (m.size() == 2 && m[0].distance < r * m[1].distance) matches.push_back({m[0].queryIdx, m[0].trainIdx});
    }
  };
  collect(ratio);
  if (static_cast<int>(matches.size()) < relax_below_matches) collect(relaxed_ratio);
  return matches;
}

}  // namespace f2c
