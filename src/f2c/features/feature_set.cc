#include "f2c/features/feature_set.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <cstring>
#include <map>
#include <mutex>
#include <string_view>
#include <fstream>
#include <unordered_map>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include "f2c/features/feature_codec.h"
#include "f2c/io/image.h"
#include "f2c/util/error.h"
#include "f2c/util/fields_json.h"
#include "f2c/util/file.h"
#include "f2c/util/progress.h"
#include "f2c/util/temp_files.h"
#include "f2c/util/timer.h"

namespace f2c {
namespace {

constexpr char kMagic[8] = {'F', '2', 'C', 'F', 'E', 'A', 'T', '\0'};
// 2: proxies' noise covariance; 3: each entry followed by its checksum (XXH3 of its key and
// body), so a bit flip or an edit is found, not read as features; 4: features packed at the
// cache's precision (feature_codec.h), 18 bytes instead of 41.
constexpr uint32_t kVersion = 4;

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
  size_t at() const { return at_; }
  std::string_view Since(size_t from) const { return bytes_.substr(from, at_ - from); }

 private:
  void Need(size_t n) {
    if (bytes_.size() - at_ < n) Truncated();
  }
  [[noreturn]] void Truncated() { ThrowInputError(path_, "feature cache is truncated or corrupt"); }
  std::filesystem::path path_;
  std::string_view bytes_;  // owned by the caller
  size_t at_ = 0;
};

constexpr size_t kProxyBytes = 4 * (3 + 1 + 3 + 6 + 6 + 2 + 1) + 4;
constexpr size_t kRunBytes = 1 + 4;  // a run of features of one type: type, count

// Features are grouped by type: runs of (type, count) instead of a type per feature.
std::vector<std::pair<uint8_t, uint32_t>> TypeRuns(const std::vector<Feature>& features) {
  std::vector<std::pair<uint8_t, uint32_t>> runs;
  for (const Feature& x : features) {
    const auto type = static_cast<uint8_t>(x.type);
    if (runs.empty() || runs.back().first != type) runs.emplace_back(type, 0);
    ++runs.back().second;
  }
  return runs;
}

void PutFrame(Writer& w, const FrameFeatures& f) {
  w.Put(static_cast<uint16_t>(std::min<size_t>(f.note.size(), 65535)));
  w.PutBytes(f.note.substr(0, 65535));
  w.Put(static_cast<uint32_t>(f.proxies.size()));
  for (const PlanarProxy& p : f.proxies) {
    w.PutFloats(p.normal.data(), 3);
    w.Put(p.offset);
    w.PutFloats(p.centroid.data(), 3);
    for (const Eigen::Matrix3f* c : {&p.covariance, &p.noise}) {
      const float upper[6] = {(*c)(0, 0), (*c)(0, 1), (*c)(0, 2), (*c)(1, 1), (*c)(1, 2), (*c)(2, 2)};
      w.PutFloats(upper, 6);
    }
    w.PutFloats(p.extent.data(), 2);
    w.Put(p.rms);
    w.Put(p.inliers);
  }
  const FeatureGrids grids = ChooseGrids(f.features);
  w.Put(grids.position_exponent);
  w.Put(grids.pixel_exponent);
  const auto runs = TypeRuns(f.features);
  w.Put(static_cast<uint32_t>(runs.size()));
  for (const auto& [type, count] : runs) {
    w.Put(type);
    w.Put(count);
  }
  w.Put(static_cast<uint32_t>(f.features.size()));
  for (const Feature& x : f.features) {
    const PackedFeature p = Pack(x, grids);
    for (int16_t v : p.position) w.Put(v);
    for (int16_t v : p.direction) w.Put(v);
    w.Put(p.salience);
    w.Put(p.proxy);
    for (int16_t v : p.pixel) w.Put(v);
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
    for (Eigen::Matrix3f* c : {&p.covariance, &p.noise}) {
      float u[6];
      r.GetFloats(u, 6);
      *c << u[0], u[1], u[2], u[1], u[3], u[4], u[2], u[4], u[5];
    }
    r.GetFloats(p.extent.data(), 2);
    p.rms = r.Get<float>();
    p.inliers = r.Get<int32_t>();
  }
  FeatureGrids grids;
  grids.position_exponent = r.Get<int8_t>();
  grids.pixel_exponent = r.Get<int8_t>();
  if (grids.position_exponent > 20 || grids.pixel_exponent > 3) {
    ThrowInputError(path, fmt::format("feature cache has a grid of 2^{} m or 2^{} pixels (at most 2^-20 and 2^-3)",
                                      -grids.position_exponent, -grids.pixel_exponent));
  }
  const uint32_t runs = r.GetCount(kRunBytes);
  uint64_t in_runs = 0;
  std::vector<std::pair<uint8_t, uint32_t>> type_runs(runs);
  for (auto& [type, count] : type_runs) {
    type = r.Get<uint8_t>();
    count = r.Get<uint32_t>();
    if (type >= kFeatureTypeCount)
      ThrowInputError(path, fmt::format("feature cache has an unknown feature type {}", type));
    in_runs += count;
  }
  const uint32_t features = r.GetCount(kPackedFeatureBytes);
  if (in_runs != features) {
    ThrowInputError(path, fmt::format("feature cache lists {} features by type but holds {}", in_runs, features));
  }
  f.features.reserve(features);
  for (const auto& [type, count] : type_runs) {
    for (uint32_t k = 0; k < count; ++k) {
      PackedFeature p;
      for (int16_t& v : p.position) v = r.Get<int16_t>();
      for (int16_t& v : p.direction) v = r.Get<int16_t>();
      p.salience = r.Get<uint16_t>();
      p.proxy = r.Get<int16_t>();
      for (int16_t& v : p.pixel) v = r.Get<int16_t>();
      if (p.proxy < -1 || p.proxy >= static_cast<int32_t>(proxies)) {
        ThrowInputError(path, fmt::format("feature cache refers to proxy {} of {}", p.proxy, proxies));
      }
      if (p.salience > 32768) {
        ThrowInputError(path, fmt::format("feature cache has a salience of {:.6f} (at most 1)", p.salience / 32768.0));
      }
      f.features.push_back(Unpack(p, static_cast<FeatureType>(type), grids));
    }
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
    Writer entry;
    entry.Put(e.key);
    PutFrame(entry, e.features);
    w.PutBytes(entry.bytes());
    w.Put(HashBytes(entry.bytes()));
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
  for (uint32_t i = 0; i < n; ++i) {
    FeatureCacheEntry& e = entries[i];
    const size_t start = r.at();
    e.key = r.Get<uint64_t>();
    e.features = GetFrame(r, path);
    const uint64_t sum = HashBytes(r.Since(start));
    if (r.Get<uint64_t>() != sum) ThrowInputError(path, fmt::format("feature cache entry {} fails its checksum", i));
  }
  if (!r.AtEnd()) ThrowInputError(path, "feature cache has trailing bytes");
  return entries;
}

// The new cache, streamed: header first (its count patched at the end), then the frames'
// entries in frame order, so the file is the same whatever the threads did. Frames arrive
// nearly in order (the odometry's chunks, the extraction's parallel loop); the few that come
// early wait, serialised, until their predecessors are written. Renamed into place when
// complete, removed if the run ends early.
class FeatureExtraction::CacheWriter {
 public:
  CacheWriter(std::filesystem::path path, uint64_t context) : path_(std::move(path)), tmp_(TemporaryName(path_)) {
    std::filesystem::create_directories(path_.parent_path().empty() ? "." : path_.parent_path());
    file_ = std::fopen(tmp_.path().c_str(), "wb");
    if (file_ == nullptr) ThrowInputError(path_, "cannot write feature cache");
    Writer w;
    w.PutBytes(std::string(kMagic, sizeof(kMagic)));
    w.Put(kVersion);
    w.Put(context);
    w.Put(static_cast<uint32_t>(0));  // count, patched by Commit()
    Write(w.bytes());
  }
  ~CacheWriter() {
    if (file_ != nullptr) {
      std::fclose(file_);
      std::filesystem::remove(tmp_.path());
    }
  }
  void Append(int frame, uint64_t key, const FrameFeatures& f) {
    Writer w;
    w.Put(key);
    PutFrame(w, f);
    w.Put(HashBytes(w.bytes()));
    std::lock_guard<std::mutex> lock(mutex_);
    waiting_[frame] = w.bytes();
    for (auto it = waiting_.begin(); it != waiting_.end() && it->first == next_; it = waiting_.erase(it), ++next_) {
      Write(it->second);
      ++count_;
    }
  }
  void Commit() {
    F2C_CHECK(waiting_.empty(), "every frame's features reached the cache");
    std::fseek(file_, sizeof(kMagic) + 4 + 8, SEEK_SET);
    const uint32_t count = count_;
    std::fwrite(&count, sizeof(count), 1, file_);
    const bool ok = std::fflush(file_) == 0 && !std::ferror(file_);
    std::fclose(file_);
    file_ = nullptr;
    std::error_code ec;
    if (ok) std::filesystem::rename(tmp_.path(), path_, ec);
    if (!ok || ec) {
      std::filesystem::remove(tmp_.path(), ec);
      ThrowInputError(path_, "cannot write feature cache");
    }
  }

 private:
  void Write(const std::string& bytes) {
    if (std::fwrite(bytes.data(), 1, bytes.size(), file_) != bytes.size())
      ThrowInputError(path_, "cannot write feature cache");
  }
  std::filesystem::path path_;
  TemporaryFileName tmp_;  // removed by a signal that stops the run
  std::FILE* file_ = nullptr;
  std::mutex mutex_;
  std::map<int, std::string> waiting_;  // entries of frames that came before their turn
  int next_ = 0;
  uint32_t count_ = 0;
};

namespace {

// Reads one cache entry from `in` into `entry` (its key, note, proxies and features) and
// checks the checksum that follows it. kEnd at the end of the file, kDamaged at a short read
// (the rest of the file cannot be framed) or a checksum that does not match.
enum class EntryRead { kOk, kEnd, kDamaged, kShort };
EntryRead ReadEntry(std::ifstream& in, uint64_t file_size, std::string* entry) {
  entry->clear();
  auto take = [&](size_t n) {
    // A damaged count must not allocate more than the file holds.
    const auto position = static_cast<uint64_t>(std::max<std::streamoff>(in.tellg(), 0));
    if (!in || n > file_size - std::min(position, file_size)) return false;
    const size_t at = entry->size();
    entry->resize(at + n);
    return static_cast<bool>(in.read(entry->data() + at, static_cast<std::streamsize>(n)));
  };
  auto count = [&](auto* value) {
    if (!take(sizeof(*value))) return false;
    std::memcpy(value, entry->data() + entry->size() - sizeof(*value), sizeof(*value));
    return true;
  };
  uint64_t key = 0, sum = 0;
  if (in.peek() == std::char_traits<char>::eof()) return EntryRead::kEnd;
  if (!count(&key)) return EntryRead::kShort;
  uint16_t note = 0, grids = 0;
  uint32_t proxies = 0, runs = 0, features = 0;
  const bool framed = count(&note) && take(note) && count(&proxies) &&
                      take(static_cast<size_t>(proxies) * kProxyBytes) && count(&grids) && count(&runs) &&
                      take(static_cast<size_t>(runs) * kRunBytes) && count(&features) &&
                      take(static_cast<size_t>(features) * kPackedFeatureBytes);
  if (!framed || !in.read(reinterpret_cast<char*>(&sum), sizeof(sum))) return EntryRead::kShort;
  return sum == HashBytes(*entry) ? EntryRead::kOk : EntryRead::kDamaged;
}

}  // namespace

FeatureExtraction::~FeatureExtraction() = default;

FeatureExtraction::FeatureExtraction(const RgbdSequence& seq, const FeatureOptions& options, const FeatureRun& run)
    : seq_(seq), options_(options), run_(run) {
  options.Check();
  RequireIntrinsics(seq);
  const int n = static_cast<int>(seq.frames.size());
  set_.frames.resize(n);
  state_.assign(n, kMissing);
  keys_.assign(n, 0);
  notes_.resize(n);
  empty_.assign(n, 0);
  context_ = Fnv1a64(CacheContext(seq, FieldsToJson(options).dump()));
  if (!run.cache_file.empty()) ReadCache();
  setup_s_ = wall_.Seconds();
}

void FeatureExtraction::Deliver(int frame, FrameFeatures&& f) {
  for (const Feature& x : f.features) ++tally_[static_cast<int>(x.type)];
  tally_[kFeatureTypeCount] += static_cast<long>(f.proxies.size());
  notes_[frame] = f.note;
  empty_[frame] = f.features.empty();
  if (writer_) writer_->Append(frame, keys_[frame], f);
  if (run_.on_frame) {
    run_.on_frame(frame, std::move(f));
  } else {
    set_.frames[frame] = std::move(f);
  }
}

void FeatureExtraction::ReadCache() {
  const int n = static_cast<int>(seq_.frames.size());
  Timer timer;
  tbb::parallel_for(0, n,
                    [&](int i) { keys_[i] = HashFrameDepth(seq_.frames[i]) ^ (context_ * 0x9E3779B97F4A7C15ULL); });
  timings_.hashing = timer.Seconds();
  std::unordered_map<uint64_t, std::vector<int>> frames_of;  // frames with identical bytes share a key
  for (int i = 0; i < n; ++i) frames_of[keys_[i]].push_back(i);
  // Pass 1: which frames the cache holds, each entry checked against its checksum. The cache
  // is streamed, never held whole: 45 KB per frame is 0.7 GB at 15,000 frames.
  std::vector<char> hit(n, 0);
  const std::filesystem::path& path = run_.cache_file;
  CheckCacheFile(path);
  std::error_code size_error;
  const uint64_t file_size = std::filesystem::exists(path) ? std::filesystem::file_size(path, size_error) : 0;
  bool version_noted = false;
  auto open = [&](std::ifstream& in) -> bool {
    in.open(path, std::ios::binary);
    char magic[sizeof(kMagic)];
    uint32_t version = 0, count = 0;
    uint64_t context = 0;
    if (!in.read(magic, sizeof(magic)) || std::string(magic, sizeof(magic)) != std::string(kMagic, sizeof(kMagic))) {
      spdlog::warn("{}: not a fine2coarse feature cache (recomputing)", path.string());
      return false;
    }
    in.read(reinterpret_cast<char*>(&version), 4);
    in.read(reinterpret_cast<char*>(&context), 8);
    in.read(reinterpret_cast<char*>(&count), 4);
    if (in && version != kVersion && !version_noted) {
      // A cache an older build wrote: expected after an upgrade, and said once.
      spdlog::info("{}: feature cache version {} (this build reads version {}): recomputing", path.string(), version,
                   kVersion);
      version_noted = true;
    }
    return in && version == kVersion && context == context_;
  };
  int damaged = 0;
  bool cut = false;
  std::string entry;
  if (std::filesystem::exists(path)) {
    std::ifstream in;
    if (open(in)) {
      for (EntryRead read; (read = ReadEntry(in, file_size, &entry)) != EntryRead::kEnd;) {
        if (read == EntryRead::kShort) {
          cut = true;
          break;
        }
        if (read == EntryRead::kDamaged) {
          ++damaged;
          continue;
        }
        uint64_t key = 0;
        std::memcpy(&key, entry.data(), sizeof(key));
        const auto it = frames_of.find(key);
        if (it != frames_of.end()) {
          for (int i : it->second) hit[i] = 1;
        }
      }
    }
  }
  if (damaged > 0 || cut) {
    spdlog::warn("{}: feature cache {} (recomputing those frames)", path.string(), CacheDamage(damaged, cut));
  }
  const int hits = static_cast<int>(std::count(hit.begin(), hit.end(), 1));
  if (hits < n) writer_ = std::make_unique<CacheWriter>(path, context_);
  if (hits == 0) return;
  // Pass 2: hand over the frames it holds (and copy them into the new cache, if one is
  // written).
  std::ifstream in;
  if (!open(in)) return;
  // Only entries that passed their checksum in pass 1 are delivered; the writer exists unless
  // every frame was a hit, so whatever is delivered also reaches the new cache.
  for (EntryRead read; (read = ReadEntry(in, file_size, &entry)) != EntryRead::kEnd && read != EntryRead::kShort;) {
    if (read != EntryRead::kOk) continue;
    uint64_t key = 0;
    std::memcpy(&key, entry.data(), sizeof(key));
    const auto it = frames_of.find(key);
    if (it == frames_of.end() || state_[it->second.front()] != kMissing) continue;
    try {
      Reader r(path, std::string_view(entry).substr(sizeof(key)));
      FrameFeatures f = GetFrame(r, path);
      for (size_t k = 0; k < it->second.size(); ++k) {
        const int i = it->second[k];
        state_[i] = kCached;
        Deliver(i, k + 1 < it->second.size() ? FrameFeatures(f) : std::move(f));
      }
    } catch (const InputError& e) {
      spdlog::warn("{} (recomputing)", e.what());  // a well-framed entry with a bad value: only a cache
    }
  }
  timings_.frames_cached = static_cast<int>(std::count(state_.begin(), state_.end(), kCached));
  if (timings_.frames_cached > 0) {
    spdlog::info("features: {} of {} frames from cache {}", timings_.frames_cached, n, path.string());
  }
}

void FeatureExtraction::Compute(int frame, const cv::Mat& depth) {
  if (state_[frame] != kMissing) return;
  Timer extract;
  FrameFeatures f = ExtractFrameFeatures(depth, *seq_.intrinsics, options_);
  RoundToCachePrecision(&f);  // what the cache gives back: a cached run is the same run
  extract_ns_ += static_cast<int64_t>(extract.Seconds() * 1e9);
  state_[frame] = kComputed;
  Deliver(frame, std::move(f));
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
  std::map<std::string, bool> empty;                 // note -> some frame with it has no features
  for (int i = 0; i < n; ++i) {
    if (state_[i] != kComputed || notes_[i].empty()) continue;
    auto [it, inserted] = notes.try_emplace(notes_[i], 0, i);
    ++it->second.first;
    empty[notes_[i]] = empty[notes_[i]] || empty_[i];
  }
  for (const auto& [note, where] : notes) {
    spdlog::log(empty[note] ? spdlog::level::warn : spdlog::level::info, "features: {} in {} frame(s), first {}", note,
                where.first, seq_.frames[where.second].depth_path.string());
  }
  timings_.frames_computed = n - timings_.frames_cached;
  if (writer_) {
    writer_->Commit();
    writer_.reset();
  }
  timings_.decode = decode_ns * 1e-9;
  timings_.extract = extract_ns_ * 1e-9;
  // The set-up and Finish(); not the time in between, when others (the odometry) may have
  // called Compute().
  timings_.wall = setup_s_ + finish.Seconds();
  if (timings) *timings = timings_;
  return std::move(set_);
}

nlohmann::json FeatureExtraction::Statistics() const {
  const int n = static_cast<int>(seq_.frames.size());
  const double frames = std::max(1, n);
  nlohmann::json per_frame = {{"proxies", tally_[kFeatureTypeCount] / frames}};
  nlohmann::json totals = {{"proxies", tally_[kFeatureTypeCount].load()}};
  long features = 0;
  for (int t = 0; t < kFeatureTypeCount; ++t) {
    per_frame[FeatureTypeName(static_cast<FeatureType>(t))] = tally_[t] / frames;
    totals[FeatureTypeName(static_cast<FeatureType>(t))] = tally_[t].load();
    features += tally_[t];
  }
  per_frame["features"] = features / frames;
  totals["features"] = features;
  const long notes = std::count_if(notes_.begin(), notes_.end(), [](const std::string& s) { return !s.empty(); });
  return {{"frames", n}, {"frames_with_note", notes}, {"per_frame", per_frame}, {"totals", totals}};
}

FeatureSet ExtractFeatures(const RgbdSequence& seq, const FeatureOptions& options, const FeatureRun& run,
                           FeatureTimings* timings) {
  FeatureExtraction extraction(seq, options, run);
  return extraction.Finish(timings);
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
