#pragma once
// Pictures of a mesh for the reports and `fuse --pictures` (not a pipeline stage): the mesh
// rasterised with a depth buffer, vertex colours shaded by how squarely each surface faces
// the viewer.

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "f2c/io/ply.h"

namespace f2c {

struct MeshView {
  Eigen::Matrix3d camera_from_world = Eigen::Matrix3d::Identity();  // rows: image right, image down, viewing direction
  Eigen::Vector3d eye = Eigen::Vector3d::Zero();                    // camera position (world)
  bool orthographic = false;
  double focal = 500;  // pixels per unit of x/z (perspective) or per metre (orthographic)
  int width = 1024, height = 768;
};

// The world's up: the direction, within 45 degrees of `prior` (e.g. the cameras' mean -y),
// shared by the most vertex normals to within 10 degrees (floors, tables, ceilings), refined
// as their mean. `prior` itself when the mesh has no such surfaces.
Eigen::Vector3d EstimateUp(const PlyPoints& mesh, const Eigen::Vector3d& prior);

// From above (looking against `up`), the first camera's viewing direction `forward` pointing
// up the picture, the whole mesh (its 1st-99th percentile extent) in view.
MeshView TopView(const PlyPoints& mesh, const Eigen::Vector3d& up, const Eigen::Vector3d& forward, int width);
// From behind and above the first camera, looking down at the mesh's centre.
MeshView PerspectiveView(const PlyPoints& mesh, const Eigen::Vector3d& up, const Eigen::Vector3d& forward, int width,
                         int height);

// 8-bit BGR picture; the background is white.
cv::Mat RenderMesh(const PlyPoints& mesh, const MeshView& view);

}  // namespace f2c
