// A 60-frame walk through the test scene (testing::SyntheticScene) written as a .sens recording
// whose colour is another camera, for bench/align_bench.sh: configurations 0 and 1 (two walks)
// a RealSense-like colour camera (800x600, 2.5 cm and 1 degree from the depth camera), 2 and 3
// a ScanNet-like one (1296x968, 5 cm away).
//   ./build/bench/two_camera_sens OUT.sens CONFIG
#include "f2c/testing/sens_writer.h"
#include <cmath>
#include <string>
int main(int argc, char** argv) {
  if (argc < 3) return 2;
  using namespace f2c;
  const int config = std::stoi(argv[2]);
  std::vector<Rigid3d, Eigen::aligned_allocator<Rigid3d>> poses;
  for (int i = 0; i < 60; ++i) {
    Rigid3d pose = Rigid3d::Identity();
    const double a = config % 2 == 0 ? 0.01 * i : 0.3 * std::sin(i / 12.0);
    pose.linear() = Eigen::AngleAxisd(a, Eigen::Vector3d::UnitY()).toRotationMatrix() *
                    Eigen::AngleAxisd(0.05 * std::sin(i / 7.0), Eigen::Vector3d::UnitX()).toRotationMatrix();
    pose.translation() = Eigen::Vector3d(0.01 * i, 0.05 * std::sin(i / 9.0), -0.6 + 0.005 * i);
    poses.push_back(pose);
  }
  testing::SensOptions o;
  if (config < 2) {  // RealSense-like: a larger colour camera 2.5 cm away, turned 1 degree
    o.color = {600.0, 605.0, 405.0, 297.0, 800, 600};
    o.color_from_depth.linear() = Eigen::AngleAxisd(M_PI / 180, Eigen::Vector3d::UnitY()).toRotationMatrix();
    o.color_from_depth.translation() = Eigen::Vector3d(-0.025, 0.002, 0.001);
  } else {  // ScanNet-like: 1296x968 colour, 5 cm away
    o.color = {1170.0, 1170.0, 647.5, 483.5, 1296, 968};
    o.color_from_depth.translation() = Eigen::Vector3d(-0.05, 0, 0);
  }
  testing::WriteSyntheticSens(argv[1], testing::SyntheticScene(), poses, o);
}
