#pragma once
// How well a reconstructed mesh matches the true surfaces (the simulator's scene.ply):
// accuracy, the distance from each mesh vertex to the nearest true triangle; and
// completeness, the share of the true surface (sampled evenly by area) that has a mesh
// vertex within `completeness_distance`. Doubled or bent walls from a bad registration
// raise the first; surfaces never seen, or smeared away, lower the second.

#include "f2c/eval/trajectory_error.h"
#include "f2c/io/ply.h"
#include "f2c/util/fields.h"

namespace f2c {

struct MeshErrorOptions {
  double completeness_distance = 0.02;  // metres
  double sample_spacing = 0.02;         // metres between the true surface's samples (about)
  double max_distance = 0.25;           // metres; farther vertices count as this far (and as "far")

  template <class V>
  void Fields(V& v) {
    v.Group("Evaluation");
    F2C_FIELD(v, completeness_distance, "", Positive(), "a true surface point is covered within this (m)");
    F2C_FIELD(v, sample_spacing, "", Positive(), "spacing of the true surfaces' samples (m)");
    F2C_FIELD(v, max_distance, "", Positive(), "farther vertices count as this far (m)");
  }
  void Check() const;
};

struct MeshError {
  ErrorStatistics accuracy;  // metres, over the mesh's vertices (capped at max_distance)
  double p90 = 0;            // 90th percentile of the accuracy distances (m)
  double far_fraction = 0;   // vertices beyond max_distance of every true triangle
  double completeness = 0;   // share of the true surface samples within completeness_distance
  int surface_samples = 0;
};

// `mesh` must already be in the truth's frame. InputError when `truth` has no triangles.
MeshError EvaluateMesh(const PlyPoints& mesh, const PlyPoints& truth, const MeshErrorOptions& options = {});

// Distance from p to the triangle (a, b, c) (exact: face, edge or corner).
double PointTriangleDistance(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                             const Eigen::Vector3d& c);

}  // namespace f2c
