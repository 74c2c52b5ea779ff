#include "f2c/geometry/intrinsics.h"

#include <fmt/format.h>

#include <cmath>
#include <map>

#include "f2c/util/error.h"
#include "f2c/util/text.h"

namespace f2c {
namespace {

const std::map<std::string, CameraIntrinsics>& Presets() {
  static const std::map<std::string, CameraIntrinsics> presets = {
      {"tum-fr1", {517.3, 516.5, 318.6, 255.3, 640, 480, true, {0.2624, -0.9531, -0.0054, 0.0026, 1.1633}}},
      {"tum-fr2", {520.9, 521.0, 325.1, 249.7, 640, 480, true, {0.2312, -0.7849, -0.0033, -0.0001, 0.9172}}},
      {"tum-fr3", {535.4, 539.2, 320.1, 247.6, 640, 480}},
      {"primesense", {525.0, 525.0, 319.5, 239.5, 640, 480}},
  };
  return presets;
}

}  // namespace

Eigen::Vector2d CameraIntrinsics::Distort(double u, double v) const {
  const double x = (u - cx) / fx, y = (v - cy) / fy;
  const auto& [k1, k2, p1, p2, k3] = distortion;
  const double r2 = x * x + y * y;
  const double radial = 1 + r2 * (k1 + r2 * (k2 + r2 * k3));
  const double xd = x * radial + 2 * p1 * x * y + p2 * (r2 + 2 * x * x);
  const double yd = y * radial + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y;
  return {fx * xd + cx, fy * yd + cy};
}

void CameraIntrinsics::Validate(const std::string& source) const {
  if (!(std::isfinite(fx) && std::isfinite(fy) && fx > 0 && fy > 0)) {
    ThrowInputError(source, fmt::format("focal length must be positive (fx={}, fy={})", fx, fy));
  }
  if (fx < kMinFocalPixels || fy < kMinFocalPixels || fx > kMaxFocalPixels || fy > kMaxFocalPixels) {
    ThrowInputError(source, fmt::format("focal length must be in [{:g}, {:g}] pixels (fx={}, fy={})", kMinFocalPixels,
                                        kMaxFocalPixels, fx, fy));
  }
  if (!(std::isfinite(cx) && std::isfinite(cy) && cx >= 0 && cy >= 0 && cx < kMaxImageSide && cy < kMaxImageSide &&
        (!size_known || (cx < width && cy < height)))) {
    if (!size_known) {
      ThrowInputError(source,
                      fmt::format("principal point ({}, {}) must be in [0, {:g}) pixels", cx, cy, kMaxImageSide));
    }
    ThrowInputError(source,
                    fmt::format("principal point ({}, {}) lies outside the {}x{} image", cx, cy, width, height));
  }
  for (double d : distortion) {
    if (!std::isfinite(d)) ThrowInputError(source, fmt::format("distortion coefficient {} is not finite", d));
  }
}

std::vector<std::string> IntrinsicsPresetNames() {
  std::vector<std::string> names;
  for (const auto& [name, _] : Presets()) names.push_back(name);
  return names;
}

CameraIntrinsics ParseIntrinsics(const std::string& text, const std::string& source) {
  if (const auto it = Presets().find(text); it != Presets().end()) return it->second;
  std::vector<double> values;
  size_t begin = 0;
  while (begin <= text.size()) {
    const size_t end = std::min(text.find(',', begin), text.size());
    double v = 0;
    if (!ParseDouble(text.substr(begin, end - begin), &v)) {
      ThrowInputError(source, fmt::format("'{}' is neither fx,fy,cx,cy[,k1,k2,p1,p2[,k3]] nor a preset ({})", text,
                                          fmt::join(IntrinsicsPresetNames(), ", ")));
    }
    values.push_back(v);
    begin = end + 1;
  }
  if (values.size() != 4 && values.size() != 8 && values.size() != 9) {
    ThrowInputError(
        source, fmt::format("expected 4 numbers fx,fy,cx,cy, 8 with k1,k2,p1,p2 or 9 with k3, got {}", values.size()));
  }
  CameraIntrinsics intrinsics{values[0], values[1], values[2], values[3], 640, 480, false};
  for (size_t i = 4; i < values.size(); ++i) intrinsics.distortion[i - 4] = values[i];
  intrinsics.Validate(source);
  return intrinsics;
}

CameraIntrinsics ReadIntrinsicsMatrixFile(const std::filesystem::path& path) {
  const std::vector<double> m = ReadNumberFile(path, 9, "a 3x3 camera matrix");
  if (m[1] != 0 || m[3] != 0 || m[6] != 0 || m[7] != 0 || m[8] != 1) {
    ThrowInputError(path, "not a camera matrix [fx 0 cx; 0 fy cy; 0 0 1]");
  }
  CameraIntrinsics intrinsics{m[0], m[4], m[2], m[5], 640, 480, false};
  intrinsics.Validate(path.string());
  return intrinsics;
}

}  // namespace f2c
