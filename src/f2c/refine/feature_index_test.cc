#include "f2c/refine/feature_index.h"

#include <gtest/gtest.h>

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

TEST(FeatureIndex, PlaneNormalsFromTheCellTheProxyOrSnappedOntoIt) {
  const FrameFeatures features = NoisyWall();
  FeatureIndexOptions o;
  // Extraction order is kept (an even subsample of all three is all three).
  const auto cell = BuildFrameIndex(features, o);
  ASSERT_EQ(Planes(*cell).size(), 3);
  EXPECT_TRUE(Planes(*cell).direction(0).isApprox(features.features[0].direction));
  EXPECT_TRUE(Planes(*cell).point(0).isApprox(features.features[0].position));

  o.plane_normals = PlaneNormals::kProxy;
  const auto proxy = BuildFrameIndex(features, o);
  for (int i = 0; i < 2; ++i) {
    EXPECT_TRUE(Planes(*proxy).direction(i).isApprox(Eigen::Vector3f(0, 0, -1))) << i;
    EXPECT_TRUE(Planes(*proxy).point(i).isApprox(features.features[i].position)) << i;
  }
  // A feature on no proxy keeps its own normal.
  EXPECT_TRUE(Planes(*proxy).direction(2).isApprox(Eigen::Vector3f(0, 1, 0)));

  o.plane_normals = PlaneNormals::kSnap;
  const auto snap = BuildFrameIndex(features, o);
  EXPECT_TRUE(Planes(*snap).point(0).isApprox(Eigen::Vector3f(0.3f, 0.1f, 2.0f)));
  EXPECT_TRUE(Planes(*snap).point(1).isApprox(Eigen::Vector3f(-0.4f, 0.2f, 2.0f)));
  EXPECT_TRUE(Planes(*snap).direction(1).isApprox(Eigen::Vector3f(0, 0, -1)));
  EXPECT_TRUE(Planes(*snap).point(2).isApprox(features.features[2].position));
}

}  // namespace
}  // namespace f2c
