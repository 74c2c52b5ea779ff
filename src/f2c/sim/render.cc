#include "f2c/sim/render.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <opencv2/imgproc.hpp>

#include "f2c/sim/raster.h"
#include "f2c/util/error.h"

namespace f2c::sim {
namespace {

using Vec3 = Eigen::Vector3d;
constexpr double kInf = std::numeric_limits<double>::infinity();

uint64_t Mix(uint64_t h) {
  h ^= h >> 33;
  h *= 0xff51afd7ed558ccdULL;
  h ^= h >> 33;
  h *= 0xc4ceb9fe1a85ec53ULL;
  h ^= h >> 33;
  return h;
}
// One finaliser over a multiplicative combination: cheap enough to call per texel lookup.
uint64_t Hash(int64_t a, int64_t b, int64_t c = 0, uint64_t d = 0) {
  return Mix(static_cast<uint64_t>(a) * 0x9E3779B97F4A7C15ULL + static_cast<uint64_t>(b) * 0xC2B2AE3D27D4EB4FULL +
             static_cast<uint64_t>(c) * 0x165667B19E3779F9ULL + d * 0x27D4EB2F165667C5ULL);
}
double Unit(uint64_t h) { return (h >> 11) * (1.0 / 9007199254740992.0); }  // [0, 1)

// Lattice values for value noise: a 32-bit finaliser (murmur3's fmix32) is enough for a
// texture and costs a third of the 64-bit hash; value noise is most of the shading time.
double Lattice(int64_t ix, int64_t iy, uint64_t salt) {
  uint32_t h = static_cast<uint32_t>(ix) * 0x8DA6B343u ^ static_cast<uint32_t>(iy) * 0xD8163841u ^
               static_cast<uint32_t>(salt * 0xCB1AB31Fu);
  h ^= h >> 16;
  h *= 0x85EBCA6Bu;
  h ^= h >> 13;
  h *= 0xC2B2AE35u;
  h ^= h >> 16;
  return h * (1.0 / 4294967296.0);
}

// Smooth value noise in [0, 1] on a grid of `cell` metres.
double ValueNoise(double s, double t, double cell, uint64_t salt) {
  const double x = s / cell, y = t / cell;
  // floor() by truncation: without SSE4.1, std::floor is a library call, and this is the
  // renderer's innermost function.
  int64_t ix = static_cast<int64_t>(x), iy = static_cast<int64_t>(y);
  ix -= x < static_cast<double>(ix);
  iy -= y < static_cast<double>(iy);
  double u = x - static_cast<double>(ix), v = y - static_cast<double>(iy);
  u = u * u * (3 - 2 * u);
  v = v * v * (3 - 2 * v);
  const double a = Lattice(ix, iy, salt), b = Lattice(ix + 1, iy, salt);
  const double c = Lattice(ix, iy + 1, salt), d = Lattice(ix + 1, iy + 1, salt);
  return (a * (1 - u) + b * u) * (1 - v) + (c * (1 - u) + d * u) * v;
}

// Standard normal samples, looked up by hash: a per-pixel Box-Muller (a log, a sqrt and a
// cosine per sample, four samples per pixel) cost more than the rest of the render. 2^16
// samples drawn once from a fixed sequence, so every run sees the same table.
double Gaussian(uint64_t h) {
  static const std::vector<double> table = [] {
    std::vector<double> t(1 << 16);
    for (size_t i = 0; i < t.size(); ++i) {
      const uint64_t g = Mix(i * 0x9E3779B97F4A7C15ULL + 0x5EED);
      t[i] = std::sqrt(-2.0 * std::log(std::max(Unit(g), 1e-12))) * std::cos(2 * M_PI * Unit(Mix(g)));
    }
    return t;
  }();
  return table[h >> 48];
}

cv::Vec3d Tint(uint64_t h) {  // a muted random colour, BGR in [0, 255]
  return {90 + 120 * Unit(Mix(h)), 90 + 120 * Unit(Mix(h + 1)), 90 + 120 * Unit(Mix(h + 2))};
}

// Colour of a surface point. (s, t) are metres along the surface.
cv::Vec3d Shade(const Triangle& tri, double s, double t) {
  const uint64_t salt = tri.surface * 7919ULL;
  switch (tri.material) {
    case Material::kPlain:
      return Tint(salt);
    case Material::kNoise: {
      const double n = 0.5 * ValueNoise(s, t, 0.25, salt) + 0.3 * ValueNoise(s, t, 0.07, salt + 1) +
                       0.2 * ValueNoise(s, t, 0.02, salt + 2);
      return Tint(salt) * (0.45 + 0.9 * n);
    }
    case Material::kTiles: {
      const double size = 0.3, grout = 0.012;
      const double fs = s / size - std::floor(s / size), ft = t / size - std::floor(t / size);
      if (fs * size < grout || ft * size < grout) return {60, 60, 60};
      const double shade = 0.7 + 0.3 * Unit(Hash(std::floor(s / size), std::floor(t / size), 0, salt));
      return Tint(salt + 5) * shade * (0.9 + 0.2 * ValueNoise(s, t, 0.05, salt));
    }
    case Material::kPoster: {
      // Posters of 0.6 x 0.8 m on a 1.3 m grid, at 0.9-1.7 m height, half the cells.
      const double cell = 1.3;
      const double cs = std::floor(s / cell);
      const double ls = s - cs * cell;
      if (Unit(Hash(cs, 17, 0, salt)) < 0.6 && ls > 0.35 && ls < 0.95 && t > 0.9 && t < 1.7) {
        const int64_t bx = static_cast<int64_t>(std::floor(ls / 0.075)), by = static_cast<int64_t>(std::floor(t / 0.1));
        const uint64_t h = Hash(bx, by, cs, salt + 3);
        return {255 * Unit(h), 255 * Unit(Mix(h)), 255 * Unit(Mix(h + 9))};
      }
      return Tint(salt) * (0.85 + 0.3 * ValueNoise(s, t, 0.1, salt));
    }
    case Material::kWood: {
      const double grain = ValueNoise(s * 0.2, t * 4.0, 0.05, salt);
      const double board = Unit(Hash(std::floor(t / 0.15), 3, 0, salt));
      const double v = 0.55 + 0.35 * grain + 0.2 * board;
      return cv::Vec3d(40, 85, 140) * v;
    }
  }
  return {128, 128, 128};
}

struct Aabb {
  Vec3 lo = Vec3::Constant(kInf), hi = Vec3::Constant(-kInf);
  void Grow(const Vec3& p) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  bool Hit(const Vec3& o, const Vec3& inv, double t_max) const {
    double t0 = 0, t1 = t_max;
    for (int i = 0; i < 3; ++i) {
      double a = (lo[i] - o[i]) * inv[i], b = (hi[i] - o[i]) * inv[i];
      if (a > b) std::swap(a, b);
      t0 = std::max(t0, a);
      t1 = std::min(t1, b);
      if (t0 > t1) return false;
    }
    return true;
  }
};

// Möller-Trumbore, two-sided.
double IntersectTriangle(const Triangle& tri, const Vec3& o, const Vec3& d) {
  const Vec3 e1 = tri.b - tri.a, e2 = tri.c - tri.a;
  const Vec3 p = d.cross(e2);
  const double det = e1.dot(p);
  if (std::abs(det) < 1e-12) return kInf;
  const double inv = 1.0 / det;
  const Vec3 s = o - tri.a;
  const double u = s.dot(p) * inv;
  if (u < 0 || u > 1) return kInf;
  const Vec3 q = s.cross(e1);
  const double v = d.dot(q) * inv;
  if (v < 0 || u + v > 1) return kInf;
  const double t = e2.dot(q) * inv;
  return t > 1e-6 ? t : kInf;
}

}  // namespace

struct Renderer::Bvh {
  struct Node {
    Aabb box;
    int left = -1, right = -1;  // children, or -1 for a leaf
    int first = 0, count = 0;   // leaf: triangles order[first .. first + count)
  };
  std::vector<Node> nodes;
  std::vector<int> order;

  int Build(const std::vector<Triangle>& tris, const std::vector<Vec3>& centroids, int first, int count) {
    Node node;
    for (int i = first; i < first + count; ++i) {
      const Triangle& t = tris[order[i]];
      node.box.Grow(t.a);
      node.box.Grow(t.b);
      node.box.Grow(t.c);
    }
    const int index = static_cast<int>(nodes.size());
    nodes.push_back(node);
    if (count <= 4) {
      nodes[index].first = first;
      nodes[index].count = count;
      return index;
    }
    int axis = 0;
    (node.box.hi - node.box.lo).maxCoeff(&axis);
    const int mid = first + count / 2;
    std::nth_element(order.begin() + first, order.begin() + mid, order.begin() + first + count,
                     [&](int a, int b) { return centroids[a][axis] < centroids[b][axis]; });
    const int left = Build(tris, centroids, first, mid - first);
    const int right = Build(tris, centroids, mid, first + count - mid);
    nodes[index].left = left;
    nodes[index].right = right;
    return index;
  }
};

SensorOptions SensorOptions::Exact() {
  SensorOptions o;
  o.depth_noise = o.drop_grazing = o.drop_depth_edges = o.color_noise = o.blur = false;
  o.min_depth = 0.0;
  o.max_depth = 1e9;
  return o;
}

void SensorOptions::Check() const {
  CheckFields(*this);
  if (!(max_depth > min_depth))
    ThrowInputError("max_depth", fmt::format("must exceed min_depth ({}), got {}", min_depth, max_depth));
}

Renderer::Renderer(const Scene& scene) : scene_(scene), bvh_(std::make_unique<Bvh>()) {
  const int n = static_cast<int>(scene.triangles.size());
  F2C_CHECK(n > 0, "a scene has triangles");
  std::vector<Vec3> centroids(n);
  for (int i = 0; i < n; ++i) {
    const Triangle& t = scene.triangles[i];
    centroids[i] = (t.a + t.b + t.c) / 3.0;
  }
  bvh_->order.resize(n);
  std::iota(bvh_->order.begin(), bvh_->order.end(), 0);
  bvh_->Build(scene.triangles, centroids, 0, n);
}

Renderer::~Renderer() = default;

double Renderer::CastRay(const Vec3& o, const Vec3& d, int* triangle) const {
  const Vec3 inv(1.0 / d.x(), 1.0 / d.y(), 1.0 / d.z());
  double best = kInf;
  int best_tri = -1;
  int stack[64];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Bvh::Node& node = bvh_->nodes[stack[--top]];
    if (!node.box.Hit(o, inv, best)) continue;
    if (node.left < 0) {
      for (int i = node.first; i < node.first + node.count; ++i) {
        const int id = bvh_->order[i];
        const double t = IntersectTriangle(scene_.triangles[id], o, d);
        // Ties go to the lower triangle id, so coincident surfaces render the same every frame.
        if (t < best || (t == best && id < best_tri)) {
          best = t;
          best_tri = id;
        }
      }
    } else {
      stack[top++] = node.left;
      stack[top++] = node.right;
    }
  }
  if (triangle) *triangle = best_tri;
  return best;
}

RenderedView Renderer::Render(const CameraIntrinsics& k, const Rigid3d& world_from_camera, const SensorOptions& sensor,
                              uint64_t noise_seed) const {
  sensor.Check();
  RenderedView view;
  view.color.create(k.height, k.width, CV_8UC3);
  cv::Mat exact(k.height, k.width, CV_32F);
  cv::Mat incidence(k.height, k.width, CV_32F);
  const Vec3 origin = world_from_camera.translation();
  const Eigen::Matrix3d r = world_from_camera.linear();
  const VisibilityBuffer visible = RasterizeVisibility(scene_.triangles, k, world_from_camera);
  tbb::parallel_for(0, k.height, [&](int v) {
    const int32_t* ids = visible.triangle.ptr<int32_t>(v);
    const double* depths = visible.depth.ptr<double>(v);
    for (int u = 0; u < k.width; ++u) {
      const int id = ids[u];
      if (id < 0) {
        exact.at<float>(v, u) = 0;
        view.color.at<cv::Vec3b>(v, u) = {0, 0, 0};
        incidence.at<float>(v, u) = 0;
        continue;
      }
      const Vec3 d = r * Vec3((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0);  // z = 1: t is depth
      const double t = depths[u];
      const Triangle& tri = scene_.triangles[id];
      const Vec3 p = origin + t * d;
      double s, tt;
      if (std::abs(tri.normal.z()) > 0.9) {
        s = p.x();
        tt = p.y();
      } else {
        s = p.x() * -tri.normal.y() + p.y() * tri.normal.x();
        tt = p.z();
      }
      const cv::Vec3d c = Shade(tri, s, tt);
      view.color.at<cv::Vec3b>(v, u) = {cv::saturate_cast<uint8_t>(c[0]), cv::saturate_cast<uint8_t>(c[1]),
                                        cv::saturate_cast<uint8_t>(c[2])};
      exact.at<float>(v, u) = static_cast<float>(t);
      incidence.at<float>(v, u) = static_cast<float>(std::abs(tri.normal.dot(d.normalized())));
    }
  });

  // Sensor model on depth.
  view.depth = cv::Mat::zeros(k.height, k.width, CV_32F);
  const double cos_max = std::cos(sensor.max_incidence_deg * M_PI / 180.0);
  const double fb = k.fx * sensor.baseline;
  tbb::parallel_for(0, k.height, [&](int v) {
    for (int u = 0; u < k.width; ++u) {
      double z = exact.at<float>(v, u);
      if (!(z > 0)) continue;
      if (sensor.drop_grazing && incidence.at<float>(v, u) < cos_max) continue;
      if (sensor.drop_depth_edges) {
        bool edge = false;
        const int du[4] = {1, -1, 0, 0}, dv[4] = {0, 0, 1, -1};
        for (int i = 0; i < 4 && !edge; ++i) {
          const int uu = u + du[i], vv = v + dv[i];
          if (uu < 0 || vv < 0 || uu >= k.width || vv >= k.height) continue;
          const float zn = exact.at<float>(vv, uu);
          edge = !(zn > 0) || std::abs(zn - z) > sensor.edge_jump * z;
        }
        if (edge) continue;
      }
      if (sensor.radial_distortion != 0) {
        const double x = (u - k.cx) / k.fx, y = (v - k.cy) / k.fy;
        z *= 1.0 + sensor.radial_distortion * (x * x + y * y);
      }
      if (sensor.depth_noise) {
        const double g = Gaussian(Hash(u, v, static_cast<int64_t>(noise_seed), 0xD1));
        z += g * (sensor.sigma_a + sensor.sigma_b * (z - 0.4) * (z - 0.4));
        const double disparity = std::round(fb / z / sensor.disparity_step) * sensor.disparity_step;
        z = disparity > 0 ? fb / disparity : 0.0;
      }
      if (z < sensor.min_depth || z > sensor.max_depth) continue;
      view.depth.at<float>(v, u) = static_cast<float>(z);
    }
  });

  // Sensor model on colour.
  if (sensor.blur && sensor.blur_sigma > 0) {
    cv::GaussianBlur(view.color, view.color, cv::Size(0, 0), sensor.blur_sigma);
  }
  if (sensor.color_noise && sensor.color_sigma > 0) {
    tbb::parallel_for(0, k.height, [&](int v) {
      for (int u = 0; u < k.width; ++u) {
        cv::Vec3b& c = view.color.at<cv::Vec3b>(v, u);
        for (int ch = 0; ch < 3; ++ch) {
          const double g = Gaussian(Hash(u, v, static_cast<int64_t>(noise_seed), 0xC0 + ch));
          c[ch] = cv::saturate_cast<uint8_t>(c[ch] + sensor.color_sigma * g);
        }
      }
    });
  }
  return view;
}

}  // namespace f2c::sim
