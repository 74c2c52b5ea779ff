#include "f2c/testing/sens_writer.h"

#include <libdeflate.h>

#include <cstring>
#include <opencv2/imgproc.hpp>
#include <string>

#include "f2c/io/image_write.h"
#include "f2c/util/file.h"

namespace f2c::testing {
namespace {

template <class T>
void Put(std::string* out, T value) {
  out->append(reinterpret_cast<const char*>(&value), sizeof(T));
}

void PutMatrix(std::string* out, const Eigen::Matrix4d& m) {
  for (int i = 0; i < 16; ++i) Put<float>(out, static_cast<float>(m(i / 4, i % 4)));
}

Eigen::Matrix4d IntrinsicMatrix(const CameraIntrinsics& k) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m(0, 0) = k.fx, m(1, 1) = k.fy, m(0, 2) = k.cx, m(1, 2) = k.cy;
  return m;
}

}  // namespace

uint64_t WriteSyntheticSens(const std::filesystem::path& path, const SyntheticScene& scene,
                            const std::vector<Rigid3d, Eigen::aligned_allocator<Rigid3d>>& poses,
                            const SensOptions& o) {
  std::string out;
  Put<uint32_t>(&out, 4);
  const std::string name = "fine2coarse test";
  Put<uint64_t>(&out, name.size());
  out += name;
  PutMatrix(&out, IntrinsicMatrix(o.color));
  // Extrinsics: each camera's pose in the rig's frame; the rig is the depth camera here.
  PutMatrix(&out, o.color_from_depth.inverse().matrix());
  PutMatrix(&out, IntrinsicMatrix(o.depth));
  PutMatrix(&out, Eigen::Matrix4d::Identity());
  Put<int32_t>(&out, o.color_compression);
  Put<int32_t>(&out, o.depth_compression);
  Put<uint32_t>(&out, o.color.width), Put<uint32_t>(&out, o.color.height);
  Put<uint32_t>(&out, o.depth.width), Put<uint32_t>(&out, o.depth.height);
  Put<float>(&out, o.depth_shift);
  Put<uint64_t>(&out, poses.size());
  libdeflate_compressor* compressor = libdeflate_alloc_compressor(6);
  for (size_t k = 0; k < poses.size(); ++k) {
    const cv::Mat depth_m = Render(scene, o.depth, poses[k]).depth;
    const cv::Mat color = Render(scene, o.color, poses[k] * o.color_from_depth.inverse()).color;
    cv::Mat depth16;
    depth_m.convertTo(depth16, CV_16U, o.depth_shift);
    std::string color_bytes;
    if (o.color_compression == 0) {
      cv::Mat rgb;
      cv::cvtColor(color, rgb, cv::COLOR_BGR2RGB);
      color_bytes.assign(reinterpret_cast<const char*>(rgb.data), rgb.total() * 3);
    } else {
      color_bytes = o.color_compression == 1 ? EncodePng(color) : EncodeJpeg(color, 95);
    }
    std::string depth_bytes(reinterpret_cast<const char*>(depth16.data), depth16.total() * 2);
    if (o.depth_compression == 1) {
      std::string z(libdeflate_zlib_compress_bound(compressor, depth_bytes.size()), '\0');
      z.resize(libdeflate_zlib_compress(compressor, depth_bytes.data(), depth_bytes.size(), z.data(), z.size()));
      depth_bytes = z;
    }
    PutMatrix(&out, poses[k].matrix());
    const auto stamp = static_cast<uint64_t>(1e6 * (1000.0 + k / 30.0));
    Put<uint64_t>(&out, stamp), Put<uint64_t>(&out, stamp);
    Put<uint64_t>(&out, color_bytes.size()), Put<uint64_t>(&out, depth_bytes.size());
    out += color_bytes;
    out += depth_bytes;
  }
  libdeflate_free_compressor(compressor);
  Put<uint64_t>(&out, 0);  // IMU frames
  WriteFileAtomic(path, out);
  return out.size();
}

}  // namespace f2c::testing
