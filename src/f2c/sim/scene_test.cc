#include "f2c/sim/scene.h"

#include <gtest/gtest.h>

#include "f2c/sim/render.h"

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
      auto down = [&](double from) { return renderer.CastRay(Vec3(centre.x(), centre.y(), from), Vec3(0, 0, -1), nullptr); };
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

}  // namespace
}  // namespace f2c::sim
