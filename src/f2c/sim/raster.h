#pragma once
// Visibility by rasterisation: which triangle each pixel sees, and the exact depth of the
// ray through the pixel centre to that triangle's plane. Same answer as casting a ray per
// pixel (up to ties on shared edges), but costs O(pixels covered) instead of a BVH walk per
// pixel, which long wall triangles make slow.

#include <opencv2/core.hpp>
#include <vector>

#include "f2c/geometry/intrinsics.h"
#include "f2c/geometry/rigid.h"
#include "f2c/sim/scene.h"

namespace f2c::sim {

struct VisibilityBuffer {
  cv::Mat triangle;  // CV_32S, -1 where no surface is seen
  cv::Mat depth;     // CV_64F, depth along the optical axis (metres), 0 where none
};

// Triangles are clipped at `near` metres in front of the camera. Coincident surfaces go to
// the lower triangle id, as in Renderer::CastRay.
VisibilityBuffer RasterizeVisibility(const std::vector<Triangle>& triangles, const CameraIntrinsics& intrinsics,
                                     const Rigid3d& world_from_camera, double near = 1e-3);

}  // namespace f2c::sim
