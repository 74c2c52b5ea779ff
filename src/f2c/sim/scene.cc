#include "f2c/sim/scene.h"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>

#include <random>

#include "f2c/util/error.h"

namespace f2c::sim {
namespace {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;

constexpr double kDoorWidth = 1.0;
constexpr double kDoorHeight = 2.05;

class SceneBuilder {
 public:
  explicit SceneBuilder(double height) { scene_.ceiling_height = height; }

  // A planar quad a-b-c-d (two triangles); its normal follows the right-hand rule.
  void AddQuad(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, Material m, uint32_t surface) {
    const Vec3 n = (b - a).cross(d - a).normalized();
    scene_.triangles.push_back({a, b, c, n, m, surface});
    scene_.triangles.push_back({a, c, d, n, m, surface});
  }

  // A wall from p0 to p1 with door openings centred at the given distances along it.
  void AddWall(const Vec2& p0, const Vec2& p1, Material m, std::vector<double> doors = {}) {
    const uint32_t surface = next_surface_++;
    const double length = (p1 - p0).norm();
    const Vec2 dir = (p1 - p0) / length;
    auto at = [&](double s, double z) {
      const Vec2 p = p0 + s * dir;
      return Vec3(p.x(), p.y(), z);
    };
    const double h = scene_.ceiling_height;
    std::sort(doors.begin(), doors.end());
    double s = 0;
    for (double centre : doors) {
      const double d0 = centre - kDoorWidth / 2, d1 = centre + kDoorWidth / 2;
      if (d0 > s) AddQuad(at(s, 0), at(d0, 0), at(d0, h), at(s, h), m, surface);
      AddQuad(at(d0, kDoorHeight), at(d1, kDoorHeight), at(d1, h), at(d0, h), m, surface);  // lintel
      s = d1;
    }
    if (s < length) AddQuad(at(s, 0), at(length, 0), at(length, h), at(s, h), m, surface);
  }

  // Floor and ceiling of a convex room (fan triangulation).
  void AddRoom(const std::string& name, const std::vector<Vec2>& outline, Material floor,
               Material ceiling = Material::kPlain) {
    scene_.rooms.push_back({name, outline});
    const uint32_t floor_id = next_surface_++, ceiling_id = next_surface_++;
    const double h = scene_.ceiling_height;
    for (size_t i = 1; i + 1 < outline.size(); ++i) {
      const Vec3 a(outline[0].x(), outline[0].y(), 0), b(outline[i].x(), outline[i].y(), 0),
          c(outline[i + 1].x(), outline[i + 1].y(), 0);
      scene_.triangles.push_back({a, b, c, Vec3::UnitZ(), floor, floor_id});
      const Vec3 up(0, 0, h);
      scene_.triangles.push_back({a + up, c + up, b + up, -Vec3::UnitZ(), ceiling, ceiling_id});
    }
  }

  // An axis-aligned box standing on the floor (no bottom face).
  void AddBox(const Vec2& min, const Vec2& max, double height, Material m) {
    const Vec3 lo(min.x(), min.y(), 0), hi(max.x(), max.y(), height);
    const Vec3 p[8] = {{lo.x(), lo.y(), 0},      {hi.x(), lo.y(), 0},      {hi.x(), hi.y(), 0},
                       {lo.x(), hi.y(), 0},      {lo.x(), lo.y(), height}, {hi.x(), lo.y(), height},
                       {hi.x(), hi.y(), height}, {lo.x(), hi.y(), height}};
    AddQuad(p[0], p[1], p[5], p[4], m, next_surface_++);
    AddQuad(p[1], p[2], p[6], p[5], m, next_surface_++);
    AddQuad(p[2], p[3], p[7], p[6], m, next_surface_++);
    AddQuad(p[3], p[0], p[4], p[7], m, next_surface_++);
    AddQuad(p[4], p[5], p[6], p[7], m, next_surface_++);
  }

  // Furniture along the walls of an axis-aligned room, leaving its centre free for the walk.
  void Furnish(const Vec2& min, const Vec2& max, std::mt19937_64* rng) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const int count = 2 + static_cast<int>(u(*rng) * 2);
    for (int i = 0; i < count; ++i) {
      const double w = 0.5 + 0.7 * u(*rng), d = 0.4 + 0.3 * u(*rng), h = 0.45 + 0.8 * u(*rng);
      const int side = static_cast<int>(u(*rng) * 4) % 4;
      const double along = 0.2 + (1.0 - 0.4) * u(*rng);
      Vec2 lo, hi;
      if (side < 2) {  // south / north wall
        const double x = min.x() + along * (max.x() - min.x() - w);
        const double y = side == 0 ? min.y() + 0.05 : max.y() - 0.05 - d;
        lo = {x, y};
        hi = {x + w, y + d};
      } else {         // west / east wall
        const double y = min.y() + along * (max.y() - min.y() - w);
        const double x = side == 2 ? min.x() + 0.05 : max.x() - 0.05 - d;
        lo = {x, y};
        hi = {x + d, y + w};
      }
      AddBox(lo, hi, h, u(*rng) < 0.6 ? Material::kWood : Material::kNoise);
    }
  }

  // Waypoints passing straight through a door in a wall of direction `wall_dir`.
  void ThroughDoor(const Vec2& door, const Vec2& wall_dir, bool forward) {
    const Vec2 normal(-wall_dir.y(), wall_dir.x());
    const double sign = forward ? 1.0 : -1.0;
    scene_.waypoints.push_back(door - sign * 0.7 * normal);
    scene_.waypoints.push_back(door + sign * 0.7 * normal);
  }
  void Visit(const Vec2& p) { scene_.waypoints.push_back(p); }

  Scene Take() { return std::move(scene_); }

 private:
  Scene scene_;
  uint32_t next_surface_ = 0;
};

std::vector<Vec2> Rect(double x0, double y0, double x1, double y1) {
  return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
}

Scene TwoRooms(uint64_t seed) {
  std::mt19937_64 rng(seed);
  SceneBuilder b(2.6);
  b.AddRoom("living", Rect(0, 0, 5, 4), Material::kWood);
  b.AddRoom("study", Rect(5, 0, 10, 4), Material::kTiles);
  b.AddWall({0, 0}, {5, 0}, Material::kPoster);
  b.AddWall({5, 0}, {10, 0}, Material::kNoise);
  b.AddWall({10, 0}, {10, 4}, Material::kPoster);
  b.AddWall({10, 4}, {5, 4}, Material::kPlain);
  b.AddWall({5, 4}, {0, 4}, Material::kNoise);
  b.AddWall({0, 4}, {0, 0}, Material::kPoster);
  b.AddWall({5, 0}, {5, 4}, Material::kNoise, {2.0});
  b.Furnish({0, 0}, {5, 4}, &rng);
  b.Furnish({5, 0}, {10, 4}, &rng);
  // living -> study -> living -> study: each doorway crossed both ways, loops close.
  for (int lap = 0; lap < 2; ++lap) {
    b.Visit({2.0, 2.6});
    b.Visit({2.8, 1.4});
    b.ThroughDoor({5, 2}, {0, 1}, false);
    b.Visit({7.5, 1.3});
    b.Visit({8.0, 2.8});
    b.ThroughDoor({5, 2}, {0, 1}, true);
  }
  b.Visit({2.0, 2.6});
  return b.Take();
}

Scene Apartment(uint64_t seed) {
  std::mt19937_64 rng(seed);
  SceneBuilder b(2.6);
  b.AddRoom("corridor", Rect(0, 4, 12, 6), Material::kTiles);
  b.AddRoom("kitchen", Rect(0, 0, 4, 4), Material::kTiles);
  b.AddRoom("bedroom", Rect(4, 0, 8, 4), Material::kWood);
  b.AddRoom("office", Rect(8, 0, 12, 4), Material::kWood);
  b.AddRoom("living", {{2, 6}, {10, 6}, {9, 10}, {3, 10}}, Material::kWood);  // trapezoid
  b.AddWall({0, 0}, {12, 0}, Material::kNoise);
  b.AddWall({12, 0}, {12, 6}, Material::kPoster);
  b.AddWall({0, 6}, {0, 0}, Material::kPoster);
  b.AddWall({4, 0}, {4, 4}, Material::kNoise);
  b.AddWall({8, 0}, {8, 4}, Material::kNoise);
  b.AddWall({0, 4}, {12, 4}, Material::kNoise, {2.0, 6.0, 10.0});
  b.AddWall({12, 6}, {10, 6}, Material::kPlain);
  b.AddWall({10, 6}, {2, 6}, Material::kPoster, {4.0});  // door at x = 6
  b.AddWall({2, 6}, {0, 6}, Material::kPlain);
  b.AddWall({10, 6}, {9, 10}, Material::kNoise);
  b.AddWall({9, 10}, {3, 10}, Material::kPoster);
  b.AddWall({3, 10}, {2, 6}, Material::kNoise);
  b.Furnish({0, 0}, {4, 4}, &rng);
  b.Furnish({4, 0}, {8, 4}, &rng);
  b.Furnish({8, 0}, {12, 4}, &rng);
  const Vec2 x_axis(1, 0);
  b.Visit({1.3, 2.2});  // kitchen
  b.Visit({2.6, 1.4});
  b.ThroughDoor({2, 4}, x_axis, true);
  b.Visit({4.0, 5.0});
  b.ThroughDoor({6, 4}, x_axis, false);
  b.Visit({5.2, 1.6});  // bedroom: a loop around its centre, not a dead end
  b.Visit({6.8, 1.6});
  b.ThroughDoor({6, 4}, x_axis, true);
  b.Visit({8.0, 5.0});
  b.ThroughDoor({10, 4}, x_axis, false);
  b.Visit({9.2, 1.6});  // office
  b.Visit({10.8, 1.6});
  b.ThroughDoor({10, 4}, x_axis, true);
  b.Visit({7.5, 5.0});
  b.ThroughDoor({6, 6}, x_axis, true);
  b.Visit({6.0, 8.2});  // living room (trapezoid)
  b.Visit({4.5, 8.6});
  b.ThroughDoor({6, 6}, x_axis, false);
  b.Visit({3.5, 5.0});
  b.ThroughDoor({2, 4}, x_axis, false);
  b.Visit({2.6, 1.4});  // back in the kitchen: the loop closes
  b.Visit({1.3, 2.2});
  return b.Take();
}

Scene Corridor(uint64_t seed) {
  std::mt19937_64 rng(seed);
  SceneBuilder b(2.5);
  b.AddRoom("west", Rect(-5, -1.5, 0, 3.5), Material::kWood);
  b.AddRoom("corridor", Rect(0, 0, 20, 2), Material::kTiles);
  b.AddRoom("east", Rect(20, -1.5, 25, 3.5), Material::kWood);
  b.AddWall({0, 0}, {20, 0}, Material::kPoster);
  b.AddWall({20, 2}, {0, 2}, Material::kNoise);
  b.AddWall({0, -1.5}, {0, 3.5}, Material::kNoise, {2.5});  // door at y = 1
  b.AddWall({20, -1.5}, {20, 3.5}, Material::kPoster, {2.5});
  b.AddWall({-5, -1.5}, {0, -1.5}, Material::kPoster);
  b.AddWall({0, 3.5}, {-5, 3.5}, Material::kNoise);
  b.AddWall({-5, 3.5}, {-5, -1.5}, Material::kPlain);
  b.AddWall({20, -1.5}, {25, -1.5}, Material::kNoise);
  b.AddWall({25, -1.5}, {25, 3.5}, Material::kPoster);
  b.AddWall({25, 3.5}, {20, 3.5}, Material::kPlain);
  b.Furnish({-5, -1.5}, {0, 3.5}, &rng);
  b.Furnish({20, -1.5}, {25, 3.5}, &rng);
  const Vec2 y_axis(0, 1);
  b.Visit({-2.5, 1.0});
  b.ThroughDoor({0, 1}, y_axis, false);
  b.Visit({10.0, 1.0});
  b.ThroughDoor({20, 1}, y_axis, false);
  b.Visit({22.0, 0.0});
  b.Visit({23.5, 1.0});
  b.Visit({22.0, 2.0});
  b.ThroughDoor({20, 1}, y_axis, true);
  b.Visit({10.0, 1.0});
  b.ThroughDoor({0, 1}, y_axis, true);
  b.Visit({-2.5, 1.0});
  return b.Take();
}

}  // namespace

Eigen::Vector2d Room::Centre() const {
  Eigen::Vector2d c = Eigen::Vector2d::Zero();
  for (const auto& p : outline) c += p;
  return c / static_cast<double>(outline.size());
}

std::vector<std::string> SceneNames() { return {"two-rooms", "apartment", "corridor"}; }

Scene BuildScene(const std::string& name, uint64_t seed) {
  if (name == "two-rooms") return TwoRooms(seed);
  if (name == "apartment") return Apartment(seed);
  if (name == "corridor") return Corridor(seed);
  ThrowInputError("--scene", fmt::format("unknown scene '{}' (expected two-rooms, apartment or corridor)", name));
}

}  // namespace f2c::sim
