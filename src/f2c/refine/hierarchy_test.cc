#include "f2c/refine/hierarchy.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include <cmath>
#include <random>

namespace f2c {
namespace {

// Proxies sampled from known world planes: centroids spread over several metres of each
// plane, normals tilted by up to 1 degree, offsets off by up to 5 mm (within the default
// thresholds, 5 deg and 5 cm, by a margin).
std::vector<ClusterItem> SamplePlanes(const std::vector<std::pair<Eigen::Vector3d, double>>& planes, int per_plane,
                                      std::vector<int>* truth) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<ClusterItem> items;
  for (int k = 0; k < per_plane; ++k) {
    for (size_t p = 0; p < planes.size(); ++p) {
      const Eigen::Vector3d n = planes[p].first.normalized();
      const Eigen::Vector3d a = n.unitOrthogonal(), b = n.cross(a);
      ClusterItem item;
      item.normal = (n + 0.012 * u(rng) * a + 0.012 * u(rng) * b).normalized();
      item.centroid = planes[p].second * n + 2.5 * u(rng) * a + 1.2 * u(rng) * b + 0.005 * u(rng) * n;
      item.weight = 20 + 10 * k % 7;
      items.push_back(item);
      truth->push_back(static_cast<int>(p));
    }
  }
  return items;
}

TEST(ClusterCoplanar, ProxiesOfKnownPlanesGiveExactlyThosePlanes) {
  // A floor, two walls at right angles, and the ceiling facing down.
  const std::vector<std::pair<Eigen::Vector3d, double>> planes = {
      {{0, 0, 1}, 0.0}, {{-1, 0, 0}, -2.0}, {{0, -1, 0}, -3.0}, {{0, 0, -1}, -2.6}};
  std::vector<int> truth;
  const std::vector<ClusterItem> items = SamplePlanes(planes, 12, &truth);
  const std::vector<PlaneCluster> clusters = ClusterCoplanar(items, HierarchyOptions());
  ASSERT_EQ(clusters.size(), planes.size());
  for (const PlaneCluster& c : clusters) {
    ASSERT_EQ(c.members.size(), 12u);
    const int p = truth[c.members[0]];
    for (int m : c.members) EXPECT_EQ(truth[m], p);
    EXPECT_GT(c.normal.dot(planes[p].first.normalized()), std::cos(1.0 * M_PI / 180));
    EXPECT_NEAR(c.offset(), planes[p].second, 0.01);
  }
}

TEST(ClusterCoplanar, ParallelWallsApartAreMergedOnlyWithinTheDistanceThreshold) {
  // Two parallel walls 0.2 m apart, 3 m from the origin.
  const std::vector<std::pair<Eigen::Vector3d, double>> planes = {{{-1, 0, 0}, -3.0}, {{-1, 0, 0}, -3.2}};
  std::vector<int> truth;
  const std::vector<ClusterItem> items = SamplePlanes(planes, 8, &truth);
  HierarchyOptions options;
  options.max_distance = 0.1;
  const std::vector<PlaneCluster> apart = ClusterCoplanar(items, options);
  ASSERT_EQ(apart.size(), 2u);
  for (const PlaneCluster& c : apart) {
    for (int m : c.members) EXPECT_EQ(truth[m], truth[c.members[0]]);
  }
  options.max_distance = 0.3;  // the authors' threshold: one plane
  EXPECT_EQ(ClusterCoplanar(items, options).size(), 1u);
  // Normals 30 degrees apart never merge (default 5 deg), however close.
  std::vector<ClusterItem> tilted = {items[0], items[0]};
  tilted[1].normal = Eigen::AngleAxisd(30 * M_PI / 180, Eigen::Vector3d::UnitZ()) * tilted[1].normal;
  EXPECT_EQ(ClusterCoplanar(tilted, HierarchyOptions()).size(), 2u);
}

// A desk and a keyboard 3 cm above it: within the 5 cm merge distance, but every image that
// sees both measures them 3 cm apart, and no pose error enters that. They stay two parents;
// without the in-image test (or with a tolerance above 3 cm) they become one.
TEST(ClusterCoplanar, SurfacesThatOneImageSeesApartAreNeverMerged) {
  // Six images, each a piece of the desk (z = 0.72) and of the keyboard (z = 0.75), with
  // normals tilted by up to 0.3 degrees and heights off by up to 3 mm.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<ClusterItem> items;
  std::vector<int> truth;
  for (int image = 0; image < 6; ++image) {
    for (int p = 0; p < 2; ++p) {
      ClusterItem item;
      item.normal = Eigen::Vector3d(0.005 * u(rng), 0.005 * u(rng), 1).normalized();
      const double x = p == 0 ? 0.5 * u(rng) : 0.2 * u(rng), y = p == 0 ? 0.3 * u(rng) : 0.1 * u(rng);
      item.centroid = Eigen::Vector3d(x, y, (p == 0 ? 0.72 : 0.75) + 0.003 * u(rng));
      item.weight = p == 0 ? 200 : 40;
      item.image = image;
      items.push_back(item);
      truth.push_back(p);
    }
  }
  HierarchyOptions options;
  const std::vector<PlaneCluster> apart = ClusterCoplanar(items, options);
  ASSERT_EQ(apart.size(), 2u);
  for (const PlaneCluster& c : apart) {
    EXPECT_EQ(c.members.size(), 6u);
    for (int m : c.members) EXPECT_EQ(truth[m], truth[c.members[0]]);
  }
  options.in_image_distance = 0;
  EXPECT_EQ(ClusterCoplanar(items, options).size(), 1u);
  options.in_image_distance = 0.045;
  EXPECT_EQ(ClusterCoplanar(items, options).size(), 1u);
  // Two pieces of one plane in one image (a wall behind a lamp) still merge.
  std::vector<ClusterItem> pieces = {items[0], items[2]};
  pieces[0].image = pieces[1].image = 7;
  EXPECT_EQ(ClusterCoplanar(pieces, HierarchyOptions()).size(), 1u);
}

// Four frames see the same wall; windows of 2 frames overlap by one: three windows, one
// parent each, every child linked to the parent of each window it is in.
// A frame whose image holds one proxy: the plane with this normal through this centroid
// (camera coordinates).
std::unique_ptr<FrameIndex> OneProxyFrame(const Eigen::Vector3d& normal, const Eigen::Vector3d& centroid, int inliers) {
  PlanarProxy p;
  p.normal = normal.cast<float>();
  p.centroid = centroid.cast<float>();
  p.offset = p.normal.dot(p.centroid);
  p.covariance = Eigen::Vector3f(0.1f, 0.1f, 0).asDiagonal();
  p.inliers = inliers;
  auto frame = std::make_unique<FrameIndex>();
  frame->proxies.push_back(p);
  return frame;
}

// The window schedule of `frames` frames starting from windows of two.
WindowSchedule PairsFirst(int frames) {
  WindowOptions w;
  w.initial_frames = 2;
  return WindowSchedule(w, std::vector<double>(frames, 0.0));
}

TEST(BuildProxyHierarchy, OneParentPerWindowAndALinkPerChildAndWindow) {
  FeatureIndex index;
  PoseVector poses;
  for (int f = 0; f < 4; ++f) {
    Pose pose;
    pose.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(0.1 * f, Eigen::Vector3d::UnitY()));
    pose.translation = Eigen::Vector3d(0.2 * f, 0, 0);
    poses.push_back(pose);
    // The wall z = 3 (normal towards the cameras: -z), in this camera's coordinates.
    const Rigid3d camera_from_world = pose.ToRigid().inverse();
    index.frames.push_back(OneProxyFrame(camera_from_world.linear() * Eigen::Vector3d(0, 0, -1),
                                         camera_from_world * Eigen::Vector3d(0.2 * f, 0.1, 3), 50 + f));
  }
  const WindowSchedule schedule = PairsFirst(4);
  const ProxyHierarchy h = BuildProxyHierarchy(schedule, 0, index, poses, HierarchyOptions());
  ASSERT_EQ(schedule.Windows(0).size(), 3u);
  EXPECT_EQ(h.stats.children, 4);
  EXPECT_EQ(h.stats.parents, 3);
  EXPECT_EQ(h.stats.parents_spanning_frames, 3);
  EXPECT_EQ(h.stats.links, 6);
  const std::vector<size_t> per_child = {1, 2, 2, 1};
  for (int c = 0; c < 4; ++c) EXPECT_EQ(h.child_parents[c].size(), per_child[c]) << c;
  for (const PlaneEstimate& p : h.structure.parents) {
    EXPECT_NEAR(p.normal.z(), -1, 1e-6);
    EXPECT_NEAR(p.offset, -3, 1e-6);
  }
  for (const CoplanarLink& l : h.structure.links) EXPECT_NEAR(l.anchor.z(), 3, 1e-6);
  // The whole scan in one window: one parent of four children.
  const ProxyHierarchy full =
      BuildProxyHierarchy(schedule, schedule.iterations() - 1, index, poses, HierarchyOptions());
  EXPECT_EQ(full.stats.parents, 1);
  EXPECT_EQ(full.stats.links, 4);
}

// Six frames see the wall z = 3; frame 5's proxy lies 4 cm before it (within the merge
// distance, as a proxy across a wall jog can). With the sibling agreement on, the whole-scan
// parent's link to it is discounted and the others are whole; off, every link weighs 1.
TEST(BuildProxyHierarchy, AChildOffItsAgreeingSiblingsIsDiscounted) {
  FeatureIndex index;
  PoseVector poses(6);
  for (int f = 0; f < 6; ++f) {
    poses[f].translation = Eigen::Vector3d(0.3 * f, 0, 0);
    const double z = f == 5 ? 2.96 : 3.0 + 0.0005 * (f % 2);
    index.frames.push_back(OneProxyFrame(Eigen::Vector3d(0, 0, -1), Eigen::Vector3d(0, 0.1, z), 100));
  }
  const WindowSchedule schedule = PairsFirst(6);
  const int last = schedule.iterations() - 1;
  HierarchyOptions options;
  options.agreement_scale = 2;
  const ProxyHierarchy on = BuildProxyHierarchy(schedule, last, index, poses, options);
  ASSERT_EQ(on.stats.parents, 1);
  ASSERT_EQ(on.stats.links, 6);
  EXPECT_EQ(on.stats.links_discounted, 1);
  for (const CoplanarLink& l : on.structure.links) {
    // s is the 3 mm floor, t 4 cm (or 0.5 mm): 1 / (1 + (t / 6 mm)^2).
    if (l.child == 5) {
      EXPECT_NEAR(l.agreement, 1 / (1 + std::pow(0.04 / 0.006, 2)), 1e-3);
    } else {
      EXPECT_GT(l.agreement, 0.99) << l.child;
    }
  }
  const ProxyHierarchy off = BuildProxyHierarchy(schedule, last, index, poses, HierarchyOptions());
  EXPECT_EQ(off.stats.links_discounted, 0);
  for (const CoplanarLink& l : off.structure.links) EXPECT_EQ(l.agreement, 1.0f);
}

// A cluster of items on the plane z = 0 (normal +z) at the given heights, unit weights.
std::pair<std::vector<ClusterItem>, PlaneCluster> Heights(const std::vector<double>& z) {
  std::vector<ClusterItem> items;
  PlaneCluster cluster;
  for (size_t i = 0; i < z.size(); ++i) {
    ClusterItem item;
    item.centroid = {0.3 * i, 0.1 * i, z[i]};
    items.push_back(item);
    cluster.members.push_back(static_cast<int>(i));
  }
  cluster.weight = static_cast<double>(z.size());
  return {items, cluster};
}

TEST(SiblingAgreement, CauchyWeightOfTheOffsetFromTheWeightedMedianInRobustSpreads) {
  HierarchyOptions options;
  options.agreement_scale = 2;
  options.agreement_floor = 0.001;
  // Heights (mm) 0, 1, 2, 3, 4, 40: median 2 (half the weight at or below), absolute
  // deviations 2, 1, 0, 1, 2, 38: their median 1, so s = 1.4826 mm and k s = 2.9652 mm.
  const auto [items, cluster] = Heights({0, 0.001, 0.002, 0.003, 0.004, 0.040});
  const std::vector<double> a = SiblingAgreement(items, cluster, options);
  ASSERT_EQ(a.size(), 6u);
  const double ks = 2 * 1.4826e-3;
  const double offsets[] = {-0.002, -0.001, 0, 0.001, 0.002, 0.038};
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(a[i], 1 / (1 + std::pow(offsets[i] / ks, 2)), 1e-9) << i;
  EXPECT_LT(a[5], 0.01);  // the child across the jog lets go
  EXPECT_DOUBLE_EQ(a[2], 1.0);

  // The floor: with s at least 1 cm, the same child keeps more of its weight...
  options.agreement_floor = 0.01;
  EXPECT_NEAR(SiblingAgreement(items, cluster, options)[5], 1 / (1 + std::pow(0.038 / 0.02, 2)), 1e-9);
  // ...and off, or in a small cluster, every link weighs 1.
  options.agreement_scale = 0;
  for (double v : SiblingAgreement(items, cluster, options)) EXPECT_EQ(v, 1.0);
  options.agreement_scale = 2;
  options.agreement_min_children = 7;
  for (double v : SiblingAgreement(items, cluster, options)) EXPECT_EQ(v, 1.0);
}

TEST(SiblingAgreement, WhenAllChildrenSpreadNoneIsSingledOut) {
  // Children spread evenly over +-3 cm (drift not yet removed): the spread grows with them,
  // so the outermost keep most of their pull; a 3 cm child among millimetre siblings does not.
  HierarchyOptions options;
  options.agreement_scale = 3;
  std::vector<double> spread, tight;
  for (int i = 0; i <= 12; ++i) spread.push_back(-0.03 + 0.005 * i);
  for (int i = 0; i < 12; ++i) tight.push_back(0.0005 * (i % 3));
  tight.push_back(0.03);
  const auto [spread_items, spread_cluster] = Heights(spread);
  const auto [tight_items, tight_cluster] = Heights(tight);
  EXPECT_GT(SiblingAgreement(spread_items, spread_cluster, options).back(), 0.5);
  EXPECT_LT(SiblingAgreement(tight_items, tight_cluster, options).back(), 0.1);
}

// The children's normal spread: the inlier-weighted RMS angle to their parents, each child's
// normal turned into the world by its frame's pose. Child 0 (frame 0, identity) is 1 deg off
// the parent's z, child 1 (frame 1, turned 90 deg about z) 2 deg off, with 3 times the
// weight: sqrt((1 + 3 * 4) / 4) deg.
TEST(ChildNormalSpread, WeightedRmsAngleUnderThePoses) {
  const double deg = M_PI / 180;
  PoseVector poses(2);
  poses[1].rotation = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ());
  StructureConstraints s;
  s.parents.push_back({Eigen::Vector3d::UnitZ(), 0.0, Eigen::Vector3d::Zero()});
  ChildProxy a, b;
  a.frame = 0;
  a.normal = Eigen::Vector3f(std::sin(1 * deg), 0, std::cos(1 * deg));
  b.frame = 1;
  // In the world 2 deg off z towards x: in frame 1's camera (turned 90 deg), towards -y.
  b.normal = Eigen::Vector3f(0, -std::sin(2 * deg), std::cos(2 * deg));
  s.children = {a, b};
  EXPECT_EQ(ChildNormalSpreadDeg(s, poses), 0.0) << "no links";
  s.links.push_back({0, 0, Eigen::Vector3d::Zero(), 1.0f});
  s.links.push_back({1, 0, Eigen::Vector3d::Zero(), 3.0f});
  EXPECT_NEAR(ChildNormalSpreadDeg(s, poses), std::sqrt(13.0 / 4), 1e-5);
  // Frame 1 turned 2 deg more about y (its child's tilt towards x grows): 4 deg off.
  poses[1].rotation = Eigen::AngleAxisd(2 * deg, Eigen::Vector3d::UnitY()) * poses[1].rotation;
  EXPECT_NEAR(ChildNormalSpreadDeg(s, poses), std::sqrt((1 + 3 * 16.0) / 4), 1e-4);
}

TEST(MakeChild, TheChildsPlaneIsTheProxysWithoutItsNoise) {
  // A wall facing (0.6, 0, -0.8) through (1, 0, 4): its members spread 0.05 m^2 and 0.25 m^2
  // across it, and depth noise of 3 cm along the ray to the centroid adds to that. The
  // least-squares plane of the sum is turned towards the ray.
  const Eigen::Vector3f n(0.6f, 0, -0.8f), centroid(1, 0, 4);
  const Eigen::Vector3f u = Eigen::Vector3f::UnitY(), v = n.cross(u).normalized();
  const Eigen::Vector3f ray = centroid.normalized();
  PlanarProxy p;
  p.noise = 0.03f * 0.03f * ray * ray.transpose();
  p.covariance = 0.05f * v * v.transpose() + 0.25f * u * u.transpose() + p.noise;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3f> eig(p.covariance);
  p.normal = eig.eigenvectors().col(0);
  if (p.normal.dot(n) < 0) p.normal = -p.normal;
  p.centroid = centroid;
  p.offset = p.normal.dot(centroid);
  p.inliers = 120;
  ASSERT_GT(std::acos(std::min(1.0f, p.normal.dot(n))), 0.2 * M_PI / 180);  // turned by the noise

  const ChildProxy clean = MakeChild(3, p, true);
  EXPECT_EQ(clean.frame, 3);
  EXPECT_EQ(clean.share, 120);
  EXPECT_NEAR(clean.normal.dot(n), 1, 1e-6);
  EXPECT_NEAR(clean.offset, n.dot(centroid), 1e-5);
  EXPECT_EQ(clean.centroid, centroid);
  EXPECT_LT((clean.covariance - (p.covariance - p.noise)).norm(), 1e-7);

  const ChildProxy as_fitted = MakeChild(3, p, false);
  EXPECT_EQ(as_fitted.normal, p.normal);
  EXPECT_EQ(as_fitted.offset, p.offset);
  EXPECT_EQ(as_fitted.covariance, p.covariance);
}

}  // namespace
}  // namespace f2c
