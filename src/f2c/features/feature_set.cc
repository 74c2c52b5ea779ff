#include "f2c/features/feature_set.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <cstring>
#include <map>
#include <mutex>
#include <string_view>
#include <nlohmann/json.hpp>

#include "f2c/io/image.h"
#include "f2c/util/error.h"
#include "f2c/util/file.h"
#include "f2c/util/progress.h"
#include "f2c/util/timer.h"

namespace f2c {
namespace {

constexpr char kMagic[8] = {'F', '2', 'C', 'F', 'E', 'A', 'T', '\0'};
constexpr uint32_t kVersion = 1;

class Writer {
 public:
  template <typename T>
  void Put(const T& value) {
    const size_t at = bytes_.size();
    bytes_.resize(at + sizeof(T));
    std::memcpy(bytes_.data() + at, &value, sizeof(T));
  }
  void PutFloats(const float* values, int n) {
    for (int i = 0; i < n; ++i) Put(values[i]);
  }
  void PutBytes(const std::string& s) { bytes_ += s; }
  const std::string& bytes() const { return bytes_; }

 private:
  std::string bytes_;
};

class Reader {
 public:
  Reader(const std::filesystem::path& path, std::string_view bytes) : path_(path), bytes_(bytes) {}
  template <typename T>
  T Get() {
    Need(sizeof(T));
    T value;
    std::memcpy(&value, bytes_.data() + at_, sizeof(T));
    at_ += sizeof(T);
    return value;
  }
  void GetFloats(float* values, int n) {
    for (int i = 0; i < n; ++i) values[i] = Get<float>();
  }
  std::string GetBytes(size_t n) {
    Need(n);
    std::string s(bytes_.substr(at_, n));
    at_ += n;
    return s;
  }
  // A count that the rest of the file could hold (guards allocations against corrupt data).
  uint32_t GetCount(size_t min_bytes_each) {
    const auto n = Get<uint32_t>();
    if (static_cast<uint64_t>(n) * min_bytes_each > bytes_.size() - at_) Truncated();
    return n;
  }
  bool AtEnd() const { return at_ == bytes_.size(); }

 private:
  void Need(size_t n) {
    if (bytes_.size() - at_ < n) Truncated();
  }
  [[noreturn]] void Truncated() { ThrowInputError(path_, "feature cache is truncated or corrupt"); }
  std::filesystem::path path_;
  std::string_view bytes_;  // owned by the caller
  size_t at_ = 0;
};

constexpr size_t kProxyBytes = 4 * (3 + 1 + 3 + 6 + 2 + 1) + 4;
constexpr size_t kFeatureBytes = 1 + 4 * (3 + 3 + 1) + 4 + 4 * 2;

void PutFrame(Writer& w, const FrameFeatures& f) {
  w.Put(static_cast<uint16_t>(std::min<size_t>(f.note.size(), 65535)));
  w.PutBytes(f.note.substr(0, 65535));
  w.Put(static_cast<uint32_t>(f.proxies.size()));
  for (const PlanarProxy& p : f.proxies) {
    w.PutFloats(p.normal.data(), 3);
    w.Put(p.offset);
    w.PutFloats(p.centroid.data(), 3);
    const Eigen::Matrix3f& c = p.covariance;
    const float cov[6] = {c(0, 0), c(0, 1), c(0, 2), c(1, 1), c(1, 2), c(2, 2)};
    w.PutFloats(cov, 6);
    w.PutFloats(p.extent.data(), 2);
    w.Put(p.rms);
    w.Put(p.inliers);
  }
  w.Put(static_cast<uint32_t>(f.features.size()));
  for (const Feature& x : f.features) {
    w.Put(static_cast<uint8_t>(x.type));
    w.PutFloats(x.position.data(), 3);
    w.PutFloats(x.direction.data(), 3);
    w.Put(x.salience);
    w.Put(x.proxy);
    w.PutFloats(x.pixel.data(), 2);
  }
}

FrameFeatures GetFrame(Reader& r, const std::filesystem::path& path) {
  FrameFeatures f;
  f.note = r.GetBytes(r.Get<uint16_t>());
  const uint32_t proxies = r.GetCount(kProxyBytes);
  f.proxies.resize(proxies);
  for (PlanarProxy& p : f.proxies) {
    r.GetFloats(p.normal.data(), 3);
    p.offset = r.Get<float>();
    r.GetFloats(p.centroid.data(), 3);
    float cov[6];
    r.GetFloats(cov, 6);
    p.covariance << cov[0], cov[1], cov[2], cov[1], cov[3], cov[4], cov[2], cov[4], cov[5];
    r.GetFloats(p.extent.data(), 2);
    p.rms = r.Get<float>();
    p.inliers = r.Get<int32_t>();
  }
  const uint32_t features = r.GetCount(kFeatureBytes);
  f.features.resize(features);
  for (Feature& x : f.features) {
    const auto type = r.Get<uint8_t>();
    if (type >= kFeatureTypeCount) ThrowInputError(path, fmt::format("feature cache has an unknown feature type {}", type));
    x.type = static_cast<FeatureType>(type);
    r.GetFloats(x.position.data(), 3);
    r.GetFloats(x.direction.data(), 3);
    x.salience = r.Get<float>();
    x.proxy = r.Get<int32_t>();
    if (x.proxy < -1 || x.proxy >= static_cast<int32_t>(proxies)) {
      ThrowInputError(path, fmt::format("feature cache refers to proxy {} of {}", x.proxy, proxies));
    }
    r.GetFloats(x.pixel.data(), 2);
  }
  return f;
}

}  // namespace

void WriteFeatureCache(const std::filesystem::path& path, uint64_t context_hash,
                       const std::vector<FeatureCacheEntry>& entries) {
  Writer w;
  w.PutBytes(std::string(kMagic, sizeof(kMagic)));
  w.Put(kVersion);
  w.Put(context_hash);
  w.Put(static_cast<uint32_t>(entries.size()));
  for (const FeatureCacheEntry& e : entries) {
    w.Put(e.key);
    PutFrame(w, e.features);
  }
  std::filesystem::create_directories(path.parent_path().empty() ? "." : path.parent_path());
  WriteFileAtomic(path, w.bytes());
}

std::vector<FeatureCacheEntry> ReadFeatureCache(const std::filesystem::path& path, uint64_t* context_hash) {
  const std::string bytes = ReadFileToString(path);
  Reader r(path, bytes);
  if (r.GetBytes(sizeof(kMagic)) != std::string(kMagic, sizeof(kMagic))) {
    ThrowInputError(path, "not a fine2coarse feature cache");
  }
  const auto version = r.Get<uint32_t>();
  if (version != kVersion) {
    ThrowInputError(path, fmt::format("feature cache version {} (this build reads version {})", version, kVersion));
  }
  *context_hash = r.Get<uint64_t>();
  const uint32_t n = r.GetCount(8 + 2 + 4 + 4);
  std::vector<FeatureCacheEntry> entries(n);
  for (FeatureCacheEntry& e : entries) {
    e.key = r.Get<uint64_t>();
    e.features = GetFrame(r, path);
  }
  if (!r.AtEnd()) ThrowInputError(path, "feature cache has trailing bytes");
  return entries;
}

FeatureExtraction::FeatureExtraction(const RgbdSequence& seq, const FeatureOptions& options, const FeatureRun& run)
    : seq_(seq), options_(options), run_(run) {
  options.Check();
  RequireIntrinsics(seq);
  const int n = static_cast<int>(seq.frames.size());
  set_.frames.resize(n);
  state_.assign(n, kMissing);
  keys_.assign(n, 0);
  context_ = Fnv1a64(CacheContext(seq, ToJson(options).dump()));
  if (!run.cache_file.empty()) ReadCache();
  setup_s_ = wall_.Seconds();
}

void FeatureExtraction::ReadCache() {
  const int n = static_cast<int>(seq_.frames.size());
  Timer timer;
  tbb::parallel_for(0, n, [&](int i) { keys_[i] = HashFile(seq_.frames[i].depth_path) ^ (context_ * 0x9E3779B97F4A7C15ULL); });
  timings_.hashing = timer.Seconds();
  if (!std::filesystem::exists(run_.cache_file)) return;
  try {
    uint64_t file_context = 0;
    std::vector<FeatureCacheEntry> entries = ReadFeatureCache(run_.cache_file, &file_context);
    if (file_context != context_) return;
    std::map<uint64_t, FrameFeatures*> by_key;
    for (FeatureCacheEntry& e : entries) by_key[e.key] = &e.features;
    for (int i = 0; i < n; ++i) {
      const auto it = by_key.find(keys_[i]);
      if (it == by_key.end()) continue;
      set_.frames[i] = *it->second;  // a copy: frames with identical bytes share a key
      state_[i] = kCached;
    }
  } catch (const InputError& e) {
    spdlog::warn("{} (recomputing)", e.what());  // only a cache
  }
  timings_.frames_cached = static_cast<int>(std::count(state_.begin(), state_.end(), kCached));
  if (timings_.frames_cached > 0) {
    spdlog::info("features: {} of {} frames from cache {}", timings_.frames_cached, n, run_.cache_file.string());
  }
}

void FeatureExtraction::Compute(int frame, const cv::Mat& depth) {
  if (state_[frame] != kMissing) return;
  Timer extract;
  set_.frames[frame] = ExtractFrameFeatures(depth, *seq_.intrinsics, options_);
  extract_ns_ += static_cast<int64_t>(extract.Seconds() * 1e9);
  state_[frame] = kComputed;
}

FeatureSet FeatureExtraction::Finish(FeatureTimings* timings) {
  Timer finish;
  const int n = static_cast<int>(seq_.frames.size());
  const int missing = static_cast<int>(std::count(state_.begin(), state_.end(), kMissing));
  Progress progress("features", missing, run_.quiet || missing == 0);
  std::atomic<int64_t> decode_ns{0};
  tbb::parallel_for(0, n, [&](int i) {
    if (state_[i] != kMissing) return;
    Timer decode;
    const cv::Mat depth = LoadDepthMeters(seq_, seq_.frames[i]);
    decode_ns += static_cast<int64_t>(decode.Seconds() * 1e9);
    Compute(i, depth);
    progress.Advance();
  });
  progress.Finish();
  // One log line per kind of note (a scan of a blank wall would otherwise print a line per
  // frame), naming how many frames and the first of them.
  // A warning where frames gave nothing at all, information where they gave some kinds.
  std::map<std::string, std::pair<int, int>> notes;  // note -> (frames, first frame)
  std::map<std::string, bool> empty;                  // note -> some frame with it has no features
  for (int i = 0; i < n; ++i) {
    if (state_[i] != kComputed || set_.frames[i].note.empty()) continue;
    auto [it, inserted] = notes.try_emplace(set_.frames[i].note, 0, i);
    ++it->second.first;
    empty[set_.frames[i].note] = empty[set_.frames[i].note] || set_.frames[i].features.empty();
  }
  for (const auto& [note, where] : notes) {
    spdlog::log(empty[note] ? spdlog::level::warn : spdlog::level::info, "features: {} in {} frame(s), first {}", note,
                where.first, seq_.frames[where.second].depth_path.string());
  }
  timings_.frames_computed = n - timings_.frames_cached;
  if (!run_.cache_file.empty() && timings_.frames_computed > 0) {
    std::vector<FeatureCacheEntry> entries(n);
    for (int i = 0; i < n; ++i) entries[i] = {keys_[i], set_.frames[i]};
    WriteFeatureCache(run_.cache_file, context_, entries);
  }
  timings_.decode = decode_ns * 1e-9;
  timings_.extract = extract_ns_ * 1e-9;
  // The set-up and Finish(); not the time in between, when others (the odometry) may have
  // called Compute().
  timings_.wall = setup_s_ + finish.Seconds();
  if (timings) *timings = timings_;
  return std::move(set_);
}

FeatureSet ExtractFeatures(const RgbdSequence& seq, const FeatureOptions& options, const FeatureRun& run,
                           FeatureTimings* timings) {
  FeatureExtraction extraction(seq, options, run);
  return extraction.Finish(timings);
}

nlohmann::json ToJson(const FeatureOptions& o) {
  return {
      {"grid",
       {{"step", o.grid.step},
        {"min_depth", o.grid.min_depth},
        {"max_depth", o.grid.max_depth},
        {"bilateral", o.grid.bilateral},
        {"bilateral_sigma_depth", o.grid.bilateral_sigma_depth},
        {"bilateral_sigma_pixels", o.grid.bilateral_sigma_pixels},
        {"normal_radius_pixels", o.grid.normal_radius_pixels},
        {"normal_radius", o.grid.normal_radius},
        {"min_normal_points", o.grid.min_normal_points}}},
      {"proxies",
       {{"min_points", o.proxies.min_points},
        {"max_distance", o.proxies.max_distance},
        {"max_normal_angle", o.proxies.max_normal_angle},
        {"max_rms_a", o.proxies.max_rms_a},
        {"max_rms_b", o.proxies.max_rms_b},
        {"max_curvature", o.proxies.max_curvature},
        {"sensor_sigma_a", o.proxies.sensor_sigma_a},
        {"sensor_sigma_b", o.proxies.sensor_sigma_b},
        {"flat_noise_ratio", o.proxies.flat_noise_ratio},
        {"trim_sigmas", o.proxies.trim_sigmas},
        {"min_trim_sigma", o.proxies.min_trim_sigma},
        {"trim_iterations", o.proxies.trim_iterations},
        {"min_width", o.proxies.min_width}}},
      {"min_spacing", o.min_spacing},
      {"edge_jump_fraction", o.edge_jump_fraction},
      {"edge_min_jump", o.edge_min_jump},
      {"edge_max_gap", o.edge_max_gap},
      {"crease_angle", o.crease_angle},
      {"crease_max_gap", o.crease_max_gap},
      {"edge_direction_radius", o.edge_direction_radius},
      {"border_features", o.border_features},
  };
}

nlohmann::json ToJson(const FeatureTimings& t, int frames) {
  const int computed = std::max(1, t.frames_computed);
  return {{"wall_s", t.wall},
          {"decode_cpu_s", t.decode},
          {"extract_cpu_s", t.extract},
          {"hashing_s", t.hashing},
          {"extract_ms_per_frame_per_core", 1000.0 * t.extract / computed},
          {"frames", frames},
          {"frames_computed", t.frames_computed},
          {"frames_cached", t.frames_cached}};
}

nlohmann::json FeatureStatistics(const FeatureSet& set) {
  const double n = std::max<size_t>(1, set.frames.size());
  long proxies = 0, notes = 0;
  long by_type[kFeatureTypeCount] = {};
  for (const FrameFeatures& f : set.frames) {
    proxies += static_cast<long>(f.proxies.size());
    notes += !f.note.empty();
    for (const Feature& x : f.features) ++by_type[static_cast<int>(x.type)];
  }
  nlohmann::json per_frame = {{"proxies", proxies / n}};
  nlohmann::json totals = {{"proxies", proxies}};
  long features = 0;
  for (int t = 0; t < kFeatureTypeCount; ++t) {
    per_frame[FeatureTypeName(static_cast<FeatureType>(t))] = by_type[t] / n;
    totals[FeatureTypeName(static_cast<FeatureType>(t))] = by_type[t];
    features += by_type[t];
  }
  per_frame["features"] = features / n;
  totals["features"] = features;
  return {{"frames", set.frames.size()}, {"frames_with_note", notes}, {"per_frame", per_frame}, {"totals", totals}};
}

}  // namespace f2c
