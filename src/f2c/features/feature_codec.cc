#include "f2c/features/feature_codec.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "f2c/util/error.h"

namespace f2c {
namespace {

constexpr int kFinestPositionExponent = 20;  // 1 micrometre
constexpr int kFinestPixelExponent = 3;
constexpr int kCoarsestExponent = -126;  // FLT_MAX 2^-126 fits int16
constexpr float kOctScale = 32767;
constexpr float kSalienceScale = 32768;

float SignOf(float v) { return v >= 0 ? 1.0f : -1.0f; }

// The finest exponent k <= finest at which round(m 2^k) fits int16.
int FitExponent(float m, int finest) {
  int k = finest;
  while (k > kCoarsestExponent && std::nearbyint(std::ldexp(m, k)) > 32767) --k;
  return k;
}

// "+ 0.0f": a value just below zero rounds to -0, which the integer code cannot hold.
float RoundTo(float v, int exponent) { return std::ldexp(std::nearbyint(std::ldexp(v, exponent)) + 0.0f, -exponent); }

int16_t ToGrid(float v, int exponent) {
  const float n = std::nearbyint(std::ldexp(v, exponent));
  F2C_CHECK(std::abs(n) <= 32767 && std::ldexp(n, -exponent) == v, "a feature value lies on the cache's grid");
  return static_cast<int16_t>(n);
}

bool SameBits(const Eigen::Vector3f& a, const Eigen::Vector3f& b) { return std::memcmp(a.data(), b.data(), 12) == 0; }

}  // namespace

Eigen::Vector3f DecodeOctahedral(int16_t x, int16_t y) {
  float u = x / kOctScale, v = y / kOctScale;
  const float z = 1 - std::abs(u) - std::abs(v);
  if (z < 0) {  // the lower half, folded over the diagonals
    const float u0 = u;
    u = (1 - std::abs(v)) * SignOf(u0);
    v = (1 - std::abs(u0)) * SignOf(v);
  }
  // "+ 0": codes on the fold's seam (|v| = 1) decode x to +0 or -0 by the sign of u; one
  // zero, so that every decoded vector encodes to a code that decodes to it again.
  return Eigen::Vector3f(u, v, z).normalized() + Eigen::Vector3f::Zero();
}

void EncodeOctahedral(const Eigen::Vector3f& d, int16_t* x, int16_t* y) {
  const float s = std::abs(d.x()) + std::abs(d.y()) + std::abs(d.z());
  float u = 0, v = 0;
  if (s > 0) {
    u = d.x() / s;
    v = d.y() / s;
    if (d.z() < 0) {
      const float u0 = u;
      u = (1 - std::abs(v)) * SignOf(u0);
      v = (1 - std::abs(u0)) * SignOf(v);
    }
  }
  *x = static_cast<int16_t>(std::nearbyint(std::clamp(u, -1.0f, 1.0f) * kOctScale));
  *y = static_cast<int16_t>(std::nearbyint(std::clamp(v, -1.0f, 1.0f) * kOctScale));
}

FeatureGrids ChooseGrids(const std::vector<Feature>& features) {
  float position = 0, pixel = 0;
  for (const Feature& f : features) {
    position = std::max(position, f.position.cwiseAbs().maxCoeff());
    pixel = std::max(pixel, f.pixel.cwiseAbs().maxCoeff());
  }
  FeatureGrids grids;
  grids.position_exponent = static_cast<int8_t>(FitExponent(position, kFinestPositionExponent));
  grids.pixel_exponent = static_cast<int8_t>(FitExponent(pixel, kFinestPixelExponent));
  return grids;
}

void RoundToCachePrecision(FrameFeatures* frame) {
  for (const Feature& f : frame->features) {
    F2C_CHECK(f.position.allFinite() && f.direction.allFinite() && f.pixel.allFinite() && std::isfinite(f.salience),
              "features are finite");
  }
  const FeatureGrids grids = ChooseGrids(frame->features);
  for (Feature& f : frame->features) {
    for (int i = 0; i < 3; ++i) f.position[i] = RoundTo(f.position[i], grids.position_exponent);
    for (int i = 0; i < 2; ++i) f.pixel[i] = RoundTo(f.pixel[i], grids.pixel_exponent);
    int16_t x, y;
    EncodeOctahedral(f.direction, &x, &y);
    f.direction = DecodeOctahedral(x, y);
    f.salience = (std::nearbyint(std::clamp(f.salience, 0.0f, 1.0f) * kSalienceScale) + 0.0f) / kSalienceScale;
  }
}

PackedFeature Pack(const Feature& f, const FeatureGrids& grids) {
  PackedFeature p;
  for (int i = 0; i < 3; ++i) p.position[i] = ToGrid(f.position[i], grids.position_exponent);
  for (int i = 0; i < 2; ++i) p.pixel[i] = ToGrid(f.pixel[i], grids.pixel_exponent);
  EncodeOctahedral(f.direction, &p.direction[0], &p.direction[1]);
  // A code decodes to one vector, but float rounding may lead that vector's encoding to a
  // neighbouring code (near the fold): the code that reproduces it is among the neighbours.
  bool found = SameBits(DecodeOctahedral(p.direction[0], p.direction[1]), f.direction);
  for (int dx = -1; dx <= 1 && !found; ++dx) {
    for (int dy = -1; dy <= 1 && !found; ++dy) {
      const int x = p.direction[0] + dx, y = p.direction[1] + dy;
      if (std::abs(x) > 32767 || std::abs(y) > 32767) continue;
      if (SameBits(DecodeOctahedral(static_cast<int16_t>(x), static_cast<int16_t>(y)), f.direction)) {
        p.direction[0] = static_cast<int16_t>(x);
        p.direction[1] = static_cast<int16_t>(y);
        found = true;
      }
    }
  }
  F2C_CHECK(found, "a feature's direction is one the cache's encoding reproduces");
  const float s = f.salience * kSalienceScale;
  F2C_CHECK(s >= 0 && s <= kSalienceScale && std::nearbyint(s) == s, "a feature's salience lies on the cache's grid");
  p.salience = static_cast<uint16_t>(s);
  F2C_CHECK(f.proxy >= -1 && f.proxy <= 32767, "a feature's proxy index fits the cache");
  p.proxy = static_cast<int16_t>(f.proxy);
  return p;
}

Feature Unpack(const PackedFeature& p, FeatureType type, const FeatureGrids& grids) {
  Feature f;
  f.type = type;
  for (int i = 0; i < 3; ++i) f.position[i] = std::ldexp(static_cast<float>(p.position[i]), -grids.position_exponent);
  for (int i = 0; i < 2; ++i) f.pixel[i] = std::ldexp(static_cast<float>(p.pixel[i]), -grids.pixel_exponent);
  f.direction = DecodeOctahedral(p.direction[0], p.direction[1]);
  f.salience = p.salience / kSalienceScale;
  f.proxy = p.proxy;
  return f;
}

}  // namespace f2c
