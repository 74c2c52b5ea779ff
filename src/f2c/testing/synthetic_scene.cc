#include "f2c/io/image_write.h"
#include "f2c/testing/synthetic_scene.h"

#include <unistd.h>

#include <cstdlib>

#include <cmath>
#include <limits>

namespace f2c::testing {
namespace {

uint32_t Hash(int64_t x, int64_t y, int64_t z) {
  uint64_t h = static_cast<uint64_t>(x) * 0x9E3779B97F4A7C15ULL ^ static_cast<uint64_t>(y) * 0xC2B2AE3D27D4EB4FULL ^
               static_cast<uint64_t>(z) * 0x165667B19E3779F9ULL;
  h ^= h >> 29;
  h *= 0xBF58476D1CE4E5B9ULL;
  h ^= h >> 32;
  return static_cast<uint32_t>(h);
}

// Blocks of random grey at two scales, so corners exist at any viewing distance.
cv::Vec3b Texture(const Eigen::Vector3d& p) {
  auto cell = [&](double size) {
    return Hash(static_cast<int64_t>(std::floor(p.x() / size)), static_cast<int64_t>(std::floor(p.y() / size)),
                static_cast<int64_t>(std::floor(p.z() / size)));
  };
  const uint32_t a = cell(0.2), b = cell(0.05);
  const int v = static_cast<int>((a & 0xff) * 0.6 + (b & 0xff) * 0.4);
  return {static_cast<uint8_t>(v), static_cast<uint8_t>((v + (a >> 8 & 0x3f)) & 0xff), static_cast<uint8_t>(255 - v)};
}

// Ray-box slab test: entry and exit distances along the ray.
bool Slab(const Box& box, const Eigen::Vector3d& o, const Eigen::Vector3d& d, double* t_in, double* t_out) {
  double lo = -std::numeric_limits<double>::infinity(), hi = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 3; ++i) {
    if (std::abs(d[i]) < 1e-12) {
      if (o[i] < box.min[i] || o[i] > box.max[i]) return false;
      continue;
    }
    double a = (box.min[i] - o[i]) / d[i], b = (box.max[i] - o[i]) / d[i];
    if (a > b) std::swap(a, b);
    lo = std::max(lo, a);
    hi = std::min(hi, b);
  }
  *t_in = lo;
  *t_out = hi;
  return lo <= hi;
}

}  // namespace

RenderedFrame Render(const SyntheticScene& scene, const CameraIntrinsics& k, const Rigid3d& world_from_camera) {
  RenderedFrame frame;
  frame.color.create(k.height, k.width, CV_8UC3);
  frame.depth.create(k.height, k.width, CV_32F);
  const Eigen::Vector3d origin = world_from_camera.translation();
  const Eigen::Matrix3d r = world_from_camera.linear();
  for (int v = 0; v < k.height; ++v) {
    for (int u = 0; u < k.width; ++u) {
      const Eigen::Vector3d ray_camera((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0);  // z = 1
      const Eigen::Vector3d d = r * ray_camera;
      double t_best = std::numeric_limits<double>::infinity(), t_in = 0, t_out = 0;
      if (Slab(scene.room, origin, d, &t_in, &t_out) && t_out > 0) t_best = t_out;
      for (const Box& box : scene.solids) {
        if (Slab(box, origin, d, &t_in, &t_out) && t_in > 1e-6 && t_in < t_best) t_best = t_in;
      }
      if (!std::isfinite(t_best)) {
        frame.depth.at<float>(v, u) = 0;
        frame.color.at<cv::Vec3b>(v, u) = {0, 0, 0};
        continue;
      }
      frame.depth.at<float>(v, u) = static_cast<float>(t_best);  // ray z = 1, so t is depth
      const Eigen::Vector3d p = origin + t_best * d;
      frame.color.at<cv::Vec3b>(v, u) = scene.textured ? Texture(p) : cv::Vec3b(128, 128, 128);
    }
  }
  return frame;
}

}  // namespace f2c::testing

#include <fmt/format.h>

#include "f2c/util/error.h"
#include "f2c/util/file.h"

namespace f2c::testing {

Trajectory WriteTumSequence(const std::filesystem::path& dir, const SyntheticScene& scene, const CameraIntrinsics& k,
                            const std::vector<Rigid3d, Eigen::aligned_allocator<Rigid3d>>& poses) {
  std::filesystem::create_directories(dir / "rgb");
  std::filesystem::create_directories(dir / "depth");
  std::string rgb_txt = "# color images\n", depth_txt = "# depth maps\n";
  Trajectory gt;
  for (size_t i = 0; i < poses.size(); ++i) {
    const double t = 1000.0 + i / 30.0;
    const RenderedFrame frame = Render(scene, k, poses[i]);
    cv::Mat depth16;
    frame.depth.convertTo(depth16, CV_16U, 5000.0);
    const std::string name = fmt::format("{:.6f}", t);
    WritePngFile(dir / "rgb" / (name + ".png"), frame.color);
    WritePngFile(dir / "depth" / (name + ".png"), depth16);
    rgb_txt += fmt::format("{} rgb/{}.png\n", name, name);
    depth_txt += fmt::format("{:.6f} depth/{}.png\n", t + 0.001, name);
    gt.Add(t, poses[i]);
  }
  WriteFileAtomic(dir / "rgb.txt", rgb_txt);
  WriteFileAtomic(dir / "depth.txt", depth_txt);
  WriteTumTrajectory(dir / "groundtruth.txt", gt);
  return gt;
}

std::string InputErrorMessage(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

namespace {

// The folders this process made, removed when it exits.
std::vector<std::filesystem::path>& MadeFolders() {
  static std::vector<std::filesystem::path> folders;
  return folders;
}

void RemoveMadeFolders() {
  std::error_code ignored;
  for (const auto& dir : MadeFolders()) std::filesystem::remove_all(dir, ignored);
}

}  // namespace

std::filesystem::path FreshTempDir(const std::string& name) {
  // Per process: two test runs at once (two checkouts, CI beside a developer's run) must not
  // delete each other's files.
  const auto dir =
      std::filesystem::temp_directory_path() / ("f2c_test_" + std::to_string(static_cast<long>(getpid())) + "_" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  if (MadeFolders().empty()) std::atexit(RemoveMadeFolders);
  MadeFolders().push_back(dir);
  return dir;
}

std::filesystem::path SharedTestDataDir() {
  namespace fs = std::filesystem;
  const fs::path exe = fs::read_symlink("/proc/self/exe");
  const auto stamp = fs::last_write_time(exe).time_since_epoch().count();
  const std::string prefix =
      "f2c_test_shared_" + exe.filename().string() + "_" + std::to_string(std::hash<std::string>()(exe.string())) + "_";
  const std::string name = prefix + std::to_string(fs::file_size(exe)) + "_" + std::to_string(stamp);
  const fs::path dir = fs::temp_directory_path() / name;
  if (!fs::exists(dir)) {
    std::error_code ec;
    for (const fs::directory_entry& e : fs::directory_iterator(fs::temp_directory_path(), ec)) {
      const std::string other = e.path().filename().string();
      if (other.rfind(prefix, 0) == 0 && other != name) fs::remove_all(e.path(), ec);
    }
    fs::create_directories(dir);
  }
  return dir;
}

namespace {

double BoxSurfaceDistance(const Box& box, const Eigen::Vector3d& p) {
  const Eigen::Vector3d outside = (box.min - p).cwiseMax(p - box.max).cwiseMax(0.0);
  if (outside.squaredNorm() > 0) return outside.norm();
  return std::min((p - box.min).minCoeff(), (box.max - p).minCoeff());
}

}  // namespace

cv::Mat PlaneDepth(const CameraIntrinsics& k, const Eigen::Vector3d& n, double d) {
  cv::Mat depth(k.height, k.width, CV_32F);
  for (int v = 0; v < k.height; ++v) {
    for (int u = 0; u < k.width; ++u) {
      const Eigen::Vector3d ray((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0);
      depth.at<float>(v, u) = static_cast<float>(d / n.dot(ray));
    }
  }
  return depth;
}

double SurfaceDistance(const SyntheticScene& scene, const Eigen::Vector3d& p) {
  double d = BoxSurfaceDistance(scene.room, p);
  for (const Box& solid : scene.solids) d = std::min(d, BoxSurfaceDistance(solid, p));
  return d;
}

}  // namespace f2c::testing
