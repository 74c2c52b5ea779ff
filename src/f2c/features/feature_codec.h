#pragma once
// Features at the precision the feature cache stores them, 18 bytes each instead of 41: a
// 15,000-frame scan's cache was 1.5 GB at 100 KB per frame. Extraction rounds every frame's
// features to this precision before anything sees them, so a run that reads its features
// from the cache and a run that computes them give the same poses, bit for bit.
//
//   position   3 x int16 on a grid of 2^-k m, k <= 20, chosen per frame: the finest that holds
//              the frame's largest coordinate (0.12 mm when it is 2-4 m, 0.24 mm at 4-8 m)
//   direction  2 x int16, the octahedral encoding of a unit vector (about 0.003 deg)
//   salience   uint16, multiples of 2^-15 in [0, 1]
//   proxy      int16 (-1: none)
//   pixel      2 x int16 on a grid of 2^-k pixels, k <= 3 (1/8 pixel), chosen per frame
// The grids are powers of two, so a rounded value is exact in float and rounds to itself.

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "f2c/features/depth_features.h"

namespace f2c {

struct FeatureGrids {
  int8_t position_exponent = 12;  // positions are multiples of 2^-position_exponent metres
  int8_t pixel_exponent = 3;      // pixels are multiples of 2^-pixel_exponent
};

struct PackedFeature {
  int16_t position[3];
  int16_t direction[2];
  uint16_t salience;
  int16_t proxy;
  int16_t pixel[2];
};
constexpr size_t kPackedFeatureBytes = 18;  // as written, without padding
static_assert(sizeof(PackedFeature) == kPackedFeatureBytes);

// The finest grids (at most 2^-20 m and 1/8 pixel) on which every feature's position and
// pixel fit int16. Rounding the features to them gives the same grids again.
FeatureGrids ChooseGrids(const std::vector<Feature>& features);

// Rounds every feature of `frame` to the cache's precision (in place; idempotent).
void RoundToCachePrecision(FrameFeatures* frame);

// Exact for features already rounded to `grids` (InternalError otherwise: a value that does
// not fit or a direction no code reproduces).
PackedFeature Pack(const Feature& feature, const FeatureGrids& grids);
Feature Unpack(const PackedFeature& packed, FeatureType type, const FeatureGrids& grids);

// The octahedral encoding of unit vectors (Cigolle et al. 2014, "A Survey of Efficient
// Representations for Independent Unit Vectors"), on a grid of 1 / 32767.
Eigen::Vector3f DecodeOctahedral(int16_t x, int16_t y);
void EncodeOctahedral(const Eigen::Vector3f& direction, int16_t* x, int16_t* y);

}  // namespace f2c
