#include "f2c/sim/scene.h"

#include <gtest/gtest.h>

#include "f2c/sim/render.h"
#include "f2c/sim/walk.h"

namespace f2c::sim {
namespace {

using Vec3 = Eigen::Vector3d;

// Walls with doors are 0.1 m partitions: a ray along the kitchen's side of the corridor wall
// (y = 4, door at x = 2) meets its face at y = 4.05, and a ray inside the door opening meets
// the jamb at x = 1.5.
TEST(Scene, PartitionWallsHaveThicknessAndDoorReveals) {
  const Scene scene = BuildScene("apartment", 0);
  const Renderer renderer(scene);
  EXPECT_NEAR(renderer.CastRay(Vec3(1.0, 5.0, 2.3), Vec3(0, -1, 0), nullptr), 0.95, 1e-9);
  EXPECT_NEAR(renderer.CastRay(Vec3(1.0, 2.0, 2.3), Vec3(0, 1, 0), nullptr), 1.95, 1e-9);
  EXPECT_NEAR(renderer.CastRay(Vec3(2.0, 4.0, 1.0), Vec3(-1, 0, 0), nullptr), 0.5, 1e-9);
  EXPECT_NEAR(renderer.CastRay(Vec3(2.0, 4.0, 1.0), Vec3(0, 0, 1), nullptr), 1.05, 1e-9);  // soffit at 2.05 m
  // Walls without doors are the building's shell: one face on the outline.
  EXPECT_NEAR(renderer.CastRay(Vec3(1.0, 2.0, 2.3), Vec3(-1, 0, 0), nullptr), 1.0, 1e-9);
}

// Furniture includes slabs with open space below: table tops (4 cm thick, 0.72-0.78 m high)
// and wall shelves (3 cm thick, 1.1-1.6 m high). A ray down from just under a slab's top
// meets its underside; one from under the slab travels on (to the floor, for a table).
TEST(Scene, FurnitureHasTablesAndShelves) {
  int tables = 0, shelves = 0;
  for (uint64_t seed = 0; seed < 6; ++seed) {
    const Scene scene = BuildScene("apartment", seed);
    const Renderer renderer(scene);
    for (const Triangle& t : scene.triangles) {
      const double area = 0.5 * (t.b - t.a).cross(t.c - t.a).norm();
      const double z = t.a.z();
      if (t.normal.z() < 0.99 || area < 0.01 || z <= 0 || z >= 2.0) continue;
      const Vec3 centre = (t.a + t.b + t.c) / 3;
      auto down = [&](double from) {
        return renderer.CastRay(Vec3(centre.x(), centre.y(), from), Vec3(0, 0, -1), nullptr);
      };
      if (z >= 0.72 && z <= 0.78 && std::abs(down(z - 0.001) - 0.039) < 1e-9) {
        ++tables;
        EXPECT_NEAR(down(z - 0.05), z - 0.05, 1e-9) << "between the legs, the floor";
      } else if (z >= 1.13 && z <= 1.63 && std::abs(down(z - 0.001) - 0.029) < 1e-9) {
        ++shelves;
        EXPECT_GT(down(z - 0.031), 0.2) << "open space under a shelf";
      }
    }
  }
  EXPECT_GT(tables, 0);
  EXPECT_GT(shelves, 0);
}

// The object scene: the camera circles the table at 1-1.5 m (0.9-1.3 m high), a little over
// one round in 30 s, aimed within a few degrees of its objects. Its image centre is on them
// in most frames (else on the floor through a gap) and never on a wall: the walls are beyond
// the sensor's 5 m from the table.
TEST(Scene, ObjectSceneIsCircledAndSeen) {
  for (uint64_t seed = 0; seed < 3; ++seed) {
    const Scene scene = BuildScene("object", seed);
    ASSERT_TRUE(scene.orbit.has_value());
    const Vec3 target = scene.orbit->target;
    const Renderer renderer(scene);
    WalkOptions options;
    options.frames = 900;
    options.seed = seed;
    const Trajectory walk = GenerateWalk(scene, options);
    double turned = 0;
    int on_objects = 0;  // frames whose image centre is on the table's objects
    for (int i = 0; i < options.frames; ++i) {
      const Rigid3d& pose = walk.world_from_camera[i];
      const Vec3 p = pose.translation();
      const double radius = (p - target).head<2>().norm();
      EXPECT_GE(radius, 1.0 - 0.01) << i;
      EXPECT_LE(radius, 1.5 + 0.01) << i;
      EXPECT_GE(p.z(), 0.9 - 0.01) << i;
      EXPECT_LE(p.z(), 1.3 + 0.01) << i;
      const Vec3 axis = pose.linear().col(2);
      EXPECT_GT(axis.dot((target - p).normalized()), std::cos(8 * M_PI / 180)) << i;
      EXPECT_LT(renderer.CastRay(p, axis, nullptr), 5.0) << "frame " << i << " sees no wall";
      on_objects += ((p + renderer.CastRay(p, axis, nullptr) * axis) - target).norm() < 0.5;
      if (i > 0) {
        const Vec3 q = walk.world_from_camera[i - 1].translation() - target, r = p - target;
        turned += std::atan2(q.x() * r.y() - q.y() * r.x(), q.x() * r.x() + q.y() * r.y());
      }
    }
    EXPECT_GT(on_objects, 0.8 * options.frames) << "seed " << seed;
    // 30 s at 0.3 m/s on a circle of about 1.25 m: more than one round, so the scan closes.
    EXPECT_GT(std::abs(turned), 2 * M_PI) << "seed " << seed;
    EXPECT_LT(std::abs(turned), 2 * M_PI * 1.5) << "seed " << seed;
    for (const Vec3& d : {Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(-1, 0, 0), Vec3(0, -1, 0)}) {
      EXPECT_GT(renderer.CastRay(Vec3(target.x(), target.y(), 2.7), d, nullptr), 5.0);
    }
  }
}

}  // namespace
}  // namespace f2c::sim
