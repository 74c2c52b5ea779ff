#include "f2c/matching/sift.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>
#include <random>

#include "f2c/testing/synthetic_scene.h"

namespace f2c {
namespace {

struct View {
  cv::Mat gray, depth;
};

View RenderView() {
  Rigid3d pose = Rigid3d::Identity();
  pose.translation() = Eigen::Vector3d(0, 0, -0.5);
  const auto frame = testing::Render(testing::SyntheticScene(), testing::TestIntrinsics(), pose);
  View view{cv::Mat(), frame.depth};
  cv::cvtColor(frame.color, view.gray, cv::COLOR_BGR2GRAY);
  return view;
}

// At full resolution and on the half-size image (keypoints mapped back), every kept keypoint
// sits on the surface at its pixel.
class SiftDownscale : public ::testing::TestWithParam<int> {};

TEST_P(SiftDownscale, PointsLieOnTheRenderedSurface) {
  const auto k = testing::TestIntrinsics();
  const View view = RenderView();
  const cv::Mat& gray = view.gray;
  SiftOptions options;
  options.downscale = GetParam();
  const SiftFeatures f = ExtractSiftWithDepth(gray, view.depth, k, options);
  ASSERT_GT(f.size(), 100u);
  EXPECT_LE(static_cast<int>(f.size()), f.detected);
  EXPECT_EQ(f.descriptors.rows, static_cast<int>(f.size()));
  for (size_t i = 0; i < f.size(); ++i) {
    const Eigen::Vector3d& p = f.points_in_camera[i];
    const float z = view.depth.at<float>(std::lround(f.pixels[i].y), std::lround(f.pixels[i].x));
    EXPECT_NEAR(p.z(), z, 1e-6);
    const Eigen::Vector2d uv = k.Project(p);
    EXPECT_NEAR(uv.x(), f.pixels[i].x, 1e-3);
    EXPECT_NEAR(uv.y(), f.pixels[i].y, 1e-3);
  }
}

INSTANTIATE_TEST_SUITE_P(FullAndHalf, SiftDownscale, ::testing::Values(1, 2));

TEST(ExtractSiftWithDepth, DepthRangeDropsKeypoints) {
  const auto k = testing::TestIntrinsics();
  const View view = RenderView();
  const cv::Mat& gray = view.gray;
  SiftOptions options;
  const size_t all = ExtractSiftWithDepth(gray, view.depth, k, options).size();
  ASSERT_GT(all, 100u);
  options.max_depth = 2.0;
  const SiftFeatures f = ExtractSiftWithDepth(gray, view.depth, k, options);
  // Some keypoints survive (the loop below checks something) and some are dropped.
  ASSERT_GT(f.size(), 10u);
  EXPECT_LT(f.size(), all);
  for (const auto& p : f.points_in_camera) EXPECT_LE(p.z(), 2.0);
  options.min_depth = 10.0;
  options.max_depth = 20.0;
  EXPECT_EQ(ExtractSiftWithDepth(gray, view.depth, k, options).size(), 0u);
}

TEST(ExtractSiftWithDepth, UntexturedViewHasFewKeypoints) {
  const auto k = testing::TestIntrinsics();
  testing::SyntheticScene scene;
  scene.textured = false;
  const auto frame = testing::Render(scene, k, Rigid3d::Identity());
  cv::Mat gray;
  cv::cvtColor(frame.color, gray, cv::COLOR_BGR2GRAY);
  EXPECT_LT(ExtractSiftWithDepth(gray, frame.depth, k, SiftOptions()).size(), 12u);
}

// Descriptors built by hand: query 0 has one clear nearest neighbour; query 1 sits between
// two train descriptors (ratio ~0.9) and passes only the relaxed test.
TEST(MatchSiftRatio, RatioTestAndItsRelaxation) {
  SiftFeatures train, query;
  train.descriptors = (cv::Mat_<float>(3, 2) << 0, 0, 10, 0, 0, 10);
  train.points_in_camera.resize(3);
  query.descriptors = (cv::Mat_<float>(2, 2) << 1, 0, 4.7f, 0);
  query.points_in_camera.resize(2);
  // 0: d = 1 vs 9 (ratio 0.11); 1: d = 4.7 vs 5.3 (ratio 0.89).
  std::vector<SiftMatch> strict = MatchSiftRatio(query, train, 0.55, 0.8, 0);
  ASSERT_EQ(strict.size(), 1u);
  EXPECT_EQ(strict[0].query, 0);
  EXPECT_EQ(strict[0].train, 0);
  // Fewer than 5 matches pass 0.55: relaxed to 0.95, both match.
  std::vector<SiftMatch> relaxed = MatchSiftRatio(query, train, 0.55, 0.95, 5);
  ASSERT_EQ(relaxed.size(), 2u);
  EXPECT_EQ(relaxed[1].query, 1);
  EXPECT_EQ(relaxed[1].train, 0);
}

// The matrix-product distances pick the same matches as a plain double-precision search, on
// SIFT-like descriptors (128 bytes-valued floats) where some queries are noisy copies of a
// train descriptor and the rest are unrelated.
TEST(MatchSiftRatio, SameMatchesAsABruteForceSearch) {
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> byte(0, 255);
  std::normal_distribution<float> noise(0.0f, 6.0f);
  SiftFeatures train, query;
  const int nt = 300, nq = 260, dim = 128;
  train.descriptors.create(nt, dim, CV_32F);
  query.descriptors.create(nq, dim, CV_32F);
  for (int i = 0; i < nt; ++i) {
    for (int d = 0; d < dim; ++d) train.descriptors.at<float>(i, d) = static_cast<float>(byte(rng));
  }
  for (int i = 0; i < nq; ++i) {
    for (int d = 0; d < dim; ++d) {
      query.descriptors.at<float>(i, d) =
          i % 2 == 0 ? train.descriptors.at<float>((7 * i) % nt, d) + noise(rng) : static_cast<float>(byte(rng));
    }
  }
  train.points_in_camera.resize(nt);
  query.points_in_camera.resize(nq);
  const double ratio = 0.8;
  std::vector<SiftMatch> expected;
  for (int i = 0; i < nq; ++i) {
    double first = 1e300, second = 1e300;
    int best = -1;
    for (int j = 0; j < nt; ++j) {
      double d2 = 0;
      for (int d = 0; d < dim; ++d) {
        const double e = double{query.descriptors.at<float>(i, d)} - train.descriptors.at<float>(j, d);
        d2 += e * e;
      }
      if (d2 < first) {
        second = first;
        first = d2;
        best = j;
      } else if (d2 < second) {
        second = d2;
      }
    }
    if (std::sqrt(first) < ratio * std::sqrt(second)) expected.push_back({i, best});
  }
  const std::vector<SiftMatch> got = MatchSiftRatio(query, train, ratio, ratio, 0);
  ASSERT_EQ(got.size(), expected.size());
  EXPECT_EQ(got.size(), static_cast<size_t>(nq / 2));  // the noisy copies, and nothing else
  for (size_t k = 0; k < got.size(); ++k) {
    EXPECT_EQ(got[k].query, expected[k].query);
    EXPECT_EQ(got[k].train, expected[k].train);
    EXPECT_EQ(got[k].train, (7 * got[k].query) % nt);
  }
}

}  // namespace
}  // namespace f2c
