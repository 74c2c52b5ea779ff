#pragma once
// Features and proxies of a whole sequence, extracted in parallel over frames, and their
// on-disk cache: a compact, versioned binary file (the authors cache theirs as .fcb).
//
// Cache format (little-endian), version 4:
//   "F2CFEAT\0"  u32 version  u64 context hash  u32 frames
//   per frame:   u64 frame key  u16 note length, note bytes
//                u32 proxies,  per proxy:   normal 3f, offset f, centroid 3f,
//                                           covariance 6f (xx xy xz yy yz zz), noise 6f
//                                           (the same), extent 2f,
//                                           rms f, inliers i32
//                i8 position grid exponent, i8 pixel grid exponent (feature_codec.h)
//                u32 runs,     per run:     type u8, features u32 (features come grouped by type)
//                u32 features, per feature: position 3 i16, direction 2 i16 (octahedral),
//                                           salience u16, proxy i16, pixel 2 i16
//                u64 checksum of the entry (XXH3 of its key and body)
// Features are rounded to this precision when extracted (feature_codec.h), so what the cache
// gives back is what a run that computes them uses.
// A frame's key hashes its depth file's bytes with the context (options, intrinsics, depth
// decoding), so frames are reused one by one: other options or another frame selection
// recompute exactly the frames they change.

#include <atomic>
#include <functional>
#include <memory>
#include <mutex>
#include <filesystem>
#include <nlohmann/json_fwd.hpp>
#include <vector>

#include "f2c/features/depth_features.h"
#include "f2c/io/sequence.h"
#include "f2c/util/timer.h"

namespace f2c {

struct FeatureSet {
  std::vector<FrameFeatures> frames;  // one per sequence frame
};

struct FeatureRun {
  std::filesystem::path cache_file;  // empty: no cache
  bool quiet = false;                // no progress bar
  // When set, each frame's features (from the cache or computed) are handed here, from any
  // thread, once per frame, and not kept: Finish() then returns a set of empty frames, and
  // memory stays bounded by what the receiver keeps (the refinement keeps a compact index).
  // The cache is streamed to disk as frames arrive instead of being built in memory.
  std::function<void(int frame, FrameFeatures&& features)> on_frame;
};

struct FeatureTimings {
  double decode = 0;   // seconds of CPU reading depth images (summed over threads)
  double extract = 0;  // seconds of CPU extracting (summed over threads)
  double hashing = 0;  // seconds hashing files for the cache (wall)
  double wall = 0;     // seconds in the extraction's own steps (set-up and Finish)
  int frames_computed = 0;
  int frames_cached = 0;
};

// InputError when the sequence has no intrinsics or a depth image cannot be read. Frames
// without usable depth give empty results with a note (logged), not an error.
FeatureSet ExtractFeatures(const RgbdSequence& sequence, const FeatureOptions& options, const FeatureRun& run,
                           FeatureTimings* timings = nullptr);

// The same in steps, so a stage that decodes depth anyway (the odometry) can hand each
// image over instead of it being decoded twice:
//   FeatureExtraction features(sequence, options, run);   // hashes frames, reads the cache
//   ... features.Compute(i, depth) for frames decoded elsewhere (any thread, distinct i) ...
//   FeatureSet set = features.Finish(&timings);           // decodes and extracts the rest,
//                                                          // writes the cache
class FeatureExtraction {
 public:
  ~FeatureExtraction();
  FeatureExtraction(const RgbdSequence& sequence, const FeatureOptions& options, const FeatureRun& run);
  // Extracts frame `frame` from its decoded depth unless it is cached or done already.
  void Compute(int frame, const cv::Mat& depth);
  FeatureSet Finish(FeatureTimings* timings = nullptr);
  // Per-type totals and per-frame means (as FeatureStatistics), also when streaming.
  nlohmann::json Statistics() const;

 private:
  enum State : char { kMissing, kCached, kComputed };
  void ReadCache();                                   // frame keys, and the frames the cache holds
  void Deliver(int frame, FrameFeatures&& features);  // tally, cache, sink or keep
  class CacheWriter;
  const RgbdSequence& seq_;
  FeatureOptions options_;
  FeatureRun run_;
  FeatureSet set_;
  std::vector<State> state_;
  std::vector<uint64_t> keys_;
  uint64_t context_ = 0;
  FeatureTimings timings_;
  std::atomic<int64_t> extract_ns_{0};
  std::unique_ptr<CacheWriter> writer_;                  // the new cache, streamed (when frames are missing)
  std::vector<std::string> notes_;                       // per frame
  std::vector<char> empty_;                              // per frame: no features at all
  std::atomic<long> tally_[kFeatureTypeCount + 1] = {};  // per type, then proxies
  Timer wall_;
  double setup_s_ = 0;
};

// One cache entry per frame: its key and its features.
struct FeatureCacheEntry {
  uint64_t key = 0;
  FrameFeatures features;
};
void WriteFeatureCache(const std::filesystem::path& path, uint64_t context_hash,
                       const std::vector<FeatureCacheEntry>& entries);
// InputError naming the file when it is not a feature cache, has another version or is
// truncated. `context_hash` receives the header's.
std::vector<FeatureCacheEntry> ReadFeatureCache(const std::filesystem::path& path, uint64_t* context_hash);

nlohmann::json ToJson(const FeatureTimings& timings, int frames);
// Per-type totals and per-frame means of a feature set, for run.json and benchmarks.
nlohmann::json FeatureStatistics(const FeatureSet& set);

}  // namespace f2c
