#include "f2c/report/mesh_views.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "f2c/geometry/up.h"

namespace f2c {
namespace {

double Percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  const size_t i = std::min(v.size() - 1, static_cast<size_t>(q * static_cast<double>(v.size())));
  std::nth_element(v.begin(), v.begin() + static_cast<long>(i), v.end());
  return v[i];
}

// Image axes for a camera looking along `view` with `up` pointing up the picture.
Eigen::Matrix3d LookRotation(const Eigen::Vector3d& view, const Eigen::Vector3d& up) {
  const Eigen::Vector3d z = view.normalized();
  Eigen::Vector3d x = (-up).cross(z);
  if (x.norm() < 1e-9) x = z.unitOrthogonal();
  x.normalize();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix3d r;
  r.row(0) = x.transpose(), r.row(1) = y.transpose(), r.row(2) = z.transpose();
  return r;
}

Eigen::Vector3d Horizontal(const Eigen::Vector3d& forward, const Eigen::Vector3d& up) {
  Eigen::Vector3d h = forward - forward.dot(up) * up;
  return h.norm() > 1e-6 ? h.normalized() : up.unitOrthogonal();
}

}  // namespace

Eigen::Vector3d EstimateUp(const PlyPoints& mesh, const Eigen::Vector3d& prior) {
  return UpFromNormals(mesh.normals, prior);
}

MeshView TopView(const PlyPoints& mesh, const Eigen::Vector3d& up_in, const Eigen::Vector3d& forward, int width) {
  const Eigen::Vector3d up = up_in.normalized();
  const Eigen::Vector3d ahead = Horizontal(forward, up);
  MeshView v;
  v.orthographic = true;
  // Looking down; `ahead` up the picture: image down is -ahead.
  v.camera_from_world.row(0) = ahead.cross(up).transpose();
  v.camera_from_world.row(1) = (-ahead).transpose();
  v.camera_from_world.row(2) = (-up).transpose();
  std::vector<double> xs, ys, zs;
  for (const Eigen::Vector3f& p : mesh.positions) {
    const Eigen::Vector3d c = v.camera_from_world * p.cast<double>();
    xs.push_back(c.x()), ys.push_back(c.y()), zs.push_back(c.z());
  }
  const double x0 = Percentile(xs, 0.01), x1 = Percentile(xs, 0.99);
  const double y0 = Percentile(ys, 0.01), y1 = Percentile(ys, 0.99);
  const double span_x = std::max(x1 - x0, 0.1), span_y = std::max(y1 - y0, 0.1);
  v.width = width;
  v.height = std::clamp(static_cast<int>(width * span_y / span_x), width / 4, 2 * width);
  v.focal = 0.9 * std::min(v.width / span_x, v.height / span_y);
  // eye: the world point that lands at the picture's centre, above everything.
  const Eigen::Vector3d centre_cam(0.5 * (x0 + x1), 0.5 * (y0 + y1), Percentile(zs, 0.0) - 1.0);
  v.eye = v.camera_from_world.transpose() * centre_cam;
  return v;
}

MeshView PerspectiveView(const PlyPoints& mesh, const Eigen::Vector3d& up_in, const Eigen::Vector3d& forward, int width,
                         int height) {
  const Eigen::Vector3d up = up_in.normalized();
  const Eigen::Vector3d ahead = Horizontal(forward, up);
  std::vector<double> coords[3];
  for (const Eigen::Vector3f& p : mesh.positions) {
    for (int i = 0; i < 3; ++i) coords[i].push_back(p[i]);
  }
  Eigen::Vector3d centre, low, high;
  for (int i = 0; i < 3; ++i) {
    centre[i] = Percentile(coords[i], 0.5), low[i] = Percentile(coords[i], 0.02), high[i] = Percentile(coords[i], 0.98);
  }
  const double extent = std::max((high - low).norm(), 0.5);
  MeshView v;
  v.width = width, v.height = height;
  v.focal = 0.9 * width;
  v.eye = centre - 0.75 * extent * ahead + 0.55 * extent * up;
  v.camera_from_world = LookRotation(centre - v.eye, up);
  return v;
}

cv::Mat RenderMesh(const PlyPoints& mesh, const MeshView& v) {
  cv::Mat image(v.height, v.width, CV_8UC3, cv::Scalar(255, 255, 255));
  std::vector<float> depth(static_cast<size_t>(v.width) * v.height, std::numeric_limits<float>::infinity());
  const size_t n = mesh.positions.size();
  std::vector<Eigen::Vector3f> screen(n);  // pixel x, pixel y, depth along the view
  std::vector<float> shade(n, 1.0f);
  const Eigen::Vector3d view_dir = v.camera_from_world.row(2).transpose();
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d c = v.camera_from_world * (mesh.positions[i].cast<double>() - v.eye);
    if (v.orthographic) {
      screen[i] = Eigen::Vector3f(static_cast<float>(v.width / 2.0 + v.focal * c.x()),
                                  static_cast<float>(v.height / 2.0 + v.focal * c.y()), static_cast<float>(c.z()));
    } else {
      const double z = std::max(c.z(), 1e-3);
      screen[i] = Eigen::Vector3f(static_cast<float>(v.width / 2.0 + v.focal * c.x() / z),
                                  static_cast<float>(v.height / 2.0 + v.focal * c.y() / z),
                                  static_cast<float>(c.z() > 0.05 ? c.z() : -1.0));
    }
    if (!mesh.normals.empty()) {
      const double facing = std::abs(mesh.normals[i].cast<double>().dot(view_dir));
      shade[i] = static_cast<float>(0.35 + 0.65 * facing);
    }
  }
  for (const std::array<int32_t, 3>& f : mesh.faces) {
    const Eigen::Vector3f &a = screen[f[0]], &b = screen[f[1]], &c = screen[f[2]];
    if (a.z() < 0 || b.z() < 0 || c.z() < 0) continue;  // behind the camera
    const float area = (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
    if (std::abs(area) < 1e-12f) continue;
    const int x0 = std::max(0, static_cast<int>(std::floor(std::min({a.x(), b.x(), c.x()}))));
    const int x1 = std::min(v.width - 1, static_cast<int>(std::ceil(std::max({a.x(), b.x(), c.x()}))));
    const int y0 = std::max(0, static_cast<int>(std::floor(std::min({a.y(), b.y(), c.y()}))));
    const int y1 = std::min(v.height - 1, static_cast<int>(std::ceil(std::max({a.y(), b.y(), c.y()}))));
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        const float px = x + 0.5f, py = y + 0.5f;
        // Barycentric weights from the edge functions (either winding).
        const float w0 = ((b.x() - px) * (c.y() - py) - (b.y() - py) * (c.x() - px)) / area;
        const float w1 = ((c.x() - px) * (a.y() - py) - (c.y() - py) * (a.x() - px)) / area;
        const float w2 = 1.0f - w0 - w1;
        if (w0 < 0 || w1 < 0 || w2 < 0) continue;
        const float z = w0 * a.z() + w1 * b.z() + w2 * c.z();
        float& nearest = depth[static_cast<size_t>(y) * v.width + x];
        if (z >= nearest) continue;
        nearest = z;
        const float s = w0 * shade[f[0]] + w1 * shade[f[1]] + w2 * shade[f[2]];
        cv::Vec3b& out = image.at<cv::Vec3b>(y, x);
        for (int ch = 0; ch < 3; ++ch) {
          const float colour = mesh.colors.empty() ? 200.0f
                                                   : w0 * mesh.colors[f[0]][2 - ch] + w1 * mesh.colors[f[1]][2 - ch] +
                                                         w2 * mesh.colors[f[2]][2 - ch];  // stored RGB, drawn BGR
          out[ch] = static_cast<uint8_t>(std::clamp(colour * s, 0.0f, 255.0f));
        }
      }
    }
  }
  return image;
}

}  // namespace f2c
