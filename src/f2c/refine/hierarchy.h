#pragma once
// The structural model's proxy hierarchy (paper §4.2, "Creating Co-planarity Constraints"):
// every per-image proxy is a child, placed in world coordinates by the current poses; in
// every window of the iteration, the children of the window's frames are clustered into
// coplanar sets by agglomerative hierarchical clustering, and each set becomes a parent proxy
// tied to its children (E_H). Windows grow each iteration, so a wall seen from two rooms joins
// one parent once a window holds both rooms.
//
// Clustering (ClusterCoplanar): two clusters may merge when their mean planes agree,
//   angle(N_a, N_b) <= max_normal_angle_deg,
//   |N_a . (c_b - c_a)| <= max_distance and |N_b . (c_a - c_b)| <= max_distance,
// (N: weighted mean normal, c: weighted centroid; weights are the proxies' inliers), and the
// pair that agrees best merges first (cost: distance / max_distance + angle / max_angle,
// the larger distance of the two), until no pair may. So that this stays near-linear in the
// proxies, a first pass assigns proxies, largest first, to the best cluster that agrees within
// premerge_fraction of both thresholds; the agglomerative merge then runs on those clusters.
// In-image separation: two children of one image were measured in one rigid depth image, so
// no pose error enters their relative placement. When such a pair is further apart than
// in_image_distance (a desk and the keyboard on it, a wall and a cupboard front) or beyond the
// merge angle, they are two surfaces, and no cluster may hold both (a cannot-link between
// their clusters).
// Each frame is in at most two windows, so children, parents and links grow linearly.

#include <Eigen/Core>
#include <nlohmann/json_fwd.hpp>
#include <vector>

#include "f2c/optim/constraints.h"
#include "f2c/optim/pose.h"
#include "f2c/refine/feature_index.h"
#include "f2c/refine/windows.h"
#include "f2c/util/fields.h"

namespace f2c {

struct HierarchyOptions {
  // The authors' code merges within 0.3 m and pi/8 (DESIGN.md §2). Measured here
  // (refine_test): that merges a wall with a cupboard front or a surface 20 deg
  // off it, or a desk with what stands on it, and E_H then bends the scan; the defaults are
  // 0.05 m and 5 deg.
  double max_distance = 0.05;  // metres
  double max_normal_angle_deg = 5;
  double premerge_fraction = 0.5;  // of both thresholds, for the first pass
  // Two children of one image further apart than this (metres) never share a parent (0: off).
  // A few sensor noise levels of a plane fitted to hundreds of points at 1-3 m.
  double in_image_distance = 0.015;
  // Agreement with the siblings, beyond the paper: a child whose centroid lies t from its
  // parent's robust plane (the weighted median of the children's offsets along the parent's
  // normal) has its link weighted by 1 / (1 + (t / (k s))^2), a Cauchy weight, with
  // s = max(agreement_floor, 1.4826 MAD) the children's robust spread about that plane and
  // k = agreement_scale (0: off, every link weighs its inliers). A proxy fitted across a wall
  // jog sits centimetres off a wall whose other views agree to millimetres, and under least
  // squares its offset turns its frame; where the parent's
  // children all spread, as under drift still to be removed, s grows with them and every
  // link keeps its pull.
  double agreement_scale = 0;
  double agreement_floor = 0.003;  // metres: the spread below which no child is singled out
  int agreement_min_children = 5;  // parents with fewer children keep every link whole
  // Children's planes without the depth noise, beyond the paper: E_P on each proxy's
  // covariance less its estimated noise (PlanarProxy::noise), and the child's plane the
  // smallest eigenvector of that. A least-squares plane through depth that is noisy along the
  // rays turns towards them, differently from each view, and E_H, asking all views of a wall
  // to be one plane, then turns each frame by its view's turn (docs/refinement.md, E_P).
  bool remove_proxy_noise = true;

  template <class V>
  void Fields(V& v) {
    v.Group("Refinement: planar structure (paper 4.2-4.3)");
    F2C_FIELD(v, max_distance, "--coplanar-distance", Positive(),
              "parents: children merge within this plane distance (m)");
    v.Field(max_normal_angle_deg, "max_normal_angle_deg", "--coplanar-angle",
            Bounds{.min = 0, .max = 90, .min_open = true, .max_open = true}, "...and this normal angle (deg)");
    F2C_FIELD(v, premerge_fraction, "", AboveUpTo(0, 1), "of both thresholds, for the first pass");
    F2C_FIELD(v, in_image_distance, "--coplanar-in-image-distance", AtLeast(0),
              "two children of one image further apart never share a parent (m; 0: off)");
    F2C_FIELD(v, agreement_scale, "--coplanar-agreement-scale", AtLeast(0),
              "E_H: a child t off its parent's robust plane weighs 1/(1+(t/(k s))^2), s its siblings' robust spread "
              "(k; 0: off)");
    F2C_FIELD(v, agreement_floor, "--coplanar-agreement-floor", Positive(), "...s at least this (m)");
    F2C_FIELD(v, agreement_min_children, "--coplanar-agreement-min-children", AtLeast(1),
              "...in parents of at least this many children");
    F2C_FIELD(v, remove_proxy_noise, "--proxy-noise-removal,!--no-proxy-noise-removal", {},
              "children's planes fitted without their estimated depth noise (off: the least-squares planes, turned "
              "towards the rays)");
  }
  void Check() const;  // InputError naming the option when out of range
};

struct ClusterItem {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // unit
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  double weight = 1;
  int image = -1;  // the image it was measured in (-1: none; no in-image separation test)
};

struct PlaneCluster {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();   // weighted mean, unit
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();  // weighted mean
  double weight = 0;
  std::vector<int> members;  // item indices, ascending
  double offset() const { return normal.dot(centroid); }
};

// Coplanar clusters of the items, heaviest first (ties: lowest member first). Deterministic.
// Per window: `options` as checked by the caller (BuildProxyHierarchy checks once).
std::vector<PlaneCluster> ClusterCoplanar(const std::vector<ClusterItem>& items, const HierarchyOptions& options);

// Each member's agreement with its siblings (HierarchyOptions::agreement_scale), in the
// order of cluster.members: all 1 when off or when the cluster is small.
std::vector<double> SiblingAgreement(const std::vector<ClusterItem>& items, const PlaneCluster& cluster,
                                     const HierarchyOptions& options);

struct HierarchyStats {
  int children = 0;
  int parents = 0;
  int parents_spanning_frames = 0;  // parents whose children come from two or more frames
  int links = 0;
  int links_discounted = 0;    // links whose sibling agreement is below one half
  double agreement_scale = 0;  // the k the links were weighted with (0: off)
};

struct ProxyHierarchy {
  // Children (every kept proxy of every frame), parents (their world planes from the
  // clustering) and links; relations are added by refine/relations.h.
  StructureConstraints structure;
  std::vector<int> parent_window;                // the window each parent was clustered in
  std::vector<std::vector<int>> window_parents;  // parents of each window
  std::vector<std::vector<int>> child_parents;   // parents of each child (one per window)
  HierarchyStats stats;
};

// A frame's proxy as a child (camera coordinates), its share its inliers; with
// `remove_noise`, its covariance less the proxy's noise and its plane that covariance's.
ChildProxy MakeChild(int frame, const PlanarProxy& proxy, bool remove_noise);

ProxyHierarchy BuildProxyHierarchy(const WindowSchedule& schedule, int iteration, const FeatureIndex& index,
                                   const PoseVector& poses, const HierarchyOptions& options);

// How far the children's normals, placed by `poses`, are from their parents' (degrees): the
// RMS over the links, each weighted by its child's inliers; 0 without links. In short windows
// the poses barely drift, so this is about how well views of one surface agree on its tilt.
double ChildNormalSpreadDeg(const StructureConstraints& structure, const PoseVector& poses);

nlohmann::json ToJson(const HierarchyStats& stats);

}  // namespace f2c
