#include "tests/cli_helpers.h"

#include <sys/wait.h>

#include <array>
#include <cstdio>

#include "f2c/testing/synthetic_scene.h"

namespace f2c::cli_test {
namespace fs = std::filesystem;

Result RunCli(const std::string& args, const std::string& shell_tail) {
  const std::string command = std::string(F2C_CLI_PATH) + " " + args + shell_tail;
  FILE* pipe = popen(command.c_str(), "r");
  Result r;
  std::array<char, 4096> buffer;
  size_t n = 0;
  while ((n = fread(buffer.data(), 1, buffer.size(), pipe)) > 0) r.output.append(buffer.data(), n);
  const int status = pclose(pipe);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

uint32_t Crc32ForTest(const std::string& bytes) {
  uint32_t crc = 0xFFFFFFFFu;
  for (unsigned char b : bytes) {
    crc ^= b;
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
  }
  return ~crc;
}

fs::path Data(const std::string& name) { return fs::path(F2C_SHARED_DATA_DIR) / name; }

fs::path SyntheticTum(const std::string& name, int n) {
  const fs::path dir = testing::FreshTempDir(name);
  std::vector<Rigid3d, Eigen::aligned_allocator<Rigid3d>> poses;
  for (int i = 0; i < n; ++i) {
    Rigid3d pose = Rigid3d::Identity();
    pose.linear() = Eigen::AngleAxisd(0.02 * i, Eigen::Vector3d::UnitY()).toRotationMatrix();
    pose.translation() = Eigen::Vector3d(0.03 * i, 0, -0.6);
    poses.push_back(pose);
  }
  testing::WriteTumSequence(dir, testing::SyntheticScene(), testing::TestIntrinsics(), poses);
  return dir;
}

}  // namespace f2c::cli_test
