#include "f2c/features/feature_codec.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "f2c/util/error.h"

namespace f2c {
namespace {

bool SameBits(const Feature& a, const Feature& b) {
  return a.type == b.type && std::memcmp(a.position.data(), b.position.data(), 12) == 0 &&
         std::memcmp(a.direction.data(), b.direction.data(), 12) == 0 &&
         std::memcmp(&a.salience, &b.salience, 4) == 0 && a.proxy == b.proxy &&
         std::memcmp(a.pixel.data(), b.pixel.data(), 8) == 0;
}

// Features as the extraction makes them: camera coordinates up to `range` metres, unit
// directions anywhere on the sphere, pixels of a 640 x 480 image.
FrameFeatures RandomFrame(int n, float range, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1, 1), unit(0, 1);
  std::normal_distribution<float> g(0, 1);
  FrameFeatures f;
  for (int i = 0; i < n; ++i) {
    Feature x;
    x.type = static_cast<FeatureType>(i * kFeatureTypeCount / n);
    x.position = Eigen::Vector3f(u(rng), u(rng), 0.5f * (u(rng) + 1)) * range;
    x.direction = Eigen::Vector3f(g(rng), g(rng), g(rng)).normalized();
    x.salience = unit(rng);
    x.proxy = i % 7 - 1;
    x.pixel = Eigen::Vector2f(639 * unit(rng), 479 * unit(rng));
    f.features.push_back(x);
  }
  return f;
}

TEST(FeatureCodec, RoundedFeaturesPackAndUnpackToTheSameBitsAndRoundToThemselves) {
  for (const float range : {0.3f, 5.0f, 20.0f, 3000.0f}) {
    const FrameFeatures raw = RandomFrame(5000, range, 3);
    FrameFeatures rounded = raw;
    RoundToCachePrecision(&rounded);
    const FeatureGrids grids = ChooseGrids(rounded.features);
    // The grids of the rounded features are the raw ones' (the writer chooses them again).
    EXPECT_EQ(grids.position_exponent, ChooseGrids(raw.features).position_exponent);
    EXPECT_LE(std::ldexp(range, grids.position_exponent), 32767);
    EXPECT_GT(std::ldexp(range, grids.position_exponent + 1), 32767 * 0.9);
    FrameFeatures twice = rounded;
    RoundToCachePrecision(&twice);
    for (size_t i = 0; i < raw.features.size(); ++i) {
      const Feature& r = rounded.features[i];
      ASSERT_TRUE(SameBits(twice.features[i], r)) << "range " << range << ", feature " << i;
      ASSERT_TRUE(SameBits(Unpack(Pack(r, grids), r.type, grids), r)) << "range " << range << ", feature " << i;
      // Half a grid step at most (2^-13 m within 8 m of the camera), 1/16 pixel.
      const float step = std::ldexp(1.0f, -grids.position_exponent);
      EXPECT_LE((r.position - raw.features[i].position).cwiseAbs().maxCoeff(), 0.5f * step);
      EXPECT_LE((r.pixel - raw.features[i].pixel).cwiseAbs().maxCoeff(), 1.0f / 16);
      EXPECT_LT((r.direction - raw.features[i].direction).norm(), 1e-4f);  // 0.006 deg
      EXPECT_NEAR(r.salience, raw.features[i].salience, 1.0f / 65536);
    }
  }
}

TEST(FeatureCodec, EachFrameGetsTheFinestGridItsFarthestFeatureAllows) {
  FrameFeatures far = RandomFrame(100, 3, 1);
  far.features[50].position.z() = 5;
  EXPECT_EQ(ChooseGrids(far.features).position_exponent, 12);  // 5 * 2^12 <= 32767: 0.24 mm
  far.features[50].position.z() = 3;
  EXPECT_EQ(ChooseGrids(far.features).position_exponent, 13);  // 0.12 mm
  far.features[50].position.x() = -20;                         // needs 20 * 2^k <= 32767: k = 10
  EXPECT_EQ(ChooseGrids(far.features).position_exponent, 10);
  EXPECT_EQ(ChooseGrids(far.features).pixel_exponent, 3);
  far.features[0].pixel.x() = 6000;  // a 6,000-pixel-wide image: quarter pixels
  EXPECT_EQ(ChooseGrids(far.features).pixel_exponent, 2);
}

TEST(FeatureCodec, OctahedralCodesReproduceTheirDirectionsOnBothHalvesAndTheFold) {
  // Axes, the fold (z = 0) and vectors just beside it, where float rounding may pick a
  // neighbouring code.
  const std::vector<Eigen::Vector3f> directions = {{0, 0, 1},
                                                   {0, 0, -1},
                                                   {1, 0, 0},
                                                   {-1, 0, 0},
                                                   {0, 1, 0},
                                                   {0, -1, 0},
                                                   {0.6f, 0.8f, 0},
                                                   {-0.6f, 0.8f, 1e-7f},
                                                   {0.3f, -0.2f, -1e-6f},
                                                   {0.5f, 0.5f, -0.70710677f},
                                                   // The lower half's seam (x = 0): codes +u
                                                   // and -u decode to +0 and -0 alike.
                                                   {-1e-9f, 0.389f, -0.921f},
                                                   {1e-9f, -0.389f, -0.921f}};
  for (const Eigen::Vector3f& raw : directions) {
    int16_t x, y;
    EncodeOctahedral(raw.normalized(), &x, &y);
    const Eigen::Vector3f d = DecodeOctahedral(x, y);
    EXPECT_LT((d - raw.normalized()).norm(), 1e-4f) << raw.transpose();
    Feature f;
    f.direction = d;
    const PackedFeature p = Pack(f, FeatureGrids{});
    EXPECT_EQ(DecodeOctahedral(p.direction[0], p.direction[1]), d) << raw.transpose();
  }
}

TEST(FeatureCodec, AFeatureNotRoundedToTheGridIsABug) {
  Feature f;
  f.direction = Eigen::Vector3f::UnitZ();
  f.position = Eigen::Vector3f(0.1f, 0, 1);  // 0.1 is not a multiple of 2^-12
  EXPECT_THROW(Pack(f, FeatureGrids{}), InternalError);
  f.position = Eigen::Vector3f(0.125f, 0, 1);
  EXPECT_NO_THROW(Pack(f, FeatureGrids{}));
  f.salience = 0.1f;
  EXPECT_THROW(Pack(f, FeatureGrids{}), InternalError);
}

}  // namespace
}  // namespace f2c
