#include "f2c/sim/raster.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace f2c::sim {
namespace {

using Vec3 = Eigen::Vector3d;

// A triangle after clipping and projection: pixel-space vertices, and the inverse depth of
// its plane as an affine function of the pixel, w(u, v) = wu u + wv v + w0.
//
// Why affine: with the ray r = ((u - cx)/fx, (v - cy)/fy, 1) (z = 1, so the ray parameter is
// the depth) and the plane n.x = d in camera coordinates, the hit is at z = d / (n.r), so
// 1/z = (n.r)/d, which is linear in u and v. This is the exact ray-plane depth, not an
// interpolation of vertex depths.
struct ScreenTriangle {
  int id;
  double x[3], y[3];
  double wu, wv, w0;
  int u_min, u_max, v_min, v_max;
};

// Clip the polygon (camera coordinates) against z >= near (Sutherland-Hodgman, one plane).
int ClipNear(const Vec3 in[3], double near, Vec3 out[4]) {
  int n = 0;
  for (int i = 0; i < 3; ++i) {
    const Vec3& a = in[i];
    const Vec3& b = in[(i + 1) % 3];
    const bool a_in = a.z() >= near, b_in = b.z() >= near;
    if (a_in) out[n++] = a;
    if (a_in != b_in) out[n++] = a + (b - a) * ((near - a.z()) / (b.z() - a.z()));
  }
  return n;
}

}  // namespace

VisibilityBuffer RasterizeVisibility(const std::vector<Triangle>& triangles, const CameraIntrinsics& k,
                                     const Rigid3d& world_from_camera, double near) {
  const Rigid3d camera_from_world = world_from_camera.inverse();
  const Eigen::Matrix3d rotation = camera_from_world.linear();
  std::vector<ScreenTriangle> screen;
  screen.reserve(triangles.size() * 2);
  for (int id = 0; id < static_cast<int>(triangles.size()); ++id) {
    const Triangle& tri = triangles[id];
    const Vec3 corners[3] = {camera_from_world * tri.a, camera_from_world * tri.b, camera_from_world * tri.c};
    Vec3 poly[4];
    const int n = ClipNear(corners, near, poly);
    if (n < 3) continue;
    const Vec3 normal = rotation * tri.normal;
    const double offset = normal.dot(corners[0]);
    // A plane through the camera centre is seen edge-on: it covers no pixel area.
    if (std::abs(offset) < 1e-12) continue;
    double px[4], py[4];
    for (int i = 0; i < n; ++i) {
      px[i] = k.fx * poly[i].x() / poly[i].z() + k.cx;
      py[i] = k.fy * poly[i].y() / poly[i].z() + k.cy;
    }
    for (int f = 1; f + 1 < n; ++f) {  // fan
      ScreenTriangle s;
      s.id = id;
      const int idx[3] = {0, f, f + 1};
      double lo_x = 1e300, hi_x = -1e300, lo_y = 1e300, hi_y = -1e300;
      for (int i = 0; i < 3; ++i) {
        s.x[i] = px[idx[i]];
        s.y[i] = py[idx[i]];
        lo_x = std::min(lo_x, s.x[i]), hi_x = std::max(hi_x, s.x[i]);
        lo_y = std::min(lo_y, s.y[i]), hi_y = std::max(hi_y, s.y[i]);
      }
      s.u_min = std::max(0, static_cast<int>(std::ceil(lo_x)));
      s.u_max = std::min(k.width - 1, static_cast<int>(std::floor(hi_x)));
      s.v_min = std::max(0, static_cast<int>(std::ceil(lo_y)));
      s.v_max = std::min(k.height - 1, static_cast<int>(std::floor(hi_y)));
      if (s.u_min > s.u_max || s.v_min > s.v_max) continue;
      s.wu = normal.x() / (k.fx * offset);
      s.wv = normal.y() / (k.fy * offset);
      s.w0 = (normal.z() - normal.x() * k.cx / k.fx - normal.y() * k.cy / k.fy) / offset;
      screen.push_back(s);
    }
  }

  VisibilityBuffer out;
  out.triangle = cv::Mat(k.height, k.width, CV_32S, cv::Scalar(-1));
  out.depth = cv::Mat::zeros(k.height, k.width, CV_64F);
  cv::Mat inverse_depth = cv::Mat::zeros(k.height, k.width, CV_64F);
  constexpr int kBand = 16;
  const int bands = (k.height + kBand - 1) / kBand;
  // Each band of rows takes every triangle in id order, so ties (w equal) keep the lower id
  // and the result does not depend on the thread count.
  tbb::parallel_for(0, bands, [&](int band) {
    const int v_lo = band * kBand, v_hi = std::min(k.height, v_lo + kBand) - 1;
    for (const ScreenTriangle& s : screen) {
      if (s.v_max < v_lo || s.v_min > v_hi) continue;
      // Edge functions, oriented so that the inside is >= 0. Pixels exactly on an edge
      // belong to both triangles (a closed test, like the ray-triangle test): no cracks.
      double ea[3], eb[3], ec[3];
      const double area = (s.x[1] - s.x[0]) * (s.y[2] - s.y[0]) - (s.y[1] - s.y[0]) * (s.x[2] - s.x[0]);
      if (area == 0) continue;
      const double sign = area > 0 ? 1.0 : -1.0;
      double scale = 0;
      for (int i = 0; i < 3; ++i) {
        const int j = (i + 1) % 3;
        // E_i(u, v) = (x_j - x_i)(v - y_i) - (y_j - y_i)(u - x_i)
        ea[i] = -sign * (s.y[j] - s.y[i]);
        eb[i] = sign * (s.x[j] - s.x[i]);
        ec[i] = sign * ((s.y[j] - s.y[i]) * s.x[i] - (s.x[j] - s.x[i]) * s.y[i]);
        scale = std::max(scale, std::abs(ea[i]) + std::abs(eb[i]));
      }
      const double tolerance = -1e-9 * scale * (1 + std::abs(s.x[0]) + std::abs(s.y[0]));
      for (int v = std::max(v_lo, s.v_min); v <= std::min(v_hi, s.v_max); ++v) {
        int32_t* ids = out.triangle.ptr<int32_t>(v);
        double* inv = inverse_depth.ptr<double>(v);
        for (int u = s.u_min; u <= s.u_max; ++u) {
          bool inside = true;
          for (int i = 0; i < 3; ++i) inside &= ea[i] * u + eb[i] * v + ec[i] >= tolerance;
          if (!inside) continue;
          const double w = s.wu * u + s.wv * v + s.w0;
          if (w > inv[u] && w > 0) {
            inv[u] = w;
            ids[u] = s.id;
          }
        }
      }
    }
    for (int v = v_lo; v <= v_hi; ++v) {
      const double* inv = inverse_depth.ptr<double>(v);
      double* depth = out.depth.ptr<double>(v);
      for (int u = 0; u < k.width; ++u) depth[u] = inv[u] > 0 ? 1.0 / inv[u] : 0.0;
    }
  });
  return out;
}

}  // namespace f2c::sim
