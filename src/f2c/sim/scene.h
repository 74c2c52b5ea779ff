#pragma once
// Synthetic interiors for ground-truth experiments: rooms joined by doors and corridors,
// furniture, procedural surface textures, as a triangle soup.
// World frame: metres, z up, floor at z = 0.

#include <Eigen/Core>
#include <Eigen/StdVector>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace f2c::sim {

enum class Material : uint8_t {
  kPlain,   // flat paint: textureless views exist in real scans
  kNoise,   // mottled plaster / concrete
  kTiles,   // floor or bathroom tiles
  kPoster,  // paint with posters and frames
  kWood,    // floor boards, furniture
};

struct Triangle {
  Eigen::Vector3d a, b, c;
  Eigen::Vector3d normal;  // unit; for walls, pointing into the room
  Material material = Material::kPlain;
  // id of the surface it belongs to: a planar one (wall, floor, box face), or one curved
  // object's side (a cylinder's mantle, a sphere)
  uint32_t surface = 0;
};

struct Room {
  std::string name;
  std::vector<Eigen::Vector2d> outline;  // floor polygon, counter-clockwise, metres
  Eigen::Vector2d Centre() const;
};

// An object scan's route: the camera circles `target` (horizontally), looking at it, at a
// distance and height that drift slowly within the swings, as a person walks round a table.
struct Orbit {
  Eigen::Vector3d target = Eigen::Vector3d::Zero();  // what the camera looks at (metres)
  double radius = 1.25;                              // horizontal distance from the target (metres)
  double radius_swing = 0.25;                        // ... varying within +- this
  double height = 1.1;                               // camera height above the floor (metres)
  double height_swing = 0.2;
  double pace = 0.3;  // metres per second along the circle, at WalkOptions::speed 1
};

struct Scene {
  std::vector<Triangle> triangles;
  std::vector<Room> rooms;
  // Floor-plan points (metres) the camera's route passes through: it leaves and re-enters
  // rooms through their doors, so loops close.
  std::vector<Eigen::Vector2d> waypoints;
  // Set for object scenes: the camera circles it instead of walking the waypoints.
  std::optional<Orbit> orbit;
  double ceiling_height = 2.6;
};

// Named scenes: "two-rooms", "apartment" (four rooms and a corridor, one trapezoid room),
// "apartment-square" (the same, its living room 6 deg off square), "corridor" (a long
// corridor with rooms off it), "object" (a table of curved and cluttered objects in the
// middle of a large room, circled at 1-1.5 m). InputError for another name. `seed` varies
// furniture, objects and posters.
Scene BuildScene(const std::string& name, uint64_t seed);
std::vector<std::string> SceneNames();

}  // namespace f2c::sim
