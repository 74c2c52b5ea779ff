// A TUM-layout folder written as a ROS 2 bag (testing/ros2_writer: rgb8 colour, 32FC1 depth,
// CameraInfo), for bench/recording_bench.sh.
//   ./build/bench/write_ros2 FOLDER OUT_DIR db3|mcap [none|zstd|lz4] fx,fy,cx,cy

#include <cstdio>
#include <string>

#include "f2c/io/image.h"
#include "f2c/io/sequence.h"
#include "f2c/testing/ros2_writer.h"
#include "f2c/util/error.h"

int main(int argc, char** argv) {
  using namespace f2c;
  if (argc < 6) {
    std::fprintf(stderr, "usage: write_ros2 FOLDER OUT_DIR db3|mcap none|zstd|lz4 fx,fy,cx,cy\n");
    return 2;
  }
  try {
    IoOptions io;
    io.intrinsics = argv[5];
    const RgbdSequence seq = ReadSequence(argv[1], io);  // the image size from its first depth image
    testing::Ros2BagOptions o;
    o.storage = argv[3];
    o.compression = std::string(argv[4]) == "none" ? "" : argv[4];
    o.intrinsics = *seq.intrinsics;
    testing::WriteRos2Bag(argv[1], argv[2], o);
  } catch (const InputError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
