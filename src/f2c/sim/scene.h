#pragma once
// Synthetic interiors for ground-truth experiments: rooms joined by doors and corridors,
// furniture, procedural surface textures, as a triangle soup.
// World frame: metres, z up, floor at z = 0.

#include <Eigen/Core>
#include <Eigen/StdVector>
#include <cstdint>
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
  Eigen::Vector3d normal;   // unit; for walls, pointing into the room
  Material material = Material::kPlain;
  uint32_t surface = 0;     // id of the planar surface (wall, floor, box face) it belongs to
};

struct Room {
  std::string name;
  std::vector<Eigen::Vector2d> outline;  // floor polygon, counter-clockwise, metres
  Eigen::Vector2d Centre() const;
};

struct Scene {
  std::vector<Triangle> triangles;
  std::vector<Room> rooms;
  // Floor-plan points (metres) the camera's route passes through: it leaves and re-enters
  // rooms through their doors, so loops close.
  std::vector<Eigen::Vector2d> waypoints;
  double ceiling_height = 2.6;
};

// Named scenes: "two-rooms", "apartment" (four rooms and a corridor, one trapezoid room),
// "corridor" (a long corridor with rooms off it). InputError for another name. `seed`
// varies furniture and posters.
Scene BuildScene(const std::string& name, uint64_t seed);
std::vector<std::string> SceneNames();

}  // namespace f2c::sim
