#include "f2c/sim/scene.h"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include <random>

#include "f2c/util/error.h"

namespace f2c::sim {
namespace {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;

constexpr double kDoorWidth = 1.0;
constexpr double kDoorHeight = 2.05;
constexpr double kPartition = 0.1;  // thickness of walls with doors (metres)

class SceneBuilder {
 public:
  explicit SceneBuilder(double height) { scene_.ceiling_height = height; }

  // A planar quad a-b-c-d (two triangles); its normal follows the right-hand rule.
  void AddQuad(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, Material m, uint32_t surface) {
    const Vec3 n = (b - a).cross(d - a).normalized();
    scene_.triangles.push_back({a, b, c, n, m, surface});
    scene_.triangles.push_back({a, c, d, n, m, surface});
  }

  // A wall from p0 to p1 with door openings centred at the given distances along it. A wall
  // with doors is a partition of `kPartition` metres: two faces, and reveals (jambs and
  // soffit) in each opening, which are the short perpendicular planes a camera sees when it
  // walks through a door. Walls without doors are one face on the line (the inside of the
  // building's shell).
  void AddWall(const Vec2& p0, const Vec2& p1, Material m, std::vector<double> doors = {}) {
    const double length = (p1 - p0).norm();
    const Vec2 dir = (p1 - p0) / length;
    const Vec2 left(-dir.y(), dir.x());
    const double h = scene_.ceiling_height;
    std::sort(doors.begin(), doors.end());
    // One face, offset `shift` along `left`; its quads face `left` if `faces_left`.
    auto face = [&](double shift, bool faces_left) {
      const uint32_t surface = next_surface_++;
      auto at = [&](double s, double z) {
        const Vec2 p = p0 + s * dir + shift * left;
        return Vec3(p.x(), p.y(), z);
      };
      auto quad = [&](double s0, double z0, double s1, double z1) {
        if (faces_left) {
          AddQuad(at(s1, z0), at(s0, z0), at(s0, z1), at(s1, z1), m, surface);
        } else {
          AddQuad(at(s0, z0), at(s1, z0), at(s1, z1), at(s0, z1), m, surface);
        }
      };
      double s = 0;
      for (double centre : doors) {
        const double d0 = centre - kDoorWidth / 2, d1 = centre + kDoorWidth / 2;
        if (d0 > s) quad(s, 0, d0, h);
        quad(d0, kDoorHeight, d1, h);  // lintel
        s = d1;
      }
      if (s < length) quad(s, 0, length, h);
    };
    if (doors.empty()) {
      face(0, true);
      return;
    }
    face(kPartition / 2, true);
    face(-kPartition / 2, false);
    for (double centre : doors) {
      auto at = [&](double s, double offset, double z) {
        const Vec2 p = p0 + s * dir + offset * left;
        return Vec3(p.x(), p.y(), z);
      };
      const double d0 = centre - kDoorWidth / 2, d1 = centre + kDoorWidth / 2, t = kPartition / 2;
      AddQuad(at(d0, -t, 0), at(d0, t, 0), at(d0, t, kDoorHeight), at(d0, -t, kDoorHeight), m, next_surface_++);
      AddQuad(at(d1, t, 0), at(d1, -t, 0), at(d1, -t, kDoorHeight), at(d1, t, kDoorHeight), m, next_surface_++);
      AddQuad(at(d0, -t, kDoorHeight), at(d0, t, kDoorHeight), at(d1, t, kDoorHeight), at(d1, -t, kDoorHeight), m,
              next_surface_++);
    }
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

  // An axis-aligned box from z0 to z1; no bottom face when it stands on the floor.
  void AddBox(const Vec2& min, const Vec2& max, double z0, double z1, Material m) {
    const Vec3 p[8] = {{min.x(), min.y(), z0}, {max.x(), min.y(), z0}, {max.x(), max.y(), z0}, {min.x(), max.y(), z0},
                       {min.x(), min.y(), z1}, {max.x(), min.y(), z1}, {max.x(), max.y(), z1}, {min.x(), max.y(), z1}};
    AddQuad(p[0], p[1], p[5], p[4], m, next_surface_++);
    AddQuad(p[1], p[2], p[6], p[5], m, next_surface_++);
    AddQuad(p[2], p[3], p[7], p[6], m, next_surface_++);
    AddQuad(p[3], p[0], p[4], p[7], m, next_surface_++);
    AddQuad(p[4], p[5], p[6], p[7], m, next_surface_++);
    if (z0 > 0) AddQuad(p[0], p[3], p[2], p[1], m, next_surface_++);
  }

  // A triangle whose normal points away from `inside` (a point within the object).
  void AddFacet(const Vec3& a, Vec3 b, Vec3 c, const Vec3& inside, Material m, uint32_t surface) {
    Vec3 n = (b - a).cross(c - a);
    if (n.norm() < 1e-12) return;
    n.normalize();
    if (n.dot((a + b + c) / 3.0 - inside) < 0) {
      std::swap(b, c);
      n = -n;
    }
    scene_.triangles.push_back({a, b, c, n, m, surface});
  }

  // A box of `size` (x, y, z) standing at `base` (its bottom face's centre), turned by `yaw`
  // about the vertical; no bottom face when it stands on z = 0.
  void AddTurnedBox(const Vec3& base, const Vec3& size, double yaw, Material m) {
    const Eigen::Matrix3d r = Eigen::AngleAxisd(yaw, Vec3::UnitZ()).toRotationMatrix();
    Vec3 p[8];
    for (int i = 0; i < 8; ++i) {
      const Vec3 corner((i & 1 ? 0.5 : -0.5) * size.x(), (i & 2 ? 0.5 : -0.5) * size.y(), i & 4 ? size.z() : 0.0);
      p[i] = base + r * corner;
    }
    const Vec3 inside = base + Vec3(0, 0, size.z() / 2);
    const int faces[6][4] = {{0, 1, 5, 4}, {1, 3, 7, 5}, {3, 2, 6, 7}, {2, 0, 4, 6}, {4, 5, 7, 6}, {0, 2, 3, 1}};
    for (int f = 0; f < 6; ++f) {
      if (f == 5 && base.z() <= 0) continue;
      const uint32_t surface = next_surface_++;
      AddFacet(p[faces[f][0]], p[faces[f][1]], p[faces[f][2]], inside, m, surface);
      AddFacet(p[faces[f][0]], p[faces[f][2]], p[faces[f][3]], inside, m, surface);
    }
  }

  // A vertical cylinder (`segments` facets round), closed on top, and below when it does
  // not stand on the floor.
  void AddCylinder(const Vec3& base, double radius, double height, Material m, int segments = 32) {
    const uint32_t side = next_surface_++, top = next_surface_++, bottom = next_surface_++;
    const Vec3 inside = base + Vec3(0, 0, height / 2), up(0, 0, height);
    for (int i = 0; i < segments; ++i) {
      const double a0 = 2 * M_PI * i / segments, a1 = 2 * M_PI * (i + 1) / segments;
      const Vec3 p0 = base + radius * Vec3(std::cos(a0), std::sin(a0), 0);
      const Vec3 p1 = base + radius * Vec3(std::cos(a1), std::sin(a1), 0);
      AddFacet(p0, p1, p1 + up, inside, m, side);
      AddFacet(p0, p1 + up, p0 + up, inside, m, side);
      AddFacet(base + up, p0 + up, p1 + up, inside, m, top);
      if (base.z() > 0) AddFacet(base, p0, p1, inside, m, bottom);
    }
  }

  // A closed blob round `centre`: a sphere of `radius` whose surface rises and falls by up to
  // `bumps` of it (five smooth random lobes), so it stays within radius (1 +- bumps) of the
  // centre: an organic shape with no plane on it.
  void AddBlob(const Vec3& centre, double radius, double bumps, std::mt19937_64* rng, Material m) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    struct Lobe {
      Vec3 axis;
      double sharpness, height;
    };
    std::vector<Lobe> lobes;
    for (int i = 0; i < 5; ++i) {
      const double z = 2 * u(*rng) - 1, phi = 2 * M_PI * u(*rng);
      lobes.push_back({Vec3(std::sqrt(1 - z * z) * std::cos(phi), std::sqrt(1 - z * z) * std::sin(phi), z),
                       2.0 + 4.0 * u(*rng), (u(*rng) < 0.5 ? -1.0 : 1.0) * (0.4 + 0.6 * u(*rng))});
    }
    auto point = [&](double theta, double phi) {
      const Vec3 d(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
      double s = 0;
      for (const Lobe& l : lobes) s += l.height * std::exp(l.sharpness * (d.dot(l.axis) - 1));
      return Vec3(centre + radius * (1 + bumps * std::clamp(s, -1.0, 1.0)) * d);
    };
    const uint32_t surface = next_surface_++;
    constexpr int kRings = 24, kSegments = 48;
    for (int i = 0; i < kRings; ++i) {
      const double t0 = M_PI * i / kRings, t1 = M_PI * (i + 1) / kRings;
      for (int j = 0; j < kSegments; ++j) {
        const double p0 = 2 * M_PI * j / kSegments, p1 = 2 * M_PI * (j + 1) / kSegments;
        const Vec3 a = point(t0, p0), b = point(t0, p1), c = point(t1, p1), d = point(t1, p0);
        if (i > 0) AddFacet(a, b, c, centre, m, surface);
        if (i + 1 < kRings) AddFacet(a, c, d, centre, m, surface);
      }
    }
  }

  // A table: a slab top on four square legs.
  void AddTable(const Vec2& min, const Vec2& max, double height, Material m) {
    constexpr double kTop = 0.04, kLeg = 0.05;
    AddBox(min, max, height - kTop, height, m);
    const Vec2 leg(kLeg, kLeg);
    const Vec2 corners[4] = {min, {max.x() - kLeg, min.y()}, max - leg, {min.x(), max.y() - kLeg}};
    for (const Vec2& c : corners) AddBox(c, c + leg, 0, height - kTop, m);
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
        const double y = side == 0 ? min.y() + 0.08 : max.y() - 0.08 - d;
        lo = {x, y};
        hi = {x + w, y + d};
      } else {  // west / east wall
        const double y = min.y() + along * (max.y() - min.y() - w);
        const double x = side == 2 ? min.x() + 0.08 : max.x() - 0.08 - d;
        lo = {x, y};
        hi = {x + d, y + w};
      }
      // A cabinet (box), a table (slab on legs) or a wall shelf (a slab at eye height).
      const double kind = u(*rng);
      const Material m = u(*rng) < 0.6 ? Material::kWood : Material::kNoise;
      if (kind < 0.45) {
        AddBox(lo, hi, 0, h, m);
      } else if (kind < 0.8) {
        AddTable(lo, hi, 0.72 + 0.06 * u(*rng), m);
      } else {
        // Shelves hug the wall: 0.25 m deep, 3 cm thick.
        const double z = 1.1 + 0.5 * u(*rng);
        Vec2 slo = lo, shi = hi;
        if (side == 0) shi.y() = slo.y() + 0.25;
        if (side == 1) slo.y() = shi.y() - 0.25;
        if (side == 2) shi.x() = slo.x() + 0.25;
        if (side == 3) slo.x() = shi.x() - 0.25;
        AddBox(slo, shi, z, z + 0.03, m);
      }
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
  void CircleAround(const Orbit& orbit) { scene_.orbit = orbit; }

  Scene Take() { return std::move(scene_); }

 private:
  Scene scene_;
  uint32_t next_surface_ = 0;
};

std::vector<Vec2> Rect(double x0, double y0, double x1, double y1) { return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}; }

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

// `skew`: how far the living room's side walls lean in over its 4 m depth (metres): 1.0
// makes a trapezoid whose side walls are 14 deg off square; 0.42, 6 deg ("nearly square",
// the case structural relations are most tempted to square up).
Scene Apartment(uint64_t seed, double skew = 1.0) {
  std::mt19937_64 rng(seed);
  SceneBuilder b(2.6);
  b.AddRoom("corridor", Rect(0, 4, 12, 6), Material::kTiles);
  b.AddRoom("kitchen", Rect(0, 0, 4, 4), Material::kTiles);
  b.AddRoom("bedroom", Rect(4, 0, 8, 4), Material::kWood);
  b.AddRoom("office", Rect(8, 0, 12, 4), Material::kWood);
  b.AddRoom("living", {{2, 6}, {10, 6}, {10 - skew, 10}, {2 + skew, 10}}, Material::kWood);  // trapezoid
  b.AddWall({0, 0}, {12, 0}, Material::kNoise);
  b.AddWall({12, 0}, {12, 6}, Material::kPoster);
  b.AddWall({0, 6}, {0, 0}, Material::kPoster);
  b.AddWall({4, 0}, {4, 4}, Material::kNoise);
  b.AddWall({8, 0}, {8, 4}, Material::kNoise);
  b.AddWall({0, 4}, {12, 4}, Material::kNoise, {2.0, 6.0, 10.0});
  b.AddWall({12, 6}, {10, 6}, Material::kPlain);
  b.AddWall({10, 6}, {2, 6}, Material::kPoster, {4.0});  // door at x = 6
  b.AddWall({2, 6}, {0, 6}, Material::kPlain);
  b.AddWall({10, 6}, {10 - skew, 10}, Material::kNoise);
  b.AddWall({10 - skew, 10}, {2 + skew, 10}, Material::kPoster);
  b.AddWall({2 + skew, 10}, {2, 6}, Material::kNoise);
  b.Furnish({0, 0}, {4, 4}, &rng);
  b.Furnish({4, 0}, {8, 4}, &rng);
  b.Furnish({8, 0}, {12, 4}, &rng);
  const Vec2 x_axis(1, 0);
  // Kitchen -> bedroom -> kitchen first, so the first loop closes within 30 s (the demo's
  // length); then the office, the living room and back to the kitchen.
  b.Visit({1.3, 2.2});  // kitchen
  b.Visit({2.6, 1.4});
  b.ThroughDoor({2, 4}, x_axis, true);
  b.Visit({4.0, 5.0});
  b.ThroughDoor({6, 4}, x_axis, false);
  b.Visit({5.2, 1.6});  // bedroom: a loop around its centre, not a dead end
  b.Visit({6.8, 1.6});
  b.ThroughDoor({6, 4}, x_axis, true);
  b.Visit({4.0, 5.0});
  b.ThroughDoor({2, 4}, x_axis, false);
  b.Visit({2.6, 1.4});  // back in the kitchen: the first loop closes
  b.Visit({1.3, 2.2});
  b.Visit({2.2, 2.6});
  b.ThroughDoor({2, 4}, x_axis, true);
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
  b.Visit({2.6, 1.4});  // the kitchen again
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

// An object scan: a low table of objects with no plane on them (a bumpy blob, a ball, a
// bottle) and a few boxes and cylinders, more clutter on the floor beside it, in the middle of
// a 13 m square room whose walls are beyond the depth sensor's reach (5-7 m away). The
// camera circles the table at 1-1.5 m, 0.9-1.3 m high, looking at its objects.
Scene ObjectScene(uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  SceneBuilder b(2.8);
  constexpr double kSide = 13;
  b.AddRoom("hall", Rect(0, 0, kSide, kSide), Material::kWood);
  b.AddWall({0, 0}, {kSide, 0}, Material::kPoster);
  b.AddWall({kSide, 0}, {kSide, kSide}, Material::kNoise);
  b.AddWall({kSide, kSide}, {0, kSide}, Material::kPoster);
  b.AddWall({0, kSide}, {0, 0}, Material::kPlain);
  const Vec2 c(kSide / 2, kSide / 2);
  constexpr double kTable = 0.45;
  b.AddTable(c - Vec2(0.45, 0.35), c + Vec2(0.45, 0.35), kTable, Material::kWood);
  const Vec3 top(c.x(), c.y(), kTable);
  auto jitter = [&](double r) { return Vec3(r * (2 * u(rng) - 1), r * (2 * u(rng) - 1), 0); };
  b.AddBlob(top + Vec3(-0.12, 0.05, 0.13) + jitter(0.04), 0.15, 0.3, &rng, Material::kNoise);
  b.AddBlob(top + Vec3(0.22, -0.15, 0.08) + jitter(0.03), 0.08, 0.05, &rng, Material::kNoise);  // a ball
  b.AddCylinder(top + Vec3(0.25, 0.15, 0) + jitter(0.03), 0.04 + 0.02 * u(rng), 0.22 + 0.1 * u(rng), Material::kNoise);
  b.AddTurnedBox(top + Vec3(-0.3, -0.2, 0) + jitter(0.03), Vec3(0.16, 0.1, 0.12 + 0.1 * u(rng)), 2 * M_PI * u(rng),
                 Material::kNoise);
  b.AddTurnedBox(top + Vec3(0.05, -0.22, 0) + jitter(0.02), Vec3(0.12, 0.12, 0.06), 2 * M_PI * u(rng), Material::kWood);
  // On the floor beside the table: a bin, a carton, a stool (a cylinder on a cylinder).
  b.AddCylinder(Vec3(c.x() + 0.7, c.y() - 0.35, 0) + jitter(0.05), 0.15, 0.4, Material::kNoise);
  b.AddTurnedBox(Vec3(c.x() - 0.75, c.y() + 0.3, 0) + jitter(0.05), Vec3(0.4, 0.3, 0.3), 2 * M_PI * u(rng),
                 Material::kNoise);
  const Vec3 stool = Vec3(c.x() + 0.1, c.y() + 0.65, 0) + jitter(0.05);
  b.AddCylinder(stool, 0.03, 0.4, Material::kWood, 12);
  b.AddCylinder(stool + Vec3(0, 0, 0.4), 0.16, 0.04, Material::kWood);
  b.AddBlob(stool + Vec3(0, 0, 0.44 + 0.07), 0.09, 0.25, &rng, Material::kNoise);
  Orbit orbit;
  orbit.target = Vec3(c.x(), c.y(), kTable + 0.1);
  b.CircleAround(orbit);
  return b.Take();
}

}  // namespace

Eigen::Vector2d Room::Centre() const {
  Eigen::Vector2d c = Eigen::Vector2d::Zero();
  for (const auto& p : outline) c += p;
  return c / static_cast<double>(outline.size());
}

std::vector<std::string> SceneNames() { return {"two-rooms", "apartment", "apartment-square", "corridor", "object"}; }

Scene BuildScene(const std::string& name, uint64_t seed) {
  if (name == "two-rooms") return TwoRooms(seed);
  if (name == "apartment") return Apartment(seed);
  if (name == "apartment-square") return Apartment(seed, 4 * std::tan(6 * M_PI / 180));
  if (name == "corridor") return Corridor(seed);
  if (name == "object") return ObjectScene(seed);
  ThrowInputError(
      "--scene",
      fmt::format("unknown scene '{}' (expected two-rooms, apartment, apartment-square, corridor or object)", name));
}

}  // namespace f2c::sim
