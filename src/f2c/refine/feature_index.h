#pragma once
// What the refinement keeps of each frame's features (paper §4.1: planar patches and depth
// edges), compactly, with a k-d tree (nanoflann) per family for the closest-feature search of
// E_C. Features are in their camera's coordinates, so the trees are built once and serve
// every iteration: a query point is moved into the target frame by the current relative pose.
//
// Families: planes match planes only; silhouettes, ridges and valleys match any of the three
// (the paper: planar features match planar features, edges edges). Shadows (the far side of a
// depth jump) and image-border points depend on the viewpoint, not on the surface, and are
// left out unless asked for.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <limits>
#include <memory>
#include <nlohmann/json_fwd.hpp>
#include <vector>

#include "f2c/features/depth_features.h"
#include "f2c/features/proxies.h"
#include "f2c/util/fields.h"

namespace f2c {

enum class FeatureFamily { kPlane = 0, kEdge = 1 };
constexpr int kFeatureFamilyCount = 2;

struct FeatureIndexOptions {
  // Features kept per frame and family (an even subsample when a frame has more): bounds
  // memory and search cost; 100 n correspondences per iteration need far fewer.
  int max_planes = 400;
  int max_edges = 400;
  bool use_shadows = false;
  bool use_borders = false;
  // Points kept per frame to estimate how much two views overlap (refine/pairs).
  int coverage_samples = 24;
  // Per-image proxies kept per frame for the structural model (the largest), and the fewest member
  // cells one must have (the extraction's own minimum is 10, DESIGN.md §2). Measured: 4 instead of
  // 8 halves the solve (fewer small parents tying many frames together) and keeps most of the
  // structure's gain.
  int max_proxies = 4;
  int min_proxy_inliers = 10;

  template <class V>
  void Fields(V& v) {
    v.Group("Refinement: frame pairs and correspondences (paper 4.2)");
    F2C_FIELD(v, max_planes, "--max-plane-features", AtLeast(1), "plane features kept per frame");
    F2C_FIELD(v, max_edges, "--max-edge-features", AtLeast(1), "edge features kept per frame");
    F2C_FIELD(v, use_shadows, "--use-shadows", {}, "also match shadow edges (view-dependent)");
    F2C_FIELD(v, use_borders, "--use-borders", {}, "also match image-border points (view-dependent)");
    F2C_FIELD(v, coverage_samples, "", AtLeast(1), "points per frame for the overlap of two views");
    v.Group("Refinement: planar structure (paper 4.2-4.3)");
    F2C_FIELD(v, max_proxies, "--max-proxies", AtLeast(0), "per-image proxies per frame taken as children (largest)");
    F2C_FIELD(v, min_proxy_inliers, "--min-proxy-inliers", AtLeast(3), "...with at least this many member cells");
  }
  void Check() const;
};

// One family of one frame: points, directions (normals or edge directions) and feature types.
class FeatureCloud {
 public:
  FeatureCloud();
  ~FeatureCloud();
  FeatureCloud(const FeatureCloud&) = delete;
  FeatureCloud& operator=(const FeatureCloud&) = delete;

  void Add(const Feature& feature);
  void Build();  // the k-d tree; call once after the last Add
  int size() const { return static_cast<int>(points_.size()); }
  const Eigen::Vector3f& point(int i) const { return points_[i]; }
  const Eigen::Vector3f& direction(int i) const { return directions_[i]; }
  FeatureType type(int i) const { return static_cast<FeatureType>(types_[i]); }
  // Up to `k` nearest points to `query` (camera coordinates of this frame), nearest first;
  // returns how many, with squared distances. Only points within `max_squared_distance` are
  // returned: the same as the first of the k nearest that are, found without visiting the
  // tree's cells beyond it (most queries of a partly overlapping pair find nothing near).
  int Nearest(const Eigen::Vector3f& query, int k, uint32_t* indices, float* squared_distances,
              float max_squared_distance = std::numeric_limits<float>::infinity()) const;
  size_t MemoryBytes() const;

  // nanoflann's dataset interface.
  size_t kdtree_get_point_count() const { return points_.size(); }
  float kdtree_get_pt(size_t i, size_t dim) const { return points_[i][static_cast<int>(dim)]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }

 private:
  struct Tree;
  std::vector<Eigen::Vector3f> points_, directions_;
  std::vector<uint8_t> types_;
  std::unique_ptr<Tree> tree_;
};

struct FrameIndex {
  FeatureCloud families[kFeatureFamilyCount];
  Eigen::AlignedBox3f box;  // of the kept features, camera coordinates
  Eigen::Vector3f centroid = Eigen::Vector3f::Zero();
  std::vector<Eigen::Vector3f> coverage;  // a spread subsample, for overlap estimates
  std::vector<PlanarProxy> proxies;       // the structural model's children, largest first
  const FeatureCloud& family(FeatureFamily f) const { return families[static_cast<int>(f)]; }
  bool empty() const { return families[0].size() + families[1].size() == 0; }
};

// Which family a feature type belongs to (false: not used).
bool FamilyOf(FeatureType type, const FeatureIndexOptions& options, FeatureFamily* family);

std::unique_ptr<FrameIndex> BuildFrameIndex(const FrameFeatures& features, const FeatureIndexOptions& options);

struct FeatureIndex {
  std::vector<std::unique_ptr<FrameIndex>> frames;
  size_t MemoryBytes() const;
};

}  // namespace f2c
