#include "f2c/features/depth_features.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <limits>

#include "f2c/testing/synthetic_scene.h"

namespace f2c {
namespace {

using Vec3 = Eigen::Vector3d;
using testing::kDeg;

// The test room of testing::SyntheticScene (y down: the floor is y = 1.5, boxes stand on it),
// seen from above and behind the boxes, pitched down so the floor, box tops and the walls
// are all in view.
Rigid3d LookingDownAtTheBoxes() {
  Rigid3d pose = Rigid3d::Identity();
  pose.linear() = Eigen::AngleAxisd(-0.5, Vec3::UnitX()).toRotationMatrix();
  pose.translation() = Vec3(0.2, -0.4, -1.2);
  return pose;
}

// Options for noise-free depth: the sensor model that lets noisy cells count as flat is off,
// so only geometry decides (the defaults describe a Kinect-class sensor).
FeatureOptions NoiseFree() {
  FeatureOptions o;
  o.proxies.sensor_sigma_a = o.proxies.sensor_sigma_b = 0;
  return o;
}

struct Plane {
  Vec3 normal;
  double offset;  // normal . x = offset
};

// Every face of the room and of the boxes, in camera coordinates.
std::vector<Plane> ScenePlanes(const testing::SyntheticScene& scene, const Rigid3d& world_from_camera) {
  std::vector<Plane> planes;
  std::vector<testing::Box> boxes = scene.solids;
  boxes.push_back(scene.room);
  for (const testing::Box& b : boxes) {
    for (int axis = 0; axis < 3; ++axis) {
      for (double value : {b.min[axis], b.max[axis]}) {
        const Vec3 n_world = Vec3::Unit(axis);
        const Vec3 n = world_from_camera.linear().transpose() * n_world;
        planes.push_back({n, value - n_world.dot(world_from_camera.translation())});
      }
    }
  }
  return planes;
}

struct Segment {
  Vec3 a, b;
  double Distance(const Vec3& p) const {
    const Vec3 d = b - a;
    const double t = std::clamp((p - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
    return (a + t * d - p).norm();
  }
};

enum class Edges { kAll, kTopAndSides, kBottom };

// Edges of a box, in camera coordinates. The bottom is the face at y = max (the floor).
std::vector<Segment> BoxEdges(const testing::Box& b, const Rigid3d& world_from_camera, Edges which = Edges::kAll) {
  std::vector<Segment> edges;
  const Rigid3d camera_from_world = world_from_camera.inverse();
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    for (double cu : {b.min[u], b.max[u]}) {
      for (double cv : {b.min[v], b.max[v]}) {
        Vec3 p0, p1;
        p0[axis] = b.min[axis], p1[axis] = b.max[axis];
        p0[u] = p1[u] = cu, p0[v] = p1[v] = cv;
        const bool bottom = axis != 1 && p0.y() == b.max.y();
        if ((which == Edges::kBottom && !bottom) || (which == Edges::kTopAndSides && bottom)) continue;
        edges.push_back({camera_from_world * p0, camera_from_world * p1});
      }
    }
  }
  return edges;
}

TEST(ExtractFrameFeatures, RecoversThePlanesOfNoiseFreeDepth) {
  const testing::SyntheticScene scene;
  const CameraIntrinsics k = testing::TestIntrinsics();
  const Rigid3d pose = LookingDownAtTheBoxes();
  const cv::Mat depth = testing::Render(scene, k, pose).depth;
  const FrameFeatures f = ExtractFrameFeatures(depth, k, NoiseFree());
  const std::vector<Plane> truth = ScenePlanes(scene, pose);
  ASSERT_GE(f.proxies.size(), 6u);  // floor, back wall, side walls, box tops and fronts
  int matched_cells = 0, cells = 0;
  for (const PlanarProxy& p : f.proxies) {
    cells += p.inliers;
    // The true plane with the closest normal among those through the proxy's centroid.
    double best_angle = 1e9, best_offset = 0;
    for (const Plane& t : truth) {
      const double sign = p.normal.cast<double>().dot(t.normal) < 0 ? -1.0 : 1.0;
      const double offset_error = std::abs(p.offset - sign * t.offset);
      if (offset_error > 0.05) continue;
      const double angle = std::acos(std::min(1.0, sign * p.normal.cast<double>().dot(t.normal)));
      if (angle < best_angle) best_angle = angle, best_offset = offset_error;
    }
    ASSERT_LT(best_angle, 1.0 * kDeg) << "proxy of " << p.inliers << " cells at " << p.centroid.transpose();
    EXPECT_LT(best_offset, 0.01) << "proxy of " << p.inliers << " cells";
    EXPECT_LT(p.rms, 0.002);
    matched_cells += p.inliers;
  }
  EXPECT_EQ(matched_cells, cells);
}

// A box face 1.5 m away in front of a wall 3 m away: a 1.5 m jump along the face's outline.
cv::Mat BoxInFrontOfWall() {
  cv::Mat depth(480, 640, CV_32F, cv::Scalar(3.0f));
  depth(cv::Rect(200, 152, 200, 176)).setTo(1.5f);  // u 200..399, v 152..327
  return depth;
}

TEST(ExtractFrameFeatures, SilhouetteAndShadowSitExactlyAtTheDepthJump) {
  const CameraIntrinsics k = testing::TestIntrinsics();
  const FrameFeatures f = ExtractFrameFeatures(BoxInFrontOfWall(), k, FeatureOptions());
  const int step = FeatureOptions().grid.step;
  auto inside = [](double u, double v) { return u >= 200 && u < 400 && v >= 152 && v < 328; };
  int silhouettes = 0, shadows = 0;
  for (const Feature& feature : f.features) {
    const double u = feature.pixel.x(), v = feature.pixel.y();
    // The cell next to it (one grid step away) lies on the other side of the jump.
    const bool at_jump = inside(u, v) != inside(u + step, v) || inside(u, v) != inside(u - step, v) ||
                         inside(u, v) != inside(u, v + step) || inside(u, v) != inside(u, v - step);
    if (feature.type == FeatureType::kSilhouette) {
      ++silhouettes;
      EXPECT_TRUE(at_jump && inside(u, v)) << u << "," << v;
      EXPECT_FLOAT_EQ(feature.position.z(), 1.5f);
      // Along the outline: horizontal on the top and bottom sides, vertical on the others
      // (away from the corners, where both meet).
      const bool side = u < 204 || u >= 396;
      const bool corner = (u < 216 || u >= 384) && (v < 168 || v >= 312);
      if (!corner) {
        EXPECT_NEAR(std::abs(feature.direction[side ? 1 : 0]), 1.0, 1e-3) << u << "," << v;
      }
    } else if (feature.type == FeatureType::kShadow) {
      ++shadows;
      EXPECT_TRUE(at_jump && !inside(u, v)) << u << "," << v;
      EXPECT_FLOAT_EQ(feature.position.z(), 3.0f);
    } else {
      EXPECT_TRUE(feature.type == FeatureType::kPlane || feature.type == FeatureType::kBorder)
          << FeatureTypeName(feature.type);
    }
  }
  // The outline is 2 (0.571 + 0.503) = 2.15 m long at 1.5 m: with 5 cm spacing, at least 2.15
  // / 0.1 features (no two within 5 cm, so a gap never exceeds 10 cm), at most 2.15 / 0.05.
  EXPECT_GE(silhouettes, 21);
  EXPECT_LE(silhouettes, 44);
  EXPECT_GE(shadows, 21);
}

TEST(ExtractFrameFeatures, RidgesOnBoxEdgesValleysWhereSurfacesMeetInside) {
  const testing::SyntheticScene scene;
  const CameraIntrinsics k = testing::TestIntrinsics();
  const Rigid3d pose = LookingDownAtTheBoxes();
  const FrameFeatures f = ExtractFrameFeatures(testing::Render(scene, k, pose).depth, k, NoiseFree());
  std::vector<Segment> convex, concave = BoxEdges(scene.room, pose);
  for (const testing::Box& b : scene.solids) {
    for (const Segment& s : BoxEdges(b, pose, Edges::kTopAndSides)) convex.push_back(s);
    for (const Segment& s : BoxEdges(b, pose, Edges::kBottom)) concave.push_back(s);  // box meets floor
  }
  // On an edge: within 1 cm of its line, parallel to it within 2 degrees, and at most 10 cm
  // past its ends (where three surfaces meet, a crease may run on by up to a cell or two).
  auto on_an_edge = [](const std::vector<Segment>& edges, const Feature& feature) {
    const Vec3 p = feature.position.cast<double>();
    for (const Segment& s : edges) {
      const Vec3 d = (s.b - s.a).normalized();
      const double line_distance = ((p - s.a) - (p - s.a).dot(d) * d).norm();
      if (line_distance < 0.01 && s.Distance(p) < 0.1 &&
          std::abs(d.dot(feature.direction.cast<double>())) > std::cos(2 * kDeg)) {
        return true;
      }
    }
    return false;
  };
  int ridges = 0, valleys = 0;
  for (const Feature& feature : f.features) {
    if (feature.type != FeatureType::kRidge && feature.type != FeatureType::kValley) continue;
    const bool ridge = feature.type == FeatureType::kRidge;
    ++(ridge ? ridges : valleys);
    EXPECT_TRUE(on_an_edge(ridge ? convex : concave, feature))
        << FeatureTypeName(feature.type) << " at " << (pose * feature.position.cast<double>()).transpose();
  }
  EXPECT_GE(ridges, 10);
  EXPECT_GE(valleys, 10);
}

TEST(ExtractFrameFeatures, FeaturesOfOneTypeAreAtLeastTheSpacingApart) {
  const testing::SyntheticScene scene;
  const CameraIntrinsics k = testing::TestIntrinsics();
  FeatureOptions options;
  options.min_spacing = 0.08;
  const FrameFeatures f = ExtractFrameFeatures(testing::Render(scene, k, LookingDownAtTheBoxes()).depth, k, options);
  ASSERT_GT(f.Count(FeatureType::kPlane), 100);
  for (size_t i = 0; i < f.features.size(); ++i) {
    for (size_t j = i + 1; j < f.features.size(); ++j) {
      if (f.features[i].type != f.features[j].type) continue;
      ASSERT_GE((f.features[i].position - f.features[j].position).norm(), 0.08f) << i << " " << j;
    }
  }
}

TEST(ExtractFrameFeatures, BadFramesGiveEmptyOrPartialResultsWithAReason) {
  const CameraIntrinsics k = testing::TestIntrinsics();
  const FrameFeatures empty = ExtractFrameFeatures(cv::Mat::zeros(480, 640, CV_32F), k, FeatureOptions());
  EXPECT_TRUE(empty.features.empty());
  EXPECT_TRUE(empty.proxies.empty());
  EXPECT_EQ(empty.note, "no valid depth");

  cv::Mat nan(480, 640, CV_32F, cv::Scalar(std::numeric_limits<float>::quiet_NaN()));
  EXPECT_EQ(ExtractFrameFeatures(nan, k, FeatureOptions()).note, "no valid depth");

  // NaN and infinite pixels are missing depth, like zeros: the same features either way.
  cv::Mat holes = BoxInFrontOfWall(), zeros = BoxInFrontOfWall();
  holes(cv::Rect(0, 0, 100, 480)).setTo(std::numeric_limits<float>::quiet_NaN());
  holes(cv::Rect(100, 0, 20, 480)).setTo(std::numeric_limits<float>::infinity());
  zeros(cv::Rect(0, 0, 120, 480)).setTo(0.0f);
  const FrameFeatures a = ExtractFrameFeatures(holes, k, FeatureOptions());
  const FrameFeatures b = ExtractFrameFeatures(zeros, k, FeatureOptions());
  ASSERT_EQ(a.features.size(), b.features.size());
  for (size_t i = 0; i < a.features.size(); ++i) EXPECT_EQ(a.features[i].position, b.features[i].position);

  // One plane filling the view: one proxy, plane and border features, no edges.
  const FrameFeatures wall = ExtractFrameFeatures(cv::Mat(480, 640, CV_32F, cv::Scalar(2.0f)), k, FeatureOptions());
  EXPECT_EQ(wall.proxies.size(), 1u);
  EXPECT_GT(wall.Count(FeatureType::kPlane), 0);
  EXPECT_EQ(wall.Count(FeatureType::kSilhouette) + wall.Count(FeatureType::kRidge) + wall.Count(FeatureType::kValley),
            0);
  EXPECT_EQ(wall.note, "no depth edges or creases");
  // Depth at isolated sample pixels 40 px apart: points (the ones on the image border are
  // border features), but no normals, so nothing planar.
  cv::Mat sparse = cv::Mat::zeros(480, 640, CV_32F);
  for (int v = 2; v < 480; v += 40) {
    for (int u = 2; u < 640; u += 40) sparse.at<float>(v, u) = 2.0f;
  }
  const FrameFeatures dots = ExtractFrameFeatures(sparse, k, FeatureOptions());
  EXPECT_TRUE(dots.proxies.empty());
  EXPECT_EQ(dots.Count(FeatureType::kPlane), 0);
  EXPECT_GT(dots.Count(FeatureType::kBorder), 0);
  EXPECT_EQ(dots.note, "no planar region");
}

}  // namespace
}  // namespace f2c
