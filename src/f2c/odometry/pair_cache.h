#pragma once
// On-disk cache of pairwise alignments (JSON), keyed by a hash of everything a pair's
// result depends on: both frames' file bytes, intrinsics, depth decoding, options.

#include <atomic>
#include <filesystem>
#include <map>
#include <mutex>
#include <string>

#include "f2c/io/sequence.h"

namespace f2c {

struct PairAlignment;

class PairCache {
 public:
  // An empty path disables the cache. A cache file that cannot be parsed or of another
  // version is ignored with a warning (it is only a cache) and rewritten on Save(); so is a
  // pair that fails the checksum stored with it (one warning for the file). InputError when
  // the path is not a regular file.
  PairCache(std::filesystem::path path, std::string context);

  bool enabled() const { return !path_.empty(); }
  std::string Key(uint64_t prev_frame_hash, uint64_t curr_frame_hash) const;
  bool Lookup(const std::string& key, PairAlignment* pair) const;
  void Store(const std::string& key, const PairAlignment& pair);
  // Writes the file atomically (no-op when disabled or unchanged).
  void Save();

 private:
  std::filesystem::path path_;
  uint64_t context_hash_ = 0;
  std::map<std::string, std::string> entries_;  // key -> serialised PairAlignment (JSON)
  bool dirty_ = false;
  mutable std::atomic<bool> warned_{false};  // a damaged entry was reported
};

}  // namespace f2c
