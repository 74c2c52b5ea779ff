#include "f2c/features/feature_set.h"

#include <gtest/gtest.h>

#include <atomic>
#include <nlohmann/json.hpp>

#include <Eigen/Geometry>
#include <fstream>

#include "f2c/features/feature_codec.h"
#include "f2c/testing/log_capture.h"
#include "f2c/testing/synthetic_scene.h"
#include "f2c/util/file.h"

namespace f2c {
namespace {

namespace fs = std::filesystem;

std::vector<Rigid3d, Eigen::aligned_allocator<Rigid3d>> Poses(int n) {
  std::vector<Rigid3d, Eigen::aligned_allocator<Rigid3d>> poses;
  for (int i = 0; i < n; ++i) {
    Rigid3d pose = Rigid3d::Identity();
    pose.linear() = Eigen::AngleAxisd(-0.4 + 0.05 * i, Eigen::Vector3d::UnitX()).toRotationMatrix();
    pose.translation() = Eigen::Vector3d(0.1 * i, -0.3, -1.0);
    poses.push_back(pose);
  }
  return poses;
}

RgbdSequence WriteSequence(const fs::path& dir, int n) {
  testing::WriteTumSequence(dir, testing::SyntheticScene(), testing::TestIntrinsics(), Poses(n));
  IoOptions io;
  io.intrinsics = "525,525,319.5,239.5";
  return ReadSequence(dir, io);
}

// A run without a progress bar that caches its features in `cache`.
FeatureRun QuietRun(const fs::path& cache) {
  FeatureRun run;
  run.quiet = true;
  run.cache_file = cache;
  return run;
}

void ExpectSameFeatures(const FrameFeatures& a, const FrameFeatures& b) {
  EXPECT_EQ(a.note, b.note);
  ASSERT_EQ(a.proxies.size(), b.proxies.size());
  for (size_t i = 0; i < a.proxies.size(); ++i) {
    const PlanarProxy &p = a.proxies[i], &q = b.proxies[i];
    EXPECT_EQ(p.normal, q.normal);
    EXPECT_EQ(p.offset, q.offset);
    EXPECT_EQ(p.centroid, q.centroid);
    EXPECT_EQ(p.covariance, q.covariance);
    EXPECT_EQ(p.noise, q.noise);
    EXPECT_EQ(p.extent, q.extent);
    EXPECT_EQ(p.rms, q.rms);
    EXPECT_EQ(p.inliers, q.inliers);
  }
  ASSERT_EQ(a.features.size(), b.features.size());
  for (size_t i = 0; i < a.features.size(); ++i) {
    const Feature &x = a.features[i], &y = b.features[i];
    EXPECT_EQ(x.type, y.type);
    EXPECT_EQ(x.position, y.position);
    EXPECT_EQ(x.direction, y.direction);
    EXPECT_EQ(x.salience, y.salience);
    EXPECT_EQ(x.proxy, y.proxy);
    EXPECT_EQ(x.pixel, y.pixel);
  }
}

TEST(FeatureCache, RoundTripsEveryField) {
  const fs::path dir = testing::FreshTempDir("feature_cache_round_trip");
  const CameraIntrinsics k = testing::TestIntrinsics();
  std::vector<FeatureCacheEntry> entries;
  for (const Rigid3d& pose : Poses(2)) {
    entries.push_back({entries.size() + 77, ExtractFrameFeatures(testing::Render({}, k, pose).depth, k, {})});
  }
  entries.push_back({5, ExtractFrameFeatures(cv::Mat::zeros(480, 640, CV_32F), k, {})});  // a note, nothing else
  for (FeatureCacheEntry& e : entries) RoundToCachePrecision(&e.features);  // as the extraction hands them over
  ASSERT_GT(entries[0].features.features.size(), 100u);
  // Exact depth has no noise to estimate: give one proxy a noise covariance of its own.
  ASSERT_FALSE(entries[0].features.proxies.empty());
  entries[0].features.proxies[0].noise << 4e-6f, 1e-6f, -2e-6f, 1e-6f, 5e-6f, 3e-6f, -2e-6f, 3e-6f, 6e-6f;
  WriteFeatureCache(dir / "f.f2cf", 0xABCDEF, entries);
  uint64_t context = 0;
  const std::vector<FeatureCacheEntry> back = ReadFeatureCache(dir / "f.f2cf", &context);
  EXPECT_EQ(context, 0xABCDEFu);
  ASSERT_EQ(back.size(), entries.size());
  for (size_t i = 0; i < back.size(); ++i) {
    EXPECT_EQ(back[i].key, entries[i].key);
    ExpectSameFeatures(back[i].features, entries[i].features);
  }
  EXPECT_EQ(back[2].features.note, "no valid depth");
}

TEST(FeatureCache, BadFilesAreClearErrors) {
  const fs::path dir = testing::FreshTempDir("feature_cache_bad");
  const CameraIntrinsics k = testing::TestIntrinsics();
  FeatureCacheEntry entry{1, ExtractFrameFeatures(testing::Render({}, k, Poses(1)[0]).depth, k, {})};
  RoundToCachePrecision(&entry.features);
  WriteFeatureCache(dir / "good.f2cf", 1, {entry});
  const std::string bytes = ReadFileToString(dir / "good.f2cf");
  WriteFileAtomic(dir / "short.f2cf", bytes.substr(0, bytes.size() - 7));
  WriteFileAtomic(dir / "other.f2cf", "P6\n640 480\n255\n");
  std::string v9 = bytes;
  v9[8] = 9;
  WriteFileAtomic(dir / "v9.f2cf", v9);
  std::string flipped = bytes;
  flipped[bytes.size() - 12] ^= 0x10;  // in the last feature's pixel (the checksum follows)
  WriteFileAtomic(dir / "flipped.f2cf", flipped);
  uint64_t context = 0;
  auto message = [&](const fs::path& p) { return testing::InputErrorMessage([&] { ReadFeatureCache(p, &context); }); };
  EXPECT_EQ(message(dir / "short.f2cf"), (dir / "short.f2cf").string() + ": feature cache is truncated or corrupt");
  EXPECT_EQ(message(dir / "other.f2cf"), (dir / "other.f2cf").string() + ": not a fine2coarse feature cache");
  EXPECT_EQ(message(dir / "v9.f2cf"),
            (dir / "v9.f2cf").string() + ": feature cache version 9 (this build reads version 4)");
  EXPECT_EQ(message(dir / "flipped.f2cf"),
            (dir / "flipped.f2cf").string() + ": feature cache entry 0 fails its checksum");
}

template <typename T>
void Put(std::string* out, const T& v) {
  out->append(reinterpret_cast<const char*>(&v), sizeof(T));
}

// A feature cache of one entry with no note and no proxies: its grid exponents, runs of
// (type, count) and `features` packed features at the camera with no proxy, with a checksum
// that matches.
std::string OneEntryCache(int8_t position_exponent, int8_t pixel_exponent,
                          const std::vector<std::pair<uint8_t, uint32_t>>& runs, uint32_t features,
                          uint16_t salience = 0) {
  std::string entry;
  Put(&entry, uint64_t{1});  // key
  Put(&entry, uint16_t{0});  // note
  Put(&entry, uint32_t{0});  // proxies
  Put(&entry, position_exponent);
  Put(&entry, pixel_exponent);
  Put(&entry, static_cast<uint32_t>(runs.size()));
  for (const auto& [type, count] : runs) {
    Put(&entry, type);
    Put(&entry, count);
  }
  Put(&entry, features);
  for (uint32_t i = 0; i < features; ++i) {
    entry.append(10, '\0');  // position, direction (+z)
    Put(&entry, salience);
    Put(&entry, int16_t{-1});  // no proxy
    entry.append(4, '\0');     // pixel
  }
  std::string file("F2CFEAT\0", 8);
  Put(&file, uint32_t{4});
  Put(&file, uint64_t{1});  // context
  Put(&file, uint32_t{1});
  file += entry;
  Put(&file, HashBytes(entry));
  return file;
}

TEST(FeatureCache, AnEntryWhoseChecksumMatchesButWhoseValuesCannotBeIsAnErrorNamingThem) {
  const fs::path dir = testing::FreshTempDir("feature_cache_values");
  auto message = [&](const std::string& bytes) {
    WriteFileAtomic(dir / "f.f2cf", bytes);
    uint64_t context = 0;
    return testing::InputErrorMessage([&] { ReadFeatureCache(dir / "f.f2cf", &context); });
  };
  const std::string prefix = (dir / "f.f2cf").string() + ": ";
  EXPECT_EQ(message(OneEntryCache(12, 3, {{0, 2}}, 2)), "no error");  // two planes at the camera: fine
  EXPECT_EQ(message(OneEntryCache(12, 3, {{9, 1}}, 1)), prefix + "feature cache has an unknown feature type 9");
  EXPECT_EQ(message(OneEntryCache(12, 3, {{0, 2}}, 1)), prefix + "feature cache lists 2 features by type but holds 1");
  EXPECT_EQ(message(OneEntryCache(12, 3, {{0, 1}}, 1, 32769)),
            prefix + "feature cache has a salience of 1.000031 (at most 1)");
  EXPECT_EQ(message(OneEntryCache(21, 3, {}, 0)),
            prefix + "feature cache has a grid of 2^-21 m or 2^-3 pixels (at most 2^-20 and 2^-3)");
}

TEST(ExtractFeatures, ReusesTheCacheFrameByFrameAndRecomputesWhatChanged) {
  const fs::path dir = testing::FreshTempDir("feature_set_cache");
  const RgbdSequence seq = WriteSequence(dir / "scan", 4);
  const FeatureRun run = QuietRun(dir / "cache" / "features.f2cf");
  FeatureTimings first, second, third;
  const FeatureSet a = ExtractFeatures(seq, FeatureOptions(), run, &first);
  EXPECT_EQ(first.frames_computed, 4);
  EXPECT_EQ(first.frames_cached, 0);
  ASSERT_TRUE(fs::exists(run.cache_file));

  const FeatureSet b = ExtractFeatures(seq, FeatureOptions(), run, &second);
  EXPECT_EQ(second.frames_cached, 4);
  EXPECT_EQ(second.frames_computed, 0);
  for (int i = 0; i < 4; ++i) ExpectSameFeatures(a.frames[i], b.frames[i]);

  // Another frame selection reuses the frames it shares; other options recompute all.
  IoOptions io;
  io.intrinsics = "525,525,319.5,239.5";
  io.first = 2;
  FeatureTimings subset;
  const FeatureSet tail = ExtractFeatures(ReadSequence(dir / "scan", io), FeatureOptions(), run, &subset);
  EXPECT_EQ(subset.frames_cached, 2);
  ExpectSameFeatures(tail.frames[0], a.frames[2]);
  FeatureOptions other;
  other.min_spacing = 0.1;
  ExtractFeatures(seq, other, run, &third);
  EXPECT_EQ(third.frames_cached, 0);
  EXPECT_EQ(third.frames_computed, 4);
}

TEST(ExtractFeatures, ACorruptCacheIsRecomputedAndAMissingIntrinsicIsAnError) {
  const fs::path dir = testing::FreshTempDir("feature_set_corrupt");
  const RgbdSequence seq = WriteSequence(dir / "scan", 2);
  const FeatureRun run = QuietRun(dir / "features.f2cf");
  WriteFileAtomic(run.cache_file, "F2CFEAT");
  FeatureTimings t;
  const FeatureSet set = ExtractFeatures(seq, FeatureOptions(), run, &t);
  EXPECT_EQ(t.frames_computed, 2);
  EXPECT_GT(set.frames[0].features.size(), 100u);
  uint64_t context = 0;
  EXPECT_EQ(ReadFeatureCache(run.cache_file, &context).size(), 2u);  // rewritten

  const RgbdSequence no_k = ReadSequence(dir / "scan");
  EXPECT_EQ(testing::InputErrorMessage([&] { ExtractFeatures(no_k, FeatureOptions(), FeatureRun()); }),
            (dir / "scan").string() +
                ": no intrinsics: pass --intrinsics (a preset: tum-fr1, tum-fr2, tum-fr3, primesense; or fx,fy,cx,cy)");
}

// A cache cut short by one byte, or with one bit flipped, is read up to the damage: the
// damaged frames are recomputed (one warning naming the file), the rest reused, and the
// cache rewritten whole. Without the checksum a flipped bit in a position was read as a
// feature; without the care for the writer a cut cache stopped the run at an internal check.
TEST(ExtractFeatures, ADamagedCacheEntryIsRecomputedWithOneWarning) {
  const fs::path dir = testing::FreshTempDir("feature_set_damaged");
  const RgbdSequence seq = WriteSequence(dir / "scan", 4);
  const FeatureRun run = QuietRun(dir / "features.f2cf");
  const FeatureSet reference = ExtractFeatures(seq, FeatureOptions(), run);
  const std::string good = ReadFileToString(run.cache_file);
  uint64_t context = 0;
  const std::vector<FeatureCacheEntry> entries = ReadFeatureCache(run.cache_file, &context);
  ASSERT_EQ(entries.size(), 4u);
  // Entry 1 starts where a cache of entry 0 alone ends; its first feature's position follows
  // its key, note, proxies (22 floats and a count each), the two grid exponents, the runs of
  // types (a byte and a count each) and the feature count.
  WriteFeatureCache(dir / "one.f2cf", context, {entries[0]});
  const size_t entry1 = ReadFileToString(dir / "one.f2cf").size();
  const FrameFeatures& f1 = entries[1].features;
  ASSERT_FALSE(f1.features.empty());
  size_t runs = 1;
  for (size_t i = 1; i < f1.features.size(); ++i) runs += f1.features[i].type != f1.features[i - 1].type;
  const size_t position = entry1 + 8 + 2 + f1.note.size() + 4 + f1.proxies.size() * (4 * 22 + 4) + 2 + 4 + runs * 5 + 4;
  std::string flipped = good;
  flipped[position + 1] ^= 0x04;
  for (const std::string& damaged : {good.substr(0, good.size() - 1), flipped}) {
    WriteFileAtomic(run.cache_file, damaged);
    testing::LogCapture log;
    FeatureTimings t;
    const FeatureSet set = ExtractFeatures(seq, FeatureOptions(), run, &t);
    EXPECT_EQ(t.frames_cached, 3);
    EXPECT_EQ(t.frames_computed, 1);
    for (int i = 0; i < 4; ++i) ExpectSameFeatures(set.frames[i], reference.frames[i]);
    const std::vector<std::string> lines = log.Lines();
    ASSERT_FALSE(lines.empty());
    EXPECT_EQ(lines[0], run.cache_file.string() + ": feature cache " +
                            (damaged.size() < good.size() ? "is cut short" : "has 1 entry that fails its checksum") +
                            " (recomputing those frames)");
    EXPECT_EQ(ReadFileToString(run.cache_file), good);
  }
}

// A cache that is not a regular file is an error naming it, never read (a device could be
// read for ever) nor replaced.
TEST(ExtractFeatures, ACacheOfAnotherVersionIsRecomputedWithOneLineSayingSo) {
  const fs::path dir = testing::FreshTempDir("feature_set_version");
  const RgbdSequence seq = WriteSequence(dir / "scan", 2);
  const FeatureRun run = QuietRun(dir / "features.f2cf");
  ExtractFeatures(seq, FeatureOptions(), run);
  std::string old = ReadFileToString(run.cache_file);
  old[8] = 3;  // the version that held features as floats
  WriteFileAtomic(run.cache_file, old);
  testing::LogCapture log;
  FeatureTimings t;
  ExtractFeatures(seq, FeatureOptions(), run, &t);
  EXPECT_EQ(t.frames_computed, 2);
  EXPECT_EQ(log.Lines(),
            std::vector<std::string>{run.cache_file.string() +
                                     ": feature cache version 3 (this build reads version 4): recomputing"});
  uint64_t context = 0;
  EXPECT_EQ(ReadFeatureCache(run.cache_file, &context).size(), 2u);  // rewritten at version 4
}

TEST(ExtractFeatures, ACacheThatIsNotARegularFileIsAnError) {
  const fs::path dir = testing::FreshTempDir("feature_set_cache_kind");
  const RgbdSequence seq = WriteSequence(dir / "scan", 2);
  FeatureRun run = QuietRun(dir / "folder.f2cf");
  fs::create_directories(run.cache_file);
  EXPECT_EQ(testing::InputErrorMessage([&] { ExtractFeatures(seq, FeatureOptions(), run); }),
            run.cache_file.string() + ": cache is a folder, not a file");
  run.cache_file = dir / "zero.f2cf";
  fs::create_symlink("/dev/zero", run.cache_file);
  EXPECT_EQ(testing::InputErrorMessage([&] { ExtractFeatures(seq, FeatureOptions(), run); }),
            run.cache_file.string() + ": cache is not a regular file (a device, FIFO or socket)");
  EXPECT_TRUE(fs::is_symlink(run.cache_file));
  EXPECT_TRUE(fs::is_character_file("/dev/zero"));
}

// Streaming: each frame reaches the receiver once, nothing is kept, and the cache written on
// the way (cached frames included) has the same bytes as one written from the whole set.
TEST(ExtractFeatures, StreamedFramesReachTheReceiverOnceAndTheCacheIsTheSame) {
  const fs::path dir = testing::FreshTempDir("feature_set_stream");
  const RgbdSequence seq = WriteSequence(dir / "scan", 5);
  FeatureRun whole;
  whole.quiet = true;
  whole.cache_file = dir / "whole.f2cf";
  const FeatureSet reference = ExtractFeatures(seq, FeatureOptions(), whole);

  FeatureRun streamed = whole;
  streamed.cache_file = dir / "streamed.f2cf";
  std::vector<FrameFeatures> received(5);
  std::atomic<int> calls{0};
  streamed.on_frame = [&](int frame, FrameFeatures&& f) {
    received[frame] = std::move(f);
    ++calls;
  };
  {
    // Two frames cached already: they are streamed from the cache, the rest computed.
    IoOptions io;
    io.intrinsics = "525,525,319.5,239.5";
    io.last = 1;
    FeatureRun prefix = whole;
    prefix.cache_file = streamed.cache_file;
    ExtractFeatures(ReadSequence(dir / "scan", io), FeatureOptions(), prefix);
  }
  FeatureExtraction extraction(seq, FeatureOptions(), streamed);
  FeatureTimings t;
  const FeatureSet left = extraction.Finish(&t);
  EXPECT_EQ(t.frames_cached, 2);
  EXPECT_EQ(calls.load(), 5);
  for (int i = 0; i < 5; ++i) {
    EXPECT_TRUE(left.frames[i].features.empty());
    ExpectSameFeatures(received[i], reference.frames[i]);
  }
  EXPECT_EQ(extraction.Statistics(), FeatureStatistics(reference));
  EXPECT_EQ(ReadFileToString(streamed.cache_file), ReadFileToString(whole.cache_file));
}

}  // namespace
}  // namespace f2c
