#pragma once
// Rigid transforms. Names follow b_from_a: `world_from_camera * point_in_camera` is the
// point in world coordinates.

#include <Eigen/Geometry>
#include <filesystem>
#include <string>

namespace f2c {

using Rigid3d = Eigen::Isometry3d;

// Angle of a rotation (radians, in [0, pi]).
double RotationAngle(const Eigen::Matrix3d& rotation);

// The pose a fraction u of the way from a to b: translation linearly, rotation along the
// shorter arc (slerp).
Rigid3d InterpolatePose(const Rigid3d& a, const Rigid3d& b, double u);

// The farthest a camera or a surface point may lie from the origin (metres). A building's
// scan spans hundreds of metres; beyond 1e6 m a double keeps less than the 1e-10 m the
// metrics' sums of squares need, and at 1e155 m they overflow to infinity: such a file is an
// error, not a result of "inf".
constexpr double kMaxCoordinateMetres = 1e6;

// Checks that a 4x4 matrix read from `path` (at `line`, 0 if none) is a rigid transform:
// finite, within kMaxCoordinateMetres of the origin, bottom row (0 0 0 1), rotation
// orthonormal within `tolerance` with det +1.
// Returns it with the rotation projected exactly onto SO(3) (files hold a few digits).
Rigid3d RigidFromMatrixOrThrow(const Eigen::Matrix4d& matrix, const std::filesystem::path& path, int line,
                               double tolerance = 1e-3);

// Builds a rigid transform from a translation and a quaternion (x, y, z, w) read from a
// file; the translation within kMaxCoordinateMetres, the quaternion of unit norm within
// `tolerance` (then normalised).
Rigid3d RigidFromQuaternionOrThrow(const Eigen::Vector3d& translation, const Eigen::Vector4d& quaternion_xyzw,
                                   const std::filesystem::path& path, int line, double tolerance = 1e-2);

}  // namespace f2c
