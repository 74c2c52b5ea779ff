#pragma once
// The structural model's relations E_G (paper §4.2, "Creating Planar Relationship
// Constraints"): between every two parent proxies of the same or of adjacent windows, the
// angle theta between their normals picks the nearest of parallel (0), orthogonal (pi/2) and
// antiparallel (pi), with weight
//   w_ab = exp(-(theta - theta_0)^2 / (2 sigma^2)),
// kept when |theta - theta_0| <= max_angle and w_ab > min_weight (the authors: sigma 7.5 deg,
// 0.15 pi, 0.1; DESIGN.md §2). The weight lets a relation guide where it is nearly met and
// fade where it is not.
//
// Beyond the paper, relations do not pull where an image measured otherwise: when a frame
// sees children of both parents, the angle between those children in that image (one rigid
// depth image, so no pose enters it) is evidence of the true angle. A relation whose
// inlier-weighted mean in-image angle is farther than covisible_tolerance_deg from theta_0 is
// dropped: two walls at 80 degrees that one image shows together stay at 80 degrees however
// tempting 90 is. Relations between parents never seen together (the ones that straighten
// drift across rooms) are kept as the paper has them.

#include <nlohmann/json_fwd.hpp>
#include <vector>

#include "f2c/optim/constraints.h"
#include "f2c/refine/hierarchy.h"
#include "f2c/util/fields.h"

namespace f2c {

struct RelationOptions {
  double sigma_deg = 7.5;
  double max_angle_deg = 27;  // 0.15 pi
  double min_weight = 0.1;
  bool adjacent_windows = true;        // also between parents of windows j and j + 1
  double covisible_tolerance_deg = 3;  // 0: no check
  // Beyond the paper: each parent keeps its relations to at most this many partners, the
  // strongest first (w_ab times the smaller parent's inliers); 0: all, as the paper. All
  // pairs grow as the square of the parents in a window, and late windows hold hundreds.
  int max_per_parent = 8;

  template <class V>
  void Fields(V& v) {
    v.Group("Refinement: planar structure (paper 4.2-4.3)");
    F2C_FIELD(v, sigma_deg, "--relation-sigma", Positive(),
              "relations: sigma of the Gaussian weight on the angle (deg)");
    v.Field(max_angle_deg, "max_angle_deg", "--relation-max-angle",
            Bounds{.min = 0, .max = 45, .min_open = true, .max_open = true},
            "relations: admitted within this of 0, 90, 180 deg (deg)");
    v.Field(min_weight, "min_weight", "--relation-min-weight", Bounds{.min = 0, .max = 1, .max_open = true},
            "relations: and with a weight above this");
    F2C_FIELD(v, adjacent_windows, "!--no-adjacent-relations", {},
              "relations within a window only (default: also between adjacent windows)");
    F2C_FIELD(v, max_per_parent, "--relations-per-parent", AtLeast(0),
              "each parent keeps its strongest relations to at most this many others (0: all, as the paper)");
    F2C_FIELD(v, covisible_tolerance_deg, "--relation-covisible-tolerance", AtLeast(0),
              "drop a relation when images that see both parents measure their angle farther than this from it (deg; "
              "0: off)");
  }
  void Check() const;  // InputError naming the option when out of range
};

// The relation for normals at angle theta (radians, [0, pi]): false when none is admitted.
bool ClassifyRelation(double theta, const RelationOptions& options, RelationType* type, double* weight);

struct RelationStats {
  int by_type[kRelationTypeCount] = {};
  int dropped_covisible = 0;  // admitted by angle, refused by an image that sees both
  int dropped_cap = 0;        // admitted, beyond max_per_parent
  int total() const { return by_type[0] + by_type[1] + by_type[2]; }
};

// Relations between the hierarchy's parents (by their clustered planes).
std::vector<PlaneRelation> DetectRelations(const ProxyHierarchy& hierarchy, const RelationOptions& options,
                                           RelationStats* stats = nullptr);

nlohmann::json ToJson(const RelationStats& stats);

}  // namespace f2c
