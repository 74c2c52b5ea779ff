// ScanNet / BundleFusion .sens recordings (version 4), read as ScanNet's own SensorData
// reader lays them out (all little-endian):
//
//   uint32 version (4); uint64 n, char[n] sensor name
//   float[16] colour intrinsics, colour extrinsics, depth intrinsics, depth extrinsics
//             (row-major 4x4; an extrinsic is its camera's pose in the rig's frame)
//   int32 colour compression (0 raw RGB, 1 PNG, 2 JPEG); int32 depth compression (0 raw
//   uint16, 1 zlib uint16, 2 occi)
//   uint32 colour width, height, depth width, height; float depth shift (units per metre)
//   uint64 frames; per frame: float[16] camera-to-world, uint64 colour and depth time
//   stamps (microseconds), uint64 colour bytes, uint64 depth bytes, then those bytes
//
// Only the headers are read here (a seek over each frame's images), so a recording of any
// size opens in memory proportional to its frames; the images are read when decoded.

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <tuple>

#include "f2c/io/readers.h"
#include "f2c/util/error.h"

namespace f2c::internal {
namespace fs = std::filesystem;

namespace {

class Reader {
 public:
  explicit Reader(const fs::path& path) : path_(path), in_(path, std::ios::binary) {
    if (!in_) ThrowInputError(path, "cannot open the recording");
    in_.seekg(0, std::ios::end);
    size_ = static_cast<uint64_t>(in_.tellg());
    in_.seekg(0);
  }
  template <class T>
  T Read(const char* what) {
    T value;
    if (!in_.read(reinterpret_cast<char*>(&value), sizeof(T))) {
      ThrowInputError(path_, fmt::format(".sens cut short in {} (at byte {} of {})", what, pos_, size_));
    }
    pos_ += sizeof(T);
    return value;
  }
  Eigen::Matrix4d Matrix(const char* what) {
    Eigen::Matrix4d m;
    for (int i = 0; i < 16; ++i) m(i / 4, i % 4) = Read<float>(what);
    return m;
  }
  // Skips `n` bytes of a frame's image; InputError when they would lie past the end.
  uint64_t Skip(uint64_t n, const std::string& what) {
    const uint64_t at = pos_;
    if (n > size_ - pos_) {
      ThrowInputError(
          path_, fmt::format(".sens cut short: {} ({} bytes at {}) lies past its end ({} bytes)", what, n, at, size_));
    }
    pos_ += n;
    in_.seekg(static_cast<std::streamoff>(pos_));
    return at;
  }
  uint64_t position() const { return pos_; }
  uint64_t size() const { return size_; }

 private:
  fs::path path_;
  std::ifstream in_;
  uint64_t size_ = 0, pos_ = 0;
};

CameraIntrinsics IntrinsicsOf(const Eigen::Matrix4d& k, uint32_t width, uint32_t height, const std::string& what) {
  CameraIntrinsics c{k(0, 0), k(1, 1), k(0, 2), k(1, 2), static_cast<int>(width), static_cast<int>(height)};
  c.Validate(what);
  return c;
}

}  // namespace

bool LooksLikeSens(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  uint32_t version = 0;
  uint64_t name_length = 0;
  if (!in.read(reinterpret_cast<char*>(&version), 4) || !in.read(reinterpret_cast<char*>(&name_length), 8)) {
    return false;
  }
  return version == 4 && name_length < 4096;
}

RgbdSequence ReadSens(const fs::path& path, const IoOptions& options) {
  Reader r(path);
  const uint32_t version = r.Read<uint32_t>("the version");
  if (version != 4) ThrowInputError(path, fmt::format(".sens version {} (fine2coarse reads version 4)", version));
  const uint64_t name_length = r.Read<uint64_t>("the sensor name");
  if (name_length > 4096) ThrowInputError(path, fmt::format(".sens sensor name of {} bytes", name_length));
  r.Skip(name_length, "the sensor name");
  const Eigen::Matrix4d color_k = r.Matrix("the colour intrinsics");
  const Eigen::Matrix4d color_pose = r.Matrix("the colour extrinsics");
  const Eigen::Matrix4d depth_k = r.Matrix("the depth intrinsics");
  const Eigen::Matrix4d depth_pose = r.Matrix("the depth extrinsics");
  const int32_t color_compression = r.Read<int32_t>("the colour compression");
  const int32_t depth_compression = r.Read<int32_t>("the depth compression");
  const uint32_t color_width = r.Read<uint32_t>("the image sizes"), color_height = r.Read<uint32_t>("the image sizes");
  const uint32_t depth_width = r.Read<uint32_t>("the image sizes"), depth_height = r.Read<uint32_t>("the image sizes");
  const float depth_shift = r.Read<float>("the depth shift");
  const uint64_t frames = r.Read<uint64_t>("the frame count");

  EmbeddedImage color, depth;
  switch (color_compression) {
    case 0:
      color.format = EmbeddedImage::Format::kRgb8;
      break;
    case 1:
    case 2:
      color.format = EmbeddedImage::Format::kEncoded;
      break;
    default:
      ThrowInputError(path, fmt::format(".sens colour compression {} is not one fine2coarse reads (0 raw, 1 PNG, 2 "
                                        "JPEG)",
                                        color_compression));
  }
  switch (depth_compression) {
    case 0:
      depth.format = EmbeddedImage::Format::kRawU16;
      break;
    case 1:
      depth.format = EmbeddedImage::Format::kZlibU16;
      break;
    case 2:
      ThrowInputError(path, ".sens depth compressed as occi_ushort, which fine2coarse does not read");
    default:
      ThrowInputError(path, fmt::format(".sens depth compression {} is not one fine2coarse reads (0 raw, 1 zlib)",
                                        depth_compression));
  }
  // Sizes are checked before any image is allocated from them (the 32-megapixel limit of
  // every frame image, io/image.h).
  for (const auto& [what, w, h] :
       {std::tuple{"colour", color_width, color_height}, std::tuple{"depth", depth_width, depth_height}}) {
    if (w == 0 || h == 0 || uint64_t{w} * h > (uint64_t{1} << 25)) {
      ThrowInputError(path, fmt::format(".sens {} images of {} x {} pixels (1 to 32 megapixels)", what, w, h));
    }
  }
  if (!(std::isfinite(depth_shift) && depth_shift > 0)) {
    ThrowInputError(path, fmt::format(".sens depth shift {} (units per metre) is not positive", depth_shift));
  }
  // Each frame takes at least its 96-byte header: a count beyond what the file holds is damage.
  if (frames == 0 || frames > (r.size() - r.position()) / 96) {
    ThrowInputError(path, fmt::format(".sens says {} frames, which {} bytes cannot hold", frames, r.size()));
  }
  color.width = static_cast<int>(color_width), color.height = static_cast<int>(color_height);
  depth.width = static_cast<int>(depth_width), depth.height = static_cast<int>(depth_height);

  RgbdSequence seq;
  seq.root = path;
  seq.layout = DatasetLayout::kSens;
  seq.intrinsics = IntrinsicsOf(depth_k, depth_width, depth_height, path.string() + " (depth intrinsics)");
  seq.intrinsics_source = path.string();
  seq.depth_scale = 1.0 / depth_shift;
  seq.invalid_depth_values = {0};
  const CameraIntrinsics color_intrinsics =
      IntrinsicsOf(color_k, color_width, color_height, path.string() + " (colour intrinsics)");
  const Rigid3d rig_from_color = RigidFromMatrixOrThrow(color_pose, path, 0);
  const Rigid3d rig_from_depth = RigidFromMatrixOrThrow(depth_pose, path, 0);
  const Rigid3d color_from_depth = rig_from_color.inverse() * rig_from_depth;
  const CameraIntrinsics& kd = *seq.intrinsics;
  const bool same_camera = color_width == depth_width && color_height == depth_height && color_intrinsics.fx == kd.fx &&
                           color_intrinsics.fy == kd.fy && color_intrinsics.cx == kd.cx &&
                           color_intrinsics.cy == kd.cy && color_from_depth.matrix().isIdentity(1e-12);
  if (!same_camera) seq.color_camera = ColorCamera{color_intrinsics, color_from_depth};

  Trajectory truth;
  uint64_t invalid_poses = 0;
  std::vector<uint64_t> stamps, color_stamps;  // the frame's (IoOptions::stamp) and the colour's
  for (uint64_t k = 0; k < frames; ++k) {
    const Eigen::Matrix4d world_from_camera = r.Matrix("a frame's pose");
    const uint64_t color_stamp = r.Read<uint64_t>("a frame's time stamps");
    const uint64_t depth_stamp = r.Read<uint64_t>("a frame's time stamps");
    const uint64_t color_bytes = r.Read<uint64_t>("a frame's sizes");
    const uint64_t depth_bytes = r.Read<uint64_t>("a frame's sizes");
    RgbdFrame frame;
    frame.color_path = frame.depth_path = path;
    frame.name = fmt::format("frame-{:06d}", k);
    color.offset = r.Skip(color_bytes, fmt::format("frame {}'s colour", k));
    color.size = color_bytes;
    depth.offset = r.Skip(depth_bytes, fmt::format("frame {}'s depth", k));
    depth.size = depth_bytes;
    frame.color_embedded = color;
    frame.depth_embedded = depth;
    stamps.push_back(options.stamp == FrameStamp::kDepth ? depth_stamp : color_stamp);
    color_stamps.push_back(color_stamp);
    seq.frames.push_back(frame);
    // ScanNet marks frames its reconstruction lost with -inf poses: no ground truth there.
    if (world_from_camera.allFinite()) {
      truth.Add(static_cast<double>(k), RigidFromMatrixOrThrow(world_from_camera, path, 0));
    } else {
      ++invalid_poses;
    }
  }
  // Time stamps in microseconds where the recording has increasing ones, else frame / fps.
  bool stamped = true;
  for (size_t k = 1; k < stamps.size(); ++k) stamped = stamped && stamps[k] > stamps[k - 1];
  for (size_t k = 0; k < seq.frames.size(); ++k) {
    seq.frames[k].timestamp = stamped ? static_cast<double>(stamps[k]) * 1e-6 : k / options.assumed_fps;
    if (stamped) {
      seq.frames[k].color_time = (static_cast<double>(color_stamps[k]) - static_cast<double>(stamps[k])) * 1e-6;
    }
  }
  for (double& t : truth.timestamps) t = seq.frames[static_cast<size_t>(t)].timestamp;
  if (!truth.empty()) {
    seq.ground_truth = std::move(truth);
    seq.ground_truth_source = path;
  }
  if (invalid_poses > 0) {
    spdlog::info("{}: {} of {} frames have no pose (not finite): left out of its ground truth", path.string(),
                 invalid_poses, frames);
  }
  return seq;
}

}  // namespace f2c::internal
