#include "f2c/fusion/tsdf.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "f2c/util/error.h"

namespace f2c {

void TsdfOptions::Check() const {
  CheckFields(*this);
  if (!(max_depth > min_depth)) {
    ThrowInputError("--fuse-max-depth",
                    fmt::format("must exceed the nearest depth ({}), got {}", min_depth, max_depth));
  }
}

namespace {

constexpr uint64_t kEmpty = ~uint64_t{0};  // never a packed key (63 bits)

int FloorDiv(int a, int b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }

}  // namespace

TsdfVolume::TsdfVolume(const TsdfOptions& options) : options_(options), index_(1 << 11) { options_.Check(); }

size_t TsdfVolume::MemoryBytes() const {
  return blocks_.size() * sizeof(blocks_[0]) + coords_.capacity() * sizeof(coords_[0]) + index_.MemoryBytes();
}

int TsdfVolume::FindBlock(const Eigen::Vector3i& block) const { return index_.Find(PackCoords(block)); }

int TsdfVolume::AddBlock(const Eigen::Vector3i& block) {
  int& b = index_.At(PackCoords(block));
  if (b < 0) {
    b = static_cast<int>(coords_.size());
    coords_.push_back(block);
    blocks_.emplace_back();
  }
  return b;
}

namespace {

Eigen::Vector3i BlockOf(const Eigen::Vector3i& v) {
  return {FloorDiv(v.x(), kTsdfBlockSide), FloorDiv(v.y(), kTsdfBlockSide), FloorDiv(v.z(), kTsdfBlockSide)};
}

int OffsetIn(const Eigen::Vector3i& v, const Eigen::Vector3i& block) {
  const Eigen::Vector3i o = v - block * kTsdfBlockSide;
  return (o.z() * kTsdfBlockSide + o.y()) * kTsdfBlockSide + o.x();
}

}  // namespace

const TsdfVoxel* TsdfVolume::Find(const Eigen::Vector3i& v) const {
  const Eigen::Vector3i block = BlockOf(v);
  const int b = FindBlock(block);
  return b < 0 ? nullptr : &blocks_[b][OffsetIn(v, block)];
}

TsdfVoxel& TsdfVolume::At(const Eigen::Vector3i& v) {
  const Eigen::Vector3i block = BlockOf(v);
  return blocks_[AddBlock(block)][OffsetIn(v, block)];
}

void TsdfVolume::Integrate(const cv::Mat& depth, const cv::Mat& bgr, const CameraIntrinsics& k,
                           const Rigid3d& world_from_camera) {
  F2C_CHECK(depth.type() == CV_32F, "depth is CV_32F metres");
  F2C_CHECK(bgr.empty() || (bgr.type() == CV_8UC3 && bgr.size() == depth.size()), "colour is 8UC3 of the depth's size");
  const float voxel = static_cast<float>(options_.voxel_size);
  const float trunc = static_cast<float>(options_.Truncation());
  const float block_len = voxel * kTsdfBlockSide;
  const float min_depth = static_cast<float>(options_.min_depth), max_depth = static_cast<float>(options_.max_depth);
  const Eigen::Matrix3f r_wc = world_from_camera.linear().cast<float>();
  const Eigen::Vector3f t_wc = world_from_camera.translation().cast<float>();
  const float fx = static_cast<float>(k.fx), fy = static_cast<float>(k.fy);
  const float cx = static_cast<float>(k.cx), cy = static_cast<float>(k.cy);

  // 1. The blocks the truncation band touches: every block each valid pixel's ray passes
  // through from z - trunc to z + trunc, walked block by block (Amanatides & Woo's grid
  // traversal, in block units), for pixels `stride` apart: at 1 cm voxels a block spans
  // ~10 pixels at 4 m, and every third pixel is enough. Sorted, so blocks are created in the
  // same order for any thread count.
  // Rays at most a third of a block apart where they are sparsest (at max_depth).
  const int stride = std::clamp(static_cast<int>(block_len * fx / (3 * max_depth)), 1, 8);
  tbb::enumerable_thread_specific<std::vector<uint64_t>> found;
  // Sampled rows and columns: 0, stride, 2 stride, ..., and the last (the image's border).
  auto samples = [&](int size) { return (size - 1 + stride - 1) / stride + 1; };
  auto sample = [&](int i, int size) { return std::min(i * stride, size - 1); };
  tbb::parallel_for(tbb::blocked_range<int>(0, samples(depth.rows), 8), [&](const tbb::blocked_range<int>& rows) {
    std::vector<uint64_t>& keys = found.local();
    // Neighbouring rays mostly meet the same blocks: a small direct-mapped cache of keys
    // already listed keeps the list (and its sort) short.
    std::array<uint64_t, 256> recent;
    recent.fill(kEmpty);
    for (int row = rows.begin(); row < rows.end(); ++row) {
      const int v = sample(row, depth.rows);
      const float* z_row = depth.ptr<float>(v);
      for (int column = 0, columns = samples(depth.cols); column < columns; ++column) {
        const int u = sample(column, depth.cols);
        const float z = z_row[u];
        if (!(z >= min_depth && z <= max_depth)) continue;
        const Eigen::Vector3f ray = r_wc * Eigen::Vector3f((u - cx) / fx, (v - cy) / fy, 1.0f);
        const Eigen::Vector3f a = (t_wc + ray * (z - trunc)) / block_len, b = (t_wc + ray * (z + trunc)) / block_len;
        const Eigen::Vector3f d = b - a;
        Eigen::Vector3i block = a.array().floor().cast<int>();
        const Eigen::Vector3i end = b.array().floor().cast<int>();
        Eigen::Vector3i step;
        Eigen::Vector3f t_max, t_delta;  // ray parameter (0..1) of the next border, and per block
        for (int i = 0; i < 3; ++i) {
          step[i] = d[i] > 0 ? 1 : -1;
          t_delta[i] = d[i] != 0 ? std::abs(1.0f / d[i]) : std::numeric_limits<float>::infinity();
          const float border = d[i] > 0 ? static_cast<float>(block[i] + 1) : static_cast<float>(block[i]);
          t_max[i] = d[i] != 0 ? (border - a[i]) / d[i] : std::numeric_limits<float>::infinity();
        }
        const int most = (end - block).cwiseAbs().sum();
        for (int n = 0;; ++n) {
          const uint64_t key = PackCoords(block);
          uint64_t& slot = recent[(key * 0x9E3779B97F4A7C15ULL) >> 56];
          if (slot != key) keys.push_back(key), slot = key;
          if (n >= most || block == end) break;
          int i = 0;
          t_max.minCoeff(&i);
          block[i] += step[i];
          t_max[i] += t_delta[i];
        }
      }
    }
  });
  std::vector<uint64_t> keys;
  for (const std::vector<uint64_t>& part : found) keys.insert(keys.end(), part.begin(), part.end());
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  std::vector<int> touched;
  touched.reserve(keys.size());
  for (uint64_t key : keys) touched.push_back(AddBlock(UnpackCoords(key)));

  // 2. Their voxels, in parallel (each voxel belongs to one block: no two threads write one).
  const Eigen::Matrix3f r_cw = r_wc.transpose();
  const Eigen::Vector3f t_cw = -(r_cw * t_wc);
  const Eigen::Vector3f step_x = r_cw.col(0) * voxel;  // camera coordinates per voxel along x
  const bool colour = !bgr.empty();
  const float cols = static_cast<float>(depth.cols), rows = static_cast<float>(depth.rows);
  // Plain pointers and strides: the colour stores (uint8_t may alias anything) would
  // otherwise make the compiler reload the Mats' fields for every voxel.
  const uint8_t* const depth_data = depth.data;
  const uint8_t* const bgr_data = bgr.data;
  const size_t depth_step = depth.step[0], bgr_step = colour ? bgr.step[0] : 0;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, touched.size(), 16), [&](const tbb::blocked_range<size_t>& range) {
    for (size_t n = range.begin(); n < range.end(); ++n) {
      const int b = touched[n];
      std::array<TsdfVoxel, kTsdfBlockVoxels>& block = blocks_[b];
      const Eigen::Vector3i origin = coords_[b] * kTsdfBlockSide;
      for (int z = 0; z < kTsdfBlockSide; ++z) {
        for (int y = 0; y < kTsdfBlockSide; ++y) {
          const Eigen::Vector3f world = (origin + Eigen::Vector3i(0, y, z)).cast<float>() * voxel;
          const Eigen::Vector3f p0 = r_cw * world + t_cw;
          TsdfVoxel* row = &block[(z * kTsdfBlockSide + y) * kTsdfBlockSide];
          // The row's 8 projections first, in a loop the compiler vectorises; then the
          // look-ups and updates one by one. The nearest pixel: + 0.5 and truncation rounds
          // every coordinate that can land in the image (>= -0.5).
          float pz[kTsdfBlockSide], uf[kTsdfBlockSide], vf[kTsdfBlockSide];
          for (int x = 0; x < kTsdfBlockSide; ++x) {
            const float px = p0.x() + x * step_x.x(), py = p0.y() + x * step_x.y();
            pz[x] = p0.z() + x * step_x.z();
            const float inv_z = 1.0f / pz[x];
            uf[x] = fx * px * inv_z + cx + 0.5f;
            vf[x] = fy * py * inv_z + cy + 0.5f;
          }
          for (int x = 0; x < kTsdfBlockSide; ++x) {
            if (!(pz[x] > 0 && uf[x] >= 0 && vf[x] >= 0 && uf[x] < cols && vf[x] < rows)) continue;
            const int u = static_cast<int>(uf[x]), v = static_cast<int>(vf[x]);
            const float d = reinterpret_cast<const float*>(depth_data + v * depth_step)[u];
            if (!(d >= min_depth && d <= max_depth)) continue;
            const float sdf = d - pz[x];
            if (sdf < -trunc) continue;  // hidden behind the surface
            const float tsdf = std::min(1.0f, sdf / trunc);
            TsdfVoxel& voxel_ref = row[x];
            const float w = voxel_ref.weight, inv = 1.0f / (w + 1.0f);
            voxel_ref.tsdf = (voxel_ref.tsdf * w + tsdf) * inv;
            if (colour && sdf < trunc) {
              const uint8_t* c = bgr_data + v * bgr_step + 3 * u;
              const float cw = voxel_ref.color_weight, cinv = 1.0f / (cw + 1.0f);
              for (int i = 0; i < 3; ++i) {  // stored RGB, read BGR
                voxel_ref.rgb[i] = static_cast<uint8_t>((voxel_ref.rgb[i] * cw + c[2 - i]) * cinv + 0.5f);
              }
              if (voxel_ref.color_weight < 255) ++voxel_ref.color_weight;
            }
            voxel_ref.weight = w + 1.0f;
          }
        }
      }
    }
  });
}

}  // namespace f2c
