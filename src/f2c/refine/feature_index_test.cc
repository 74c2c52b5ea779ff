#include "f2c/refine/feature_index.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>

namespace f2c {
namespace {

// One proxy, the plane z = 2 seen head-on (normal towards the camera), and two plane
// features on it whose own cell fits are tilted and off the plane by depth noise, plus one
// plane feature on no proxy.
FrameFeatures NoisyWall() {
  FrameFeatures f;
  PlanarProxy wall;
  wall.normal = Eigen::Vector3f(0, 0, -1);
  wall.offset = -2;  // -z = -2
  wall.inliers = 50;
  f.proxies.push_back(wall);
  auto add = [&](Eigen::Vector3f position, Eigen::Vector3f direction, int proxy) {
    Feature feature;
    feature.type = FeatureType::kPlane;
    feature.position = position;
    feature.direction = direction.normalized();
    feature.proxy = proxy;
    f.features.push_back(feature);
  };
  add({0.3f, 0.1f, 2.01f}, {0.05f, 0, -1}, 0);
  add({-0.4f, 0.2f, 1.98f}, {0, -0.04f, -1}, 0);
  add({1.0f, 1.0f, 3.0f}, {0, 1, 0}, -1);
  return f;
}

const FeatureCloud& Planes(const FrameIndex& frame) { return frame.family(FeatureFamily::kPlane); }

// A plane feature keeps its own cell's fit, tilt and depth noise included, not its proxy's.
TEST(FeatureIndex, PlaneFeaturesKeepTheirOwnCellsFit) {
  const FrameFeatures features = NoisyWall();
  const auto frame = BuildFrameIndex(features, FeatureIndexOptions());
  ASSERT_EQ(Planes(*frame).size(), 3);  // extraction order kept
  for (int i = 0; i < 3; ++i) {
    EXPECT_TRUE(Planes(*frame).direction(i).isApprox(features.features[i].direction)) << i;
    EXPECT_TRUE(Planes(*frame).point(i).isApprox(features.features[i].position)) << i;
  }
}

// Shadow edges and image-border points depend on the view (where the camera stood, where the
// image ends), so they join the edge family only when asked (--use-shadows, --use-borders).
TEST(FeatureIndex, ViewDependentEdgesOnlyWhenAsked) {
  FrameFeatures f;
  const FeatureType types[] = {FeatureType::kSilhouette, FeatureType::kShadow, FeatureType::kBorder};
  for (int i = 0; i < 3; ++i) {
    Feature x;
    x.type = types[i];
    x.position = Eigen::Vector3f(0.1f * i, 0, 2);
    x.direction = Eigen::Vector3f(1, 0, 0);
    f.features.push_back(x);
  }
  FeatureIndexOptions o;
  EXPECT_EQ(BuildFrameIndex(f, o)->family(FeatureFamily::kEdge).size(), 1);
  o.use_shadows = true;
  EXPECT_EQ(BuildFrameIndex(f, o)->family(FeatureFamily::kEdge).size(), 2);
  o.use_borders = true;
  EXPECT_EQ(BuildFrameIndex(f, o)->family(FeatureFamily::kEdge).size(), 3);
  EXPECT_EQ(BuildFrameIndex(f, o)->family(FeatureFamily::kPlane).size(), 0);
}

// The bounded search returns the points within the bound, nearest first, and only those:
// against brute force over a random cloud, for bounds that cut through the neighbours, and
// for a point at exactly the bound's distance (a grid, so such distances are exact).
TEST(FeatureCloud, NearestWithinABoundIsTheNearestOfThoseWithinIt) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> coordinate(-1, 1);
  FeatureCloud cloud;
  std::vector<Eigen::Vector3f> points;
  for (int i = 0; i < 2000; ++i) {
    Feature f;
    f.position = Eigen::Vector3f(coordinate(rng), coordinate(rng), 2 + coordinate(rng));
    points.push_back(f.position);
    cloud.Add(f);
  }
  cloud.Build();
  uint32_t index[8];
  float d2[8];
  for (int q = 0; q < 300; ++q) {
    const Eigen::Vector3f query(1.2f * coordinate(rng), 1.2f * coordinate(rng), 2 + 1.2f * coordinate(rng));
    std::vector<float> all;
    for (const Eigen::Vector3f& p : points) all.push_back((p - query).squaredNorm());
    std::vector<int> order(all.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int a, int b) { return all[a] < all[b]; });
    for (const float bound : {0.0005f, 0.003f, 0.01f, 1.0f}) {
      int expected = 0;
      while (expected < 8 && all[order[expected]] <= bound) ++expected;
      const int k = cloud.Nearest(query, 8, index, d2, bound);
      ASSERT_EQ(k, expected) << "query " << q << ", bound " << bound;
      for (int m = 0; m < k; ++m) {
        EXPECT_EQ(static_cast<int>(index[m]), order[m]) << "query " << q << ", neighbour " << m;
        EXPECT_FLOAT_EQ(d2[m], all[order[m]]);
        EXPECT_LE(d2[m], bound);
      }
    }
    // Unbounded: the 8 nearest.
    ASSERT_EQ(cloud.Nearest(query, 8, index, d2), 8);
    EXPECT_EQ(static_cast<int>(index[7]), order[7]);
  }

  FeatureCloud grid;
  for (int x = 0; x < 4; ++x) {
    Feature f;
    f.position = Eigen::Vector3f(0.25f * x, 0, 2);
    grid.Add(f);
  }
  grid.Build();
  // From (0, 0, 2) the points are 0, 0.0625, 0.25 and 0.5625 away (squared, exact in floats).
  EXPECT_EQ(grid.Nearest(Eigen::Vector3f(0, 0, 2), 4, index, d2, 0.25f), 3);
  EXPECT_EQ(d2[2], 0.25f);
  EXPECT_EQ(grid.Nearest(Eigen::Vector3f(0, 0, 2), 4, index, d2, 0.2499f), 2);
  EXPECT_EQ(grid.Nearest(Eigen::Vector3f(0, 0, 2), 1, index, d2, 0.0f), 1);
  EXPECT_EQ(index[0], 0u);
  EXPECT_EQ(grid.Nearest(Eigen::Vector3f(3, 0, 2), 4, index, d2, 1.0f), 0);
}

}  // namespace
}  // namespace f2c
