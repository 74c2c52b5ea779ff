#include "apps/feature_views.h"

#include <opencv2/imgproc.hpp>

namespace f2c::app {

cv::Vec3b FeatureColor(FeatureType type) {
  switch (type) {
    case FeatureType::kPlane:
      return {200, 200, 200};
    case FeatureType::kSilhouette:
      return {40, 40, 235};
    case FeatureType::kShadow:
      return {235, 120, 30};
    case FeatureType::kBorder:
      return {30, 220, 240};
    case FeatureType::kRidge:
      return {40, 200, 40};
    case FeatureType::kValley:
      return {220, 40, 220};
  }
  return {255, 255, 255};
}

namespace {

cv::Vec3b ProxyColor(int proxy) {
  uint32_t h = static_cast<uint32_t>(proxy + 1) * 2654435761u;
  h ^= h >> 15;
  return {static_cast<uint8_t>(60 + (h & 0x7f)), static_cast<uint8_t>(60 + ((h >> 8) & 0x7f)),
          static_cast<uint8_t>(60 + ((h >> 16) & 0x7f))};
}

}  // namespace

cv::Mat DrawFeatures(const FrameFeatures& f, const FeatureDebug& debug, const CameraIntrinsics& k) {
  const PointGrid& g = debug.grid;
  cv::Mat image(k.height, k.width, CV_8UC3, cv::Scalar(0, 0, 0));
  for (int y = 0; y < g.height; ++y) {
    for (int x = 0; x < g.width; ++x) {
      const int i = g.Index(x, y);
      if (!g.Valid(i)) continue;
      // Lambert shading by the normal, seen from the camera; grey where none was fitted.
      const double shade = g.HasNormal(i) ? 0.35 + 0.65 * std::abs(g.normals[i].z()) : 0.3;
      cv::Vec3b c(128, 128, 128);
      if (debug.labels[i] >= 0) c = ProxyColor(debug.labels[i]);
      const cv::Vec3b shaded(cv::saturate_cast<uint8_t>(c[0] * shade), cv::saturate_cast<uint8_t>(c[1] * shade),
                             cv::saturate_cast<uint8_t>(c[2] * shade));
      image(cv::Rect(x * g.step, y * g.step, g.step, g.step)).setTo(cv::Scalar(shaded[0], shaded[1], shaded[2]));
    }
  }
  for (const Feature& feature : f.features) {
    const cv::Point p(static_cast<int>(feature.pixel.x()), static_cast<int>(feature.pixel.y()));
    const cv::Vec3b c = FeatureColor(feature.type);
    const cv::Scalar color(c[0], c[1], c[2]);
    if (feature.type == FeatureType::kPlane) {
      cv::circle(image, p, 1, color, cv::FILLED);
      continue;
    }
    // A stroke along the 3D direction, projected (5 cm each way).
    const Eigen::Vector3f a = feature.position - 0.05f * feature.direction;
    const Eigen::Vector3f b = feature.position + 0.05f * feature.direction;
    if (a.z() > 0.05f && b.z() > 0.05f) {
      const Eigen::Vector2d pa = k.Project(a.cast<double>()), pb = k.Project(b.cast<double>());
      cv::line(image, cv::Point(pa.x(), pa.y()), cv::Point(pb.x(), pb.y()), color, 1, cv::LINE_AA);
    }
    cv::circle(image, p, 2, color, cv::FILLED);
  }
  return image;
}

PlyPoints FeaturesToPly(const FrameFeatures& f) {
  PlyPoints ply;
  for (const Feature& feature : f.features) {
    ply.positions.push_back(feature.position);
    ply.normals.push_back(feature.direction);
    const cv::Vec3b c = FeatureColor(feature.type);
    ply.colors.push_back({c[2], c[1], c[0]});
  }
  return ply;
}

}  // namespace f2c::app
