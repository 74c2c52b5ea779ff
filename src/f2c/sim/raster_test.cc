#include "f2c/sim/raster.h"

#include <gtest/gtest.h>

#include "f2c/sim/render.h"
#include "f2c/sim/walk.h"

namespace f2c::sim {
namespace {

// The rasteriser must see what a ray cast through each pixel centre sees. They may differ
// only where a pixel centre lies on an edge between two surfaces at the same depth.
TEST(RasterizeVisibility, AgreesWithRayCastingAlongAWalk) {
  const CameraIntrinsics k{525.0, 525.0, 319.5, 239.5, 160, 120};  // every 4th pixel of VGA
  for (const std::string& name : SceneNames()) {
    const Scene scene = BuildScene(name, 5);
    const Renderer renderer(scene);
    WalkOptions walk;
    walk.frames = 400;
    const Trajectory poses = GenerateWalk(scene, walk);
    for (int i = 0; i < walk.frames; i += 40) {
      const Rigid3d& pose = poses.world_from_camera[i];
      const VisibilityBuffer buffer = RasterizeVisibility(scene.triangles, k, pose);
      int checked = 0, same_surface = 0;
      for (int v = 0; v < k.height; ++v) {
        for (int u = 0; u < k.width; ++u) {
          const Eigen::Vector3d d = pose.linear() * Eigen::Vector3d((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0);
          int id = -1;
          const double t = renderer.CastRay(pose.translation(), d, &id);
          ++checked;
          ASSERT_EQ(buffer.triangle.at<int>(v, u) < 0, id < 0) << name << " frame " << i << " pixel " << u << "," << v;
          if (id < 0) continue;
          EXPECT_NEAR(buffer.depth.at<double>(v, u), t, 1e-9 * t) << name << " frame " << i;
          same_surface += scene.triangles[buffer.triangle.at<int>(v, u)].surface == scene.triangles[id].surface;
        }
      }
      EXPECT_GE(same_surface, checked - 20) << name << " frame " << i;
    }
  }
}

// A triangle reaching behind the camera is clipped at the near plane, not projected through
// it: a floor under a camera that looks straight ahead covers exactly the lower half.
TEST(RasterizeVisibility, ClipsTrianglesBehindTheCamera) {
  const CameraIntrinsics k{100.0, 100.0, 49.5, 39.5, 100, 80};
  Triangle floor;
  floor.a = {-1e4, -1e4, 0};
  floor.b = {1e4, -1e4, 0};
  floor.c = {0, 2e4, 0};
  floor.normal = {0, 0, 1};
  Rigid3d pose = Rigid3d::Identity();
  Eigen::Matrix3d r;
  r.col(2) = Eigen::Vector3d(0, 1, 0);   // forward: +y
  r.col(0) = Eigen::Vector3d(1, 0, 0);   // right: +x
  r.col(1) = Eigen::Vector3d(0, 0, -1);  // down: -z
  pose.linear() = r;
  pose.translation() = Eigen::Vector3d(0, 0, 1.5);
  const VisibilityBuffer buffer = RasterizeVisibility({floor}, k, pose);
  for (int v = 0; v < k.height; ++v) {
    for (int u = 0; u < k.width; ++u) {
      if (v < 40) {
        EXPECT_EQ(buffer.triangle.at<int>(v, u), -1) << u << "," << v;  // above the horizon
        continue;
      }
      ASSERT_EQ(buffer.triangle.at<int>(v, u), 0) << u << "," << v;
      // Ray (x, (v - cy)/f, 1) meets z = 0 at depth 1.5 f / (v - cy).
      EXPECT_NEAR(buffer.depth.at<double>(v, u), 1.5 * k.fy / (v - k.cy), 1e-9);
    }
  }
}

}  // namespace
}  // namespace f2c::sim
