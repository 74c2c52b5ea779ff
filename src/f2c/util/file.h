#pragma once
// File helpers: whole-file reads, atomic writes (never a half-written output), content
// hashes for caches.

#include <cstdint>
#include <filesystem>
#include <set>
#include <string>
#include <string_view>

namespace f2c {

// Reads a whole file; InputError naming the file when it cannot be read.
std::string ReadFileToString(const std::filesystem::path& path);

// Writes `content` to a temporary file beside `path` and renames it into place, so a
// reader (or a crash) never sees a partial file; a symbolic link keeps pointing at the new
// file. What is not a regular file is never replaced: a device or FIFO (/dev/null,
// /dev/stdout, a pipe) is written through, a folder is refused. InputError naming the path
// on failure (a full disk or device included).
void WriteFileAtomic(const std::filesystem::path& path, std::string_view content);

// A cache file must be a regular file or absent: InputError naming it when it is a folder,
// a device, a FIFO or a link to one (a cache read from /dev/zero never ends).
void CheckCacheFile(const std::filesystem::path& path);

// Creates `dir` (and parents) and checks that a file can be created in it; InputError
// naming the folder otherwise.
void EnsureWritableDirectory(const std::filesystem::path& dir);

// A command's output folder, made writable on construction (EnsureWritableDirectory). When
// the command leaves by an exception (a corrupt image found mid-run), the destructor removes
// the folders it made that are still empty: subfolders that were not there before, and the
// output folder itself when it was not. Files are never removed (each is written whole, so a
// finished cache stays valid), nor a folder that holds anything.
class OutputFolder {
 public:
  explicit OutputFolder(const std::filesystem::path& dir);
  ~OutputFolder();
  OutputFolder(const OutputFolder&) = delete;
  OutputFolder& operator=(const OutputFolder&) = delete;

 private:
  std::filesystem::path dir_;
  bool existed_ = false;
  std::set<std::filesystem::path> folders_before_;
  int exceptions_ = 0;  // std::uncaught_exceptions() when made
};

// 64-bit FNV-1a: stable across runs, platforms and compilers (unlike std::hash), which is
// what a cache key on disk needs.
uint64_t Fnv1a64(std::string_view bytes, uint64_t seed = 0xcbf29ce484222325ULL);
// Hash of a file's bytes (XXH3, 64 bits: stable across platforms like FNV-1a, and about ten
// times faster on the megabytes of a frame's images, which every cached run hashes);
// InputError if it cannot be read.
uint64_t HashFile(const std::filesystem::path& path);
std::string HexString(uint64_t value);
// XXH3 (64 bits) of bytes in memory: the caches' checksums.
uint64_t HashBytes(std::string_view bytes);

// What a cache reader found damaged, for its one warning: "has 2 entries that fail their
// checksum", "is cut short", or both joined by "and"; empty when nothing was.
std::string CacheDamage(int entries_failing_checksum, bool cut_short);

}  // namespace f2c
