#pragma once
// The paper's per-image features (§4.1, "Extracting Features"): planar patches and linear
// edges along creases and contours of the depth image, well spaced, each tied to the planar
// proxy it lies on. Thresholds follow DESIGN.md §2 (the authors' code).
//
//   plane       a sample of a flat cell (IsFlat, proxies.h); direction = its normal
//   silhouette  the near side of a depth jump (jump > edge_jump_fraction z and >= edge_min_jump)
//   shadow      the far side of the same jump
//   border      valid depth on the image border (the surface continues out of view)
//   ridge       a convex crease: two proxies meeting at more than crease_angle_deg
//   valley      a concave crease (a wall meeting the floor)
// Edge directions are unit 3D vectors along the edge (creases: n_a x n_b, exact; contours:
// the principal axis of the nearby edge cells of the same type).

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "f2c/features/point_grid.h"
#include "f2c/features/proxies.h"
#include "f2c/util/fields.h"

namespace f2c {

enum class FeatureType : uint8_t { kPlane = 0, kSilhouette, kShadow, kBorder, kRidge, kValley };
constexpr int kFeatureTypeCount = 6;
const char* FeatureTypeName(FeatureType type);

struct Feature {
  FeatureType type = FeatureType::kPlane;
  Eigen::Vector3f position = Eigen::Vector3f::Zero();   // camera coordinates, metres
  Eigen::Vector3f direction = Eigen::Vector3f::Zero();  // planes: normal (towards the camera); edges: along the edge
  // In [0, 1]: planes their cell's Flatness() (proxies.h); silhouette and shadow
  // min(1, jump / 0.5 m); border 1; creases sin(angle between the two planes).
  float salience = 0;
  int32_t proxy = -1;                               // proxy in this frame (creases: one of the two), -1 none
  Eigen::Vector2f pixel = Eigen::Vector2f::Zero();  // where it was found in the image
};

struct FeatureOptions {
  PointGridOptions grid;
  ProxyOptions proxies;
  double min_spacing = 0.05;        // metres between features of the same type (DESIGN.md)
  double edge_jump_fraction = 0.1;  // depth jump > this fraction of the near depth...
  double edge_min_jump = 0.1;       // ...and >= this many metres (DESIGN.md)
  int edge_max_gap = 2;             // cells of missing depth a jump may span (sensor shadows)
  double crease_angle_deg = 45;     // ridges/valleys where planes meet at more than this
  int crease_max_gap = 2;           // unlabelled cells between two proxies at a crease
  int edge_direction_radius = 3;    // cells: neighbourhood for contour directions
  bool border_features = true;

  template <class V>
  void Fields(V& v) {
    F2C_NESTED(v, grid);
    F2C_NESTED(v, proxies);
    v.Group("Features (paper 4.1; DESIGN.md section 2)");
    F2C_FIELD(v, min_spacing, "--min-spacing", AtLeast(0), "features of one type at least this far apart (m)");
    F2C_FIELD(v, edge_jump_fraction, "--edge-jump-fraction", Positive(),
              "contours: depth jump above this fraction of depth...");
    F2C_FIELD(v, edge_min_jump, "--edge-min-jump", AtLeast(0), "...and at least this many metres");
    F2C_FIELD(v, edge_max_gap, "", AtLeast(0), "cells of missing depth a jump may span");
    v.Field(crease_angle_deg, "crease_angle_deg", "--crease-angle",
            Bounds{.min = 0, .max = 180, .min_open = true, .max_open = true},
            "ridges/valleys where proxies meet at more than this (deg)");
    F2C_FIELD(v, crease_max_gap, "", AtLeast(0), "unlabelled cells between two proxies at a crease");
    F2C_FIELD(v, edge_direction_radius, "", AtLeast(1), "cells around a contour point for its direction");
    F2C_FIELD(v, border_features, "", {}, "image-border points as features");
  }
  void Check() const;  // InputError naming the field when out of range
};

struct FrameFeatures {
  std::vector<PlanarProxy> proxies;
  std::vector<Feature> features;  // grouped by type, in FeatureType order
  // Why a frame has no or only some kinds of features, empty otherwise: "no valid depth",
  // "no planar region", "no depth edges or creases".
  std::string note;
  int Count(FeatureType type) const;
};

// Intermediate results, for pictures and tests.
struct FeatureDebug {
  PointGrid grid;
  std::vector<int32_t> labels;  // per grid cell: proxy, or -1
};

// `depth` is CV_32F metres (0, NaN, inf = invalid). Never throws on bad depth: a frame
// without usable depth gives empty results and a note. Per frame, so `options` is not checked
// here: the stage checks it once (FeatureExtraction), as a caller of this alone must.
FrameFeatures ExtractFrameFeatures(const cv::Mat& depth, const CameraIntrinsics& intrinsics,
                                   const FeatureOptions& options, FeatureDebug* debug = nullptr);

}  // namespace f2c
