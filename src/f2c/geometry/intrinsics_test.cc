#include "f2c/geometry/intrinsics.h"

#include <gtest/gtest.h>

#include <array>
#include <filesystem>
#include <limits>

#include "f2c/util/error.h"
#include "f2c/util/file.h"

namespace f2c {
namespace {

TEST(ParseIntrinsics, PresetAndNumbers) {
  const CameraIntrinsics fr1 = ParseIntrinsics("tum-fr1", "--intrinsics");
  EXPECT_DOUBLE_EQ(fr1.fx, 517.3);
  EXPECT_DOUBLE_EQ(fr1.cy, 255.3);
  const CameraIntrinsics k = ParseIntrinsics("500,501,320.5,240", "--intrinsics");
  EXPECT_DOUBLE_EQ(k.fy, 501);
  EXPECT_DOUBLE_EQ(k.cx, 320.5);
}

TEST(ParseIntrinsics, ZeroFocalLengthIsAnError) {
  try {
    ParseIntrinsics("0,525,320,240", "--intrinsics");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "--intrinsics: focal length must be positive (fx=0, fy=525)");
  }
}

// Finite but implausible values are unit mistakes, refused with the range they missed:
// fx = 1e-300 once ran to the end and found no planar region anywhere.
TEST(ParseIntrinsics, FocalLengthsAndPrincipalPointsOutsideAPlausibleRangeAreErrors) {
  auto message = [](const std::string& text) {
    try {
      ParseIntrinsics(text, "--intrinsics");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message("1e-300,525,320,240"),
            "--intrinsics: focal length must be in [10, 100000] pixels (fx=1e-300, fy=525)");
  EXPECT_EQ(message("525,1e308,320,240"),
            "--intrinsics: focal length must be in [10, 100000] pixels (fx=525, fy=1e+308)");
  EXPECT_EQ(message("525,525,1e300,240"), "--intrinsics: principal point (1e+300, 240) must be in [0, 100000) pixels");
  EXPECT_EQ(message("10,100000,0,99999"), "no error");
}

TEST(ParseIntrinsics, UnknownPreset) {
  try {
    ParseIntrinsics("kinect2", "--intrinsics");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(),
                 "--intrinsics: 'kinect2' is neither fx,fy,cx,cy[,k1,k2,p1,p2[,k3]] nor a preset (primesense, "
                 "tum-fr1, tum-fr2, tum-fr3)");
  }
}

TEST(ParseIntrinsics, Distortion) {
  // TUM's published calibrations (k1 k2 p1 p2 k3); fr3 was stored undistorted.
  const CameraIntrinsics fr1 = ParseIntrinsics("tum-fr1", "--intrinsics");
  EXPECT_EQ(fr1.distortion, (std::array<double, 5>{0.2624, -0.9531, -0.0054, 0.0026, 1.1633}));
  EXPECT_TRUE(fr1.HasDistortion());
  EXPECT_FALSE(ParseIntrinsics("tum-fr3", "--intrinsics").HasDistortion());
  EXPECT_FALSE(ParseIntrinsics("500,501,320.5,240", "--intrinsics").HasDistortion());
  const CameraIntrinsics eight = ParseIntrinsics("500,501,320,240,0.1,-0.2,0.003,0.004", "--intrinsics");
  EXPECT_EQ(eight.distortion, (std::array<double, 5>{0.1, -0.2, 0.003, 0.004, 0}));
  const CameraIntrinsics nine = ParseIntrinsics("500,501,320,240,0.1,-0.2,0.003,0.004,0.5", "--intrinsics");
  EXPECT_DOUBLE_EQ(nine.distortion[4], 0.5);
  try {
    ParseIntrinsics("500,501,320,240,0.1", "--intrinsics");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "--intrinsics: expected 4 numbers fx,fy,cx,cy, 8 with k1,k2,p1,p2 or 9 with k3, got 5");
  }
  CameraIntrinsics bad = nine;
  bad.distortion[1] = std::numeric_limits<double>::quiet_NaN();
  try {
    bad.Validate("calib.txt");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "calib.txt: distortion coefficient nan is not finite");
  }
}

TEST(CameraIntrinsics, DistortByHand) {
  CameraIntrinsics k{500, 400, 320, 240, 640, 480};
  EXPECT_EQ(k.Distort(123.5, 456.25), Eigen::Vector2d(123.5, 456.25));  // no distortion: identity
  // x = 0.2, y = -0.1: r^2 = 0.05.
  const double u = 320 + 500 * 0.2, v = 240 - 400 * 0.1;
  k.distortion = {0.1, 0, 0, 0, 0};  // radial 1 + 0.1 * 0.05 = 1.005
  EXPECT_NEAR(k.Distort(u, v).x(), 320 + 500 * 0.2 * 1.005, 1e-9);
  EXPECT_NEAR(k.Distort(u, v).y(), 240 - 400 * 0.1 * 1.005, 1e-9);
  k.distortion = {0, 2, 0, 0, 3};  // radial 1 + 2 * 0.0025 + 3 * 0.000125 = 1.005375
  EXPECT_NEAR(k.Distort(u, v).x(), 320 + 500 * 0.2 * 1.005375, 1e-9);
  k.distortion = {0, 0, 0.01, 0.02, 0};
  // Tangential: x' = x + 2 p1 x y + p2 (r^2 + 2 x^2) = 0.2 - 0.0004 + 0.0026 = 0.2022;
  //             y' = y + p1 (r^2 + 2 y^2) + 2 p2 x y = -0.1 + 0.0007 - 0.0008 = -0.1001.
  EXPECT_NEAR(k.Distort(u, v).x(), 320 + 500 * 0.2022, 1e-9);
  EXPECT_NEAR(k.Distort(u, v).y(), 240 - 400 * 0.1001, 1e-9);
}

TEST(CameraIntrinsics, ProjectInvertsUnproject) {
  const CameraIntrinsics k{500, 510, 320, 240, 640, 480};
  const Eigen::Vector3d p = k.Unproject(100.25, 400.5, 2.5);
  EXPECT_NEAR(p.z(), 2.5, 1e-12);
  EXPECT_NEAR(p.x(), (100.25 - 320) * 2.5 / 500, 1e-12);
  const Eigen::Vector2d uv = k.Project(p);
  EXPECT_NEAR(uv.x(), 100.25, 1e-9);
  EXPECT_NEAR(uv.y(), 400.5, 1e-9);
}

TEST(ReadIntrinsicsMatrixFile, ZeroFocalLengthNamesTheFile) {
  const auto path = std::filesystem::temp_directory_path() / "f2c_zero_focal.txt";
  WriteFileAtomic(path, "0 0 320\n0 585 240\n0 0 1\n");
  try {
    ReadIntrinsicsMatrixFile(path);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), path.string() + ": focal length must be positive (fx=0, fy=585)");
  }
}

TEST(ReadIntrinsicsMatrixFile, WrongCount) {
  const auto path = std::filesystem::temp_directory_path() / "f2c_short_k.txt";
  WriteFileAtomic(path, "585 0 320\n0 585 240\n");
  try {
    ReadIntrinsicsMatrixFile(path);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), path.string() + ": expected a 3x3 camera matrix (9 numbers), got 6");
  }
}

}  // namespace
}  // namespace f2c
