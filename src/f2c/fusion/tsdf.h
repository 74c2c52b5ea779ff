#pragma once
// A sparse truncated signed distance volume (Curless & Levoy 1996; KinectFusion; the
// voxel-block hashing of Niessner et al. 2013). Space is cut into blocks of 8^3 voxels, and a
// block exists only once a depth image has seen a surface within the truncation band of it,
// so memory follows the observed surface, not the bounding box (docs/fusion.md).
//
// Each voxel holds the projective signed distance to the surface along the camera ray,
// divided by the truncation distance and clamped to [-1, 1] (positive in front of the
// surface, in free space), a weight (observations so far) and a colour, each the running
// average over the frames that saw it. A voxel further than the truncation behind the
// surface is left alone: it is hidden, not empty.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <deque>
#include <opencv2/core.hpp>
#include <vector>

#include "f2c/geometry/coord_table.h"
#include "f2c/geometry/intrinsics.h"
#include "f2c/geometry/rigid.h"
#include "f2c/util/fields.h"

namespace f2c {

struct TsdfOptions {
  double voxel_size = 0.01;   // metres (--voxel-size)
  int truncation_voxels = 4;  // the signed distance is truncated at this many voxels
  double min_depth = 0.3;     // metres; depth outside [min_depth, max_depth] is ignored
  double max_depth = 4.0;     // (--fuse-max-depth: far depth is noisy and blurs the surface)

  double Truncation() const { return voxel_size * truncation_voxels; }

  template <class V>
  void Fields(V& v) {
    v.Group("Mesh (TSDF fusion, marching cubes; docs/fusion.md)");
    F2C_FIELD(v, voxel_size, "--voxel-size", Between(0.001, 0.5), "TSDF voxel edge (m)");
    F2C_FIELD(v, truncation_voxels, "--truncation-voxels", Between(1, 64),
              "signed distances are truncated at this many voxels");
    F2C_FIELD(v, min_depth, "", AtLeast(0), "depth nearer than this (m) is not fused");
    F2C_FIELD(v, max_depth, "--fuse-max-depth", Positive(), "depth beyond this (m) is not fused");
  }
  void Check() const;  // InputError naming the option
};

struct TsdfVoxel {
  float tsdf = 1.0f;    // signed distance / truncation, in [-1, 1]
  float weight = 0.0f;  // 0: never observed
  std::array<uint8_t, 3> rgb{0, 0, 0};
  // Observations averaged into rgb: only those within the truncation band (free space has no
  // colour), and at most 255, after which the colour follows the newest frames a little more.
  uint8_t color_weight = 0;
};

constexpr int kTsdfBlockSide = 8;
constexpr int kTsdfBlockVoxels = kTsdfBlockSide * kTsdfBlockSide * kTsdfBlockSide;

class TsdfVolume {
 public:
  explicit TsdfVolume(const TsdfOptions& options);

  // Integrates one frame: depth in metres (CV_32F, 0 = invalid), colour as 8-bit BGR of the
  // same size (or empty: no colour), and the camera's pose in the world. Blocks the frame's
  // truncation band touches are allocated first, then their voxels updated in parallel;
  // the result does not depend on the thread count.
  void Integrate(const cv::Mat& depth, const cv::Mat& bgr, const CameraIntrinsics& intrinsics,
                 const Rigid3d& world_from_camera);

  const TsdfOptions& options() const { return options_; }
  int BlockCount() const { return static_cast<int>(coords_.size()); }
  size_t MemoryBytes() const;  // the voxels and the block index
  // Voxel v (integer coordinates: its position is v * voxel_size), or nullptr where no block.
  const TsdfVoxel* Find(const Eigen::Vector3i& voxel) const;
  // Voxel v, its block allocated if need be (to fill a volume by other means than depth).
  TsdfVoxel& At(const Eigen::Vector3i& voxel);
  // Block b's integer coordinates (voxel = block * 8 + offset) and its voxels, x fastest.
  const Eigen::Vector3i& BlockCoords(int b) const { return coords_[b]; }
  const TsdfVoxel* BlockVoxels(int b) const { return blocks_[b].data(); }

 private:
  int FindBlock(const Eigen::Vector3i& block) const;  // -1 when absent
  int AddBlock(const Eigen::Vector3i& block);

  TsdfOptions options_;
  std::deque<std::array<TsdfVoxel, kTsdfBlockVoxels>> blocks_;  // stable addresses as it grows
  std::vector<Eigen::Vector3i> coords_;
  CoordTable index_;  // packed block coordinates -> block number
};

}  // namespace f2c
