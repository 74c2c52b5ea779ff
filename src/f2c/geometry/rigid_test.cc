#include "f2c/geometry/rigid.h"

#include <gtest/gtest.h>

#include <cmath>

#include "f2c/util/error.h"

namespace f2c {
namespace {

TEST(RotationAngle, KnownAngle) {
  const Eigen::Matrix3d r = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  EXPECT_NEAR(RotationAngle(r), 0.3, 1e-12);
  EXPECT_NEAR(RotationAngle(Eigen::Matrix3d::Identity()), 0.0, 1e-12);
}

TEST(RigidFromMatrixOrThrow, AcceptsRoundedRotationAndOrthonormalisesIt) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() = Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  m.topLeftCorner<3, 3>() = (m.topLeftCorner<3, 3>() * 1e4).array().round() / 1e4;  // 4 digits
  const Rigid3d t = RigidFromMatrixOrThrow(m, "p.txt", 0);
  EXPECT_NEAR((t.linear().transpose() * t.linear() - Eigen::Matrix3d::Identity()).norm(), 0, 1e-12);
  EXPECT_NEAR(RotationAngle(t.linear()), 0.7, 1e-4);
}

TEST(RigidFromMatrixOrThrow, RejectsScaledRotation) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m(0, 0) = 1.2;
  try {
    RigidFromMatrixOrThrow(m, "frame-000010.pose.txt", 0);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "frame-000010.pose.txt: pose is not rigid (max |R^T R - I| = 0.44, det R = 1.2)");
  }
}

TEST(RigidFromMatrixOrThrow, RejectsNaN) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m(1, 3) = std::nan("");
  try {
    RigidFromMatrixOrThrow(m, "traj.log", 12);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "traj.log:12: pose is not finite (NaN or infinity)");
  }
}

// Finite is not enough: at 1e155 m the metrics' squares overflow (ATE "inf"), and beyond
// 1e6 m a double keeps less precision than they need.
TEST(RigidFromMatrixOrThrow, RejectsPositionsFartherThanAMillionMetres) {
  auto message = [](const auto& f) {
    try {
      f();
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m(0, 3) = 1e155;
  EXPECT_EQ(message([&] { RigidFromMatrixOrThrow(m, "traj.log", 7); }),
            "traj.log:7: pose lies 1e+155 m from the origin (at most 1e+06 m)");
  m(0, 3) = 9.9e5;
  EXPECT_EQ(RigidFromMatrixOrThrow(m, "traj.log", 7).translation().x(), 9.9e5);
  EXPECT_EQ(message([&] {
              RigidFromQuaternionOrThrow({0, 2e6, 0}, {0, 0, 0, 1}, "gt.txt", 3);
            }),
            "gt.txt:3: pose lies 2e+06 m from the origin (at most 1e+06 m)");
}

TEST(RigidFromQuaternionOrThrow, RejectsNonUnitQuaternion) {
  try {
    RigidFromQuaternionOrThrow({0, 0, 0}, {0, 0, 0, 2}, "groundtruth.txt", 4);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "groundtruth.txt:4: quaternion is not unit (norm 2)");
  }
}

}  // namespace
}  // namespace f2c
