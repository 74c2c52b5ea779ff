#pragma once
// The paper's Fig. 1: a horizontal slab of the registered points, seen from above, once per
// set of poses (ground truth, T0, the result). Drift draws a wall twice, or bent; a
// consistent registration draws each wall once, as a thin line.

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "f2c/geometry/rigid.h"
#include "f2c/util/fields.h"

namespace f2c {

// What one frame saw, in its camera's coordinates, with unit normals (zero where none).
struct SliceFrame {
  std::vector<Eigen::Vector3f> points, normals;
};

struct SliceOptions {
  double thickness = 0.2;     // m: the slab's height
  double bin = 0.1;           // m: height bins when choosing where the slab goes
  double wall_max_cos = 0.3;  // a wall point: |normal . up| below this (more than 72 degrees from up)

  template <class V>
  void Fields(V& v) {
    v.Group("Report");
    F2C_FIELD(v, thickness, "", Positive(), "the slab's height (m)");
    F2C_FIELD(v, bin, "", Positive(), "height bins for the slab's place (m)");
    v.Field(wall_max_cos, "wall_max_cos", "", Bounds{.min = 0, .max = 1, .min_open = true, .max_open = true},
            "a wall point: |normal . up| below this");
  }
  void Check() const;  // InputError naming the field when out of range
};

// A slab: the points whose height (point . up) is within thickness/2 of `height`.
struct SliceBand {
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  double height = 0;
  double thickness = 0.2;
};

// Where to cut, under the given poses (one per frame; nullopt: the frame is left out): up from
// the horizontal surfaces' normals (geometry/up.h) near the cameras' mean -y axis; the height
// is the centre of the `bin`-tall layer holding the most wall points, so the slab crosses the
// walls where furniture hides them least.
SliceBand ChooseSliceBand(const std::vector<SliceFrame>& frames,
                          const std::vector<std::optional<Rigid3d>>& world_from_camera, const SliceOptions& options);

// The points inside the slab, in world coordinates, under the given poses.
std::vector<Eigen::Vector3d> SlicePoints(const std::vector<SliceFrame>& frames,
                                         const std::vector<std::optional<Rigid3d>>& world_from_camera,
                                         const SliceBand& band);

}  // namespace f2c
