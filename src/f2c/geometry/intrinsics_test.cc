#include "f2c/geometry/intrinsics.h"

#include <gtest/gtest.h>

#include <filesystem>

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

TEST(ParseIntrinsics, UnknownPreset) {
  try {
    ParseIntrinsics("kinect2", "--intrinsics");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(),
                 "--intrinsics: 'kinect2' is neither fx,fy,cx,cy nor a preset (primesense, "
                 "tum-fr1, tum-fr2, tum-fr3)");
  }
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
