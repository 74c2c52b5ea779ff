#include "f2c/odometry/pair_cache.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <nlohmann/json.hpp>

#include "f2c/odometry/odometry.h"
#include "f2c/util/error.h"
#include "f2c/util/file.h"

namespace f2c {
namespace {

// Bumped whenever a pair's answer changes for the same options (3: the photometric step also
// refines the directions the image measures better than the depth; 4: SIFT and tracked pairs
// carry their information; 5: so do ICP fallbacks; 6: with their prior widened by its age;
// 7: each pair stored with a checksum, so an edited or damaged pair is recomputed, not trusted).
constexpr int kCacheVersion = 7;

// XXH3 of a pair's key and its compact JSON text. dump() of what parse() read gives the text
// that was written (keys sorted, numbers in their shortest exact form), so the sum is
// checked on that.
std::string Checksum(const std::string& key, const std::string& pair_json) {
  return HexString(HashBytes(key + pair_json));
}

}  // namespace

PairCache::PairCache(std::filesystem::path path, std::string context)
    : path_(std::move(path)), context_hash_(Fnv1a64(context)) {
  if (!enabled()) return;
  CheckCacheFile(path_);
  if (!std::filesystem::exists(path_)) return;
  try {
    const auto j = nlohmann::json::parse(ReadFileToString(path_));
    if (j.at("version") != kCacheVersion) {  // json equality: no conversion of a damaged number
      spdlog::warn("{}: cache of another version; recomputing", path_.string());
      return;
    }
    int damaged = 0;
    for (const auto& [key, value] : j.at("pairs").items()) {
      std::string pair = value.contains("pair") ? value["pair"].dump() : std::string();
      if (!value.contains("checksum") || value["checksum"] != Checksum(key, pair)) {
        ++damaged;
        continue;
      }
      entries_[key] = std::move(pair);
    }
    if (damaged > 0) {
      spdlog::warn("{}: {} cached {} (edited or damaged); recomputing", path_.string(), damaged,
                   damaged == 1 ? "pair fails its checksum" : "pairs fail their checksum");
    }
  } catch (const std::exception& e) {
    spdlog::warn("{}: unreadable cache ({}); recomputing", path_.string(), e.what());
    entries_.clear();
  }
}

std::string PairCache::Key(uint64_t prev_frame_hash, uint64_t curr_frame_hash) const {
  return HexString(context_hash_ ^ (prev_frame_hash * 0x9E3779B97F4A7C15ULL)) + HexString(curr_frame_hash);
}

bool PairCache::Lookup(const std::string& key, PairAlignment* pair) const {
  const auto it = entries_.find(key);
  if (it == entries_.end()) return false;
  try {
    *pair = PairAlignmentFromJson(nlohmann::json::parse(it->second));
    return true;
  } catch (const std::exception& e) {
    // Recomputed; said once per cache, not once per damaged entry.
    if (!warned_.exchange(true))
      spdlog::warn("{}: a cached pair is damaged ({}); recomputing it", path_.string(), e.what());
    return false;
  }
}

void PairCache::Store(const std::string& key, const PairAlignment& pair) {
  if (!enabled()) return;
  entries_[key] = ToJson(pair).dump();
  dirty_ = true;
}

void PairCache::Save() {
  if (!enabled() || !dirty_) return;
  nlohmann::json pairs = nlohmann::json::object();
  for (const auto& [key, value] : entries_) {
    pairs[key] = {{"checksum", Checksum(key, value)}, {"pair", nlohmann::json::parse(value)}};
  }
  const nlohmann::json j = {{"version", kCacheVersion}, {"pairs", pairs}};
  std::filesystem::create_directories(path_.parent_path());
  WriteFileAtomic(path_, j.dump());
  dirty_ = false;
}

}  // namespace f2c
