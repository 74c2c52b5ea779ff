#pragma once
// Rendering of a sim::Scene into colour and depth, and a Kinect v1 / Xtion-like sensor
// model. Exact geometry first (rasterised visibility with the exact ray-plane depth per
// pixel, see raster.h), then each sensor effect, each switchable.

#include <memory>
#include <opencv2/core.hpp>

#include "f2c/geometry/intrinsics.h"
#include "f2c/geometry/rigid.h"
#include "f2c/sim/scene.h"
#include "f2c/util/fields.h"

namespace f2c::sim {

struct SensorOptions {
  // Depth from disparity: z = f b / d, d quantised to disparity_step pixels (structured
  // light sensors report 1/8-pixel disparities), plus Gaussian noise of
  // sigma(z) = sigma_a + sigma_b (z - 0.4)^2 metres (Nguyen et al., 3DIMPVT 2012).
  bool depth_noise = true;
  double baseline = 0.075;        // metres
  double disparity_step = 0.125;  // pixels
  double sigma_a = 0.0012;        // metres
  double sigma_b = 0.0019;        // metres per square metre
  // No depth outside [min_depth, max_depth] metres.
  double min_depth = 0.4;
  double max_depth = 5.0;
  // No depth where the surface is seen at more than this angle from its normal (degrees).
  bool drop_grazing = true;
  double max_incidence_deg = 80.0;
  // No depth beside depth edges (the projector's pattern is occluded there): a pixel whose
  // 4-neighbour depths differ by more than edge_jump * z is dropped.
  bool drop_depth_edges = true;
  double edge_jump = 0.1;
  // Colour: Gaussian noise (intensity levels) and a mild blur (sigma in pixels).
  bool color_noise = true;
  double color_sigma = 3.0;
  bool blur = true;
  double blur_sigma = 0.7;
  // Low-frequency depth distortion of uncalibrated sensors: z *= 1 + k r^2, r the distance
  // from the principal point over the focal length. 0 = off.
  double radial_distortion = 0.0;

  // Everything off: exact depth and colour.
  static SensorOptions Exact();

  template <class V>
  void Fields(V& v) {
    v.Group("Simulation");
    F2C_FIELD(v, depth_noise, "", {}, "structured-light depth noise and quantisation");
    F2C_FIELD(v, baseline, "", Positive(), "projector baseline (m)");
    F2C_FIELD(v, disparity_step, "", Positive(), "disparity quantisation (pixels)");
    F2C_FIELD(v, sigma_a, "", AtLeast(0), "depth noise a (m)");
    F2C_FIELD(v, sigma_b, "", AtLeast(0), "depth noise b (m per m^2)");
    F2C_FIELD(v, min_depth, "", AtLeast(0), "nearest depth seen (m)");
    F2C_FIELD(v, max_depth, "", Positive(), "farthest depth seen (m)");
    F2C_FIELD(v, drop_grazing, "", {}, "no depth at grazing incidence");
    F2C_FIELD(v, max_incidence_deg, "", AboveUpTo(0, 90), "...beyond this incidence (deg)");
    F2C_FIELD(v, drop_depth_edges, "", {}, "no depth beside depth edges");
    F2C_FIELD(v, edge_jump, "", Positive(), "...jumps above this (m)");
    F2C_FIELD(v, color_noise, "", {}, "colour noise");
    F2C_FIELD(v, color_sigma, "", AtLeast(0), "...its sigma (grey levels)");
    F2C_FIELD(v, blur, "", {}, "colour blur");
    F2C_FIELD(v, blur_sigma, "", AtLeast(0), "...its sigma (pixels)");
    F2C_FIELD(v, radial_distortion, "--depth-distortion", Between(-1, 1),
              "low-frequency depth distortion k: z *= 1 + k r^2 (0: off)");
  }
  void Check() const;
};

struct RenderedView {
  cv::Mat color;  // CV_8UC3 (BGR)
  cv::Mat depth;  // CV_32F metres, 0 = no depth
};

class Renderer {
 public:
  explicit Renderer(const Scene& scene);
  ~Renderer();
  // `noise_seed` fixes the sensor noise of this view (same seed, same bytes).
  RenderedView Render(const CameraIntrinsics& intrinsics, const Rigid3d& world_from_camera, const SensorOptions& sensor,
                      uint64_t noise_seed) const;
  // Distance along the ray to the first surface (infinity if none), and its triangle: a ray
  // cast against a BVH, for single rays (ground-truth correspondences, visibility tests).
  double CastRay(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction, int* triangle) const;

 private:
  struct Bvh;
  const Scene& scene_;
  std::unique_ptr<Bvh> bvh_;
};

}  // namespace f2c::sim
