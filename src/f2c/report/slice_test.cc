#include "f2c/report/slice.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

namespace f2c {
namespace {

// A 4 x 3 m room, 2.5 m tall (floor z = 0), with a table top at 0.75 m; walls are x = +-2 and
// y = +-1.5. Each frame's camera stands at 1.5 m, upright (its -y along +z), turned towards
// a different wall, and sees points of every surface.
struct Room {
  std::vector<SliceFrame> frames;
  std::vector<std::optional<Rigid3d>> truth;
};

Room MakeRoom(int frames) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  Room room;
  for (int k = 0; k < frames; ++k) {
    const double yaw = 2 * M_PI * k / frames;
    Rigid3d world_from_camera = Rigid3d::Identity();
    // Camera axes: z (view) horizontal at `yaw`, y pointing down.
    const Eigen::Vector3d z(std::cos(yaw), std::sin(yaw), 0), y(0, 0, -1);
    Eigen::Matrix3d r;
    r.col(2) = z, r.col(1) = y, r.col(0) = y.cross(z);
    world_from_camera.linear() = r;
    world_from_camera.translation() = Eigen::Vector3d(0.5 * std::cos(yaw + 1), 0.4 * std::sin(yaw + 1), 1.5);
    SliceFrame f;
    const Rigid3d camera_from_world = world_from_camera.inverse();
    auto add = [&](const Eigen::Vector3d& p, const Eigen::Vector3d& n) {
      f.points.push_back((camera_from_world * p).cast<float>());
      f.normals.push_back((camera_from_world.linear() * n).cast<float>());
    };
    for (int i = 0; i < 600; ++i) {
      const double a = u(rng), b = u(rng);
      switch (i % 6) {
        case 0:
          add({-2 + 4 * a, -1.5 + 3 * b, 0}, {0, 0, 1});
          break;  // floor
        case 1:
          add({-2 + 4 * a, -1.5 + 3 * b, 2.5}, {0, 0, -1});
          break;  // ceiling
        case 2:
          add({-0.5 + a, -0.4 + 0.8 * b, 0.75}, {0, 0, 1});
          break;  // table top
        case 3:
          add({2, -1.5 + 3 * a, 2.5 * b}, {-1, 0, 0});
          break;  // walls
        case 4:
          add({-2, -1.5 + 3 * a, 2.5 * b}, {1, 0, 0});
          break;
        default:
          add({-2 + 4 * a, (b < 0.5 ? -1.5 : 1.5), 1.0 + u(rng)}, {0, b < 0.5 ? 1.0 : -1.0, 0});
          break;  // walls, 1-2 m
      }
    }
    room.frames.push_back(std::move(f));
    room.truth.push_back(world_from_camera);
  }
  return room;
}

double DistanceToWalls(const Eigen::Vector3d& p) {
  return std::min(std::abs(std::abs(p.x()) - 2), std::abs(std::abs(p.y()) - 1.5));
}

TEST(Slice, CutsThroughTheWallsWhereMostAreSeen) {
  const Room room = MakeRoom(24);
  const SliceBand band = ChooseSliceBand(room.frames, room.truth, {});
  EXPECT_LT(std::acos(std::min(1.0, band.up.dot(Eigen::Vector3d::UnitZ()))), 1e-6);
  // The y = +-1.5 walls are seen only from 1 to 2 m, so the layer with the most wall points is there.
  EXPECT_GT(band.height, 1.0);
  EXPECT_LT(band.height, 2.0);
  const std::vector<Eigen::Vector3d> slice = SlicePoints(room.frames, room.truth, band);
  ASSERT_GT(slice.size(), 200u);
  for (const Eigen::Vector3d& p : slice) {
    EXPECT_LE(std::abs(p.z() - band.height), 0.1 + 1e-9);
    EXPECT_LT(DistanceToWalls(p), 1e-5);  // no floor, ceiling or table
  }
}

TEST(Slice, DriftDrawsTheWallsTwice) {
  const Room room = MakeRoom(24);
  // Each frame turned by 0.5 degrees more than the last about the room's vertical axis.
  std::vector<std::optional<Rigid3d>> drifted = room.truth;
  for (size_t k = 0; k < drifted.size(); ++k) {
    drifted[k] = Rigid3d(Eigen::AngleAxisd(0.5 * M_PI / 180 * k, Eigen::Vector3d::UnitZ())) * *drifted[k];
  }
  const SliceBand band = ChooseSliceBand(room.frames, room.truth, {});
  double worst = 0;
  for (const Eigen::Vector3d& p : SlicePoints(room.frames, drifted, band)) worst = std::max(worst, DistanceToWalls(p));
  EXPECT_GT(worst, 0.15);  // 11.5 degrees at 2 m from the centre
  // A frame without a pose is left out.
  std::vector<std::optional<Rigid3d>> some = room.truth;
  some[0].reset();
  EXPECT_LT(SlicePoints(room.frames, some, band).size(), SlicePoints(room.frames, room.truth, band).size());
}

TEST(Slice, OptionsAreChecked) {
  SliceOptions o;
  o.thickness = 0;
  EXPECT_THROW(o.Check(), std::exception);
  o = {};
  o.wall_max_cos = 1;
  EXPECT_THROW(o.Check(), std::exception);
}

}  // namespace
}  // namespace f2c
