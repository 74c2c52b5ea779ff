#include "f2c/refine/feature_index.h"

#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <nanoflann.hpp>
#include <nlohmann/json.hpp>

#include "f2c/util/error.h"

namespace f2c {

void FeatureIndexOptions::Check() const { CheckFields(*this); }

struct FeatureCloud::Tree {
  using Index =
      nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, FeatureCloud>, FeatureCloud, 3, uint32_t>;
  explicit Tree(const FeatureCloud& cloud) : index(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(12)) {}
  Index index;
};

FeatureCloud::FeatureCloud() = default;
FeatureCloud::~FeatureCloud() = default;

void FeatureCloud::Add(const Feature& f) {
  points_.push_back(f.position);
  directions_.push_back(f.direction);
  types_.push_back(static_cast<uint8_t>(f.type));
}

void FeatureCloud::Build() {
  points_.shrink_to_fit();
  directions_.shrink_to_fit();
  types_.shrink_to_fit();
  if (!points_.empty()) tree_ = std::make_unique<Tree>(*this);
}

int FeatureCloud::Nearest(const Eigen::Vector3f& query, int k, uint32_t* indices, float* squared_distances,
                          float max_squared_distance) const {
  if (!tree_ || k <= 0) return 0;
  // nanoflann's k-nearest set admits a point closer than its worst slot, which starts at the
  // largest float: starting it just above the bound prunes every cell beyond the bound, and
  // the points within it arrive in the same order as in the unbounded search.
  nanoflann::KNNResultSet<float, uint32_t, size_t> result(static_cast<size_t>(k));
  result.init(indices, squared_distances);
  if (max_squared_distance < std::numeric_limits<float>::infinity()) {
    squared_distances[k - 1] = std::nextafter(max_squared_distance, std::numeric_limits<float>::infinity());
  }
  tree_->index.findNeighbors(result, query.data(), nanoflann::SearchParams());
  return static_cast<int>(result.size());
}

size_t FeatureCloud::MemoryBytes() const {
  // Points, directions, types, and nanoflann's index array and nodes (about one node per
  // leaf of up to 12 points, 2 per split).
  const size_t n = points_.size();
  return n * (2 * sizeof(Eigen::Vector3f) + 1 + sizeof(uint32_t)) + (n / 6 + 1) * 48;
}

bool FamilyOf(FeatureType type, const FeatureIndexOptions& options, FeatureFamily* family) {
  switch (type) {
    case FeatureType::kPlane:
      *family = FeatureFamily::kPlane;
      return true;
    case FeatureType::kSilhouette:
    case FeatureType::kRidge:
    case FeatureType::kValley:
      *family = FeatureFamily::kEdge;
      return true;
    case FeatureType::kShadow:
      *family = FeatureFamily::kEdge;
      return options.use_shadows;
    case FeatureType::kBorder:
      *family = FeatureFamily::kEdge;
      return options.use_borders;
  }
  return false;
}

std::unique_ptr<FrameIndex> BuildFrameIndex(const FrameFeatures& features, const FeatureIndexOptions& options) {
  auto frame = std::make_unique<FrameIndex>();
  std::vector<int> members[kFeatureFamilyCount];
  for (int i = 0; i < static_cast<int>(features.features.size()); ++i) {
    FeatureFamily family;
    if (FamilyOf(features.features[i].type, options, &family)) members[static_cast<int>(family)].push_back(i);
  }
  const int caps[kFeatureFamilyCount] = {options.max_planes, options.max_edges};
  std::vector<int> kept;
  for (int f = 0; f < kFeatureFamilyCount; ++f) {
    const int n = static_cast<int>(members[f].size());
    const int take = std::min(n, caps[f]);
    // An even subsample in extraction order (the extraction orders features spatially).
    for (int j = 0; j < take; ++j) {
      // A plane feature keeps its own cell's normal (the paper). Its proxy's normal, or its
      // point snapped onto the proxy's plane, halved the simulated walks' correspondence error
      // but cost the real sequences, whose planes a Kinect bends by millimetres.
      const Feature& feature = features.features[members[f][static_cast<int64_t>(j) * n / take]];
      frame->families[f].Add(feature);
      frame->box.extend(feature.position);
      frame->centroid += feature.position;
      kept.push_back(members[f][static_cast<int64_t>(j) * n / take]);
    }
    frame->families[f].Build();
  }
  if (!kept.empty()) frame->centroid /= static_cast<float>(kept.size());
  // The structural model's children: the largest per-image proxies (extraction lists them
  // largest first).
  for (const PlanarProxy& proxy : features.proxies) {
    if (static_cast<int>(frame->proxies.size()) >= options.max_proxies) break;
    if (proxy.inliers >= options.min_proxy_inliers) frame->proxies.push_back(proxy);
  }
  const int samples = std::min<int>(options.coverage_samples, static_cast<int>(kept.size()));
  for (int j = 0; j < samples; ++j) {
    frame->coverage.push_back(features.features[kept[static_cast<int64_t>(j) * kept.size() / samples]].position);
  }
  return frame;
}

size_t FeatureIndex::MemoryBytes() const {
  size_t bytes = 0;
  for (const auto& f : frames) {
    bytes +=
        sizeof(FrameIndex) + f->coverage.size() * sizeof(Eigen::Vector3f) + f->proxies.size() * sizeof(PlanarProxy);
    for (const FeatureCloud& c : f->families) bytes += c.MemoryBytes();
  }
  return bytes;
}

}  // namespace f2c
