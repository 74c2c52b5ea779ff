// Features on real depth from ../shared/data (skipped when absent): planar proxies must be
// repeatable, i.e. the same wall, floor or table found again in the next frame where the
// ground-truth motion puts it.

#include <gtest/gtest.h>

#include <filesystem>
#include <map>

#include "f2c/features/feature_set.h"

namespace f2c {
namespace {

std::filesystem::path Data(const std::string& name) { return std::filesystem::path(F2C_SHARED_DATA_DIR) / name; }

TEST(RealData, RedkitchenProxiesReappearWhereTheTrueMotionPutsThem) {
  if (!std::filesystem::exists(Data("7scenes_redkitchen_15hz"))) GTEST_SKIP() << "../shared/data absent";
  IoOptions io;
  io.last = 40;
  const RgbdSequence seq = ReadSequence(Data("7scenes_redkitchen_15hz"), io);
  FeatureRun run;
  run.quiet = true;
  const FeatureSet set = ExtractFeatures(seq, FeatureOptions(), run);
  std::map<double, Rigid3d> gt;
  for (size_t i = 0; i < seq.ground_truth->size(); ++i)
    gt[seq.ground_truth->timestamps[i]] = seq.ground_truth->world_from_camera[i];

  int large = 0, found = 0;
  for (size_t i = 0; i + 1 < seq.frames.size(); ++i) {
    const FrameFeatures& a = set.frames[i];
    const FrameFeatures& b = set.frames[i + 1];
    EXPECT_GE(a.proxies.size(), 3u) << i;
    EXPECT_GT(a.Count(FeatureType::kPlane), 100) << i;
    EXPECT_GT(a.Count(FeatureType::kSilhouette) + a.Count(FeatureType::kRidge) + a.Count(FeatureType::kValley), 10)
        << i;
    const Rigid3d b_from_a = gt.at(seq.frames[i + 1].timestamp).inverse() * gt.at(seq.frames[i].timestamp);
    for (const PlanarProxy& p : a.proxies) {
      if (p.inliers < 200) continue;
      ++large;
      const Eigen::Vector3f normal = (b_from_a.linear() * p.normal.cast<double>()).cast<float>();
      const Eigen::Vector3f centroid = (b_from_a * p.centroid.cast<double>()).cast<float>();
      for (const PlanarProxy& q : b.proxies) {
        if (q.normal.dot(normal) > std::cos(5.0 * M_PI / 180) && std::abs(q.Distance(centroid)) < 0.03f) {
          ++found;
          break;
        }
      }
    }
  }
  EXPECT_GT(large, 40);
  EXPECT_GE(found, 0.95 * large) << found << " of " << large << " large proxies found again";
}

}  // namespace
}  // namespace f2c
