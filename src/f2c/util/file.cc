#include "f2c/util/file.h"

#include <fmt/format.h>
#include <unistd.h>
#include <xxhash.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <exception>
#include <fstream>
#include <iterator>
#include <sstream>
#include <vector>

#include "f2c/util/error.h"
#include "f2c/util/temp_files.h"

namespace f2c {
namespace fs = std::filesystem;

std::string ReadFileToString(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    if (!fs::exists(path)) ThrowInputError(path, "no such file");
    ThrowInputError(path, "cannot open for reading");
  }
  // One read into a buffer of the file's size (a stream copy grew and copied the buffer
  // several times: a tenth of a frame's decoding). A file that changes size while being read
  // still reads whole: the stream copy takes over for whatever follows.
  std::error_code error;
  const uintmax_t size = fs::file_size(path, error);
  std::string bytes(error ? 0 : static_cast<size_t>(size), '\0');
  in.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (in.bad()) ThrowInputError(path, "read error");
  bytes.resize(static_cast<size_t>(in.gcount()));
  if (in) {
    std::ostringstream rest;
    rest << in.rdbuf();
    bytes += rest.str();
  }
  return bytes;
}

namespace {

// Writes straight into what is not a regular file (a device, a FIFO): it cannot be renamed
// over, and replacing it would destroy it.
void WriteThrough(const fs::path& path, std::string_view content) {
  std::ofstream out(path, std::ios::binary);
  if (!out) ThrowInputError(path, fmt::format("cannot write ({})", std::strerror(errno)));
  out.write(content.data(), static_cast<std::streamsize>(content.size()));
  out.flush();
  if (!out) ThrowInputError(path, fmt::format("write failed ({})", std::strerror(errno)));
}

}  // namespace

void WriteFileAtomic(const fs::path& given, std::string_view content) {
  std::error_code ec;
  const fs::file_status status = fs::status(given, ec);
  if (fs::is_directory(status)) ThrowInputError(given, "is a folder, not a file");
  if (fs::exists(status) && !fs::is_regular_file(status)) return WriteThrough(given, content);
  // Through a symbolic link: the file it names is replaced, the link stays.
  const fs::path path = fs::is_symlink(fs::symlink_status(given, ec)) ? fs::weakly_canonical(given, ec) : given;
  static std::atomic<int> counter{0};
  const TemporaryFileName tmp(TemporaryName(path) + fmt::format(".{}", counter++));
  {
    std::ofstream out(tmp.path(), std::ios::binary | std::ios::trunc);
    if (!out) ThrowInputError(given, fmt::format("cannot write ({})", std::strerror(errno)));
    out.write(content.data(), static_cast<std::streamsize>(content.size()));
    out.flush();
    if (!out) {
      std::error_code ignored;
      fs::remove(tmp.path(), ignored);
      ThrowInputError(given, "write failed (disk full?)");
    }
  }
  fs::rename(tmp.path(), path, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(tmp.path(), ignored);
    ThrowInputError(given, "cannot rename temporary file into place: " + ec.message());
  }
}

void CheckCacheFile(const fs::path& path) {
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (!fs::exists(status) || fs::is_regular_file(status)) return;
  ThrowInputError(path, fs::is_directory(status) ? "cache is a folder, not a file"
                                                 : "cache is not a regular file (a device, FIFO or socket)");
}

void EnsureWritableDirectory(const fs::path& dir) {
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec)) {
    ThrowInputError(dir, "exists and is not a folder");
  }
  fs::create_directories(dir, ec);
  if (ec) ThrowInputError(dir, "cannot create output folder: " + ec.message());
  const fs::path probe = dir / fmt::format(".f2c-write-probe.{}", static_cast<long>(getpid()));
  {
    std::ofstream out(probe);
    if (!out) ThrowInputError(dir, "output folder is not writable");
  }
  fs::remove(probe, ec);
}

OutputFolder::OutputFolder(const fs::path& dir) : dir_(dir), exceptions_(std::uncaught_exceptions()) {
  std::error_code ec;
  existed_ = fs::exists(dir_, ec);
  if (existed_ && fs::is_directory(dir_, ec)) {
    for (auto it = fs::recursive_directory_iterator(dir_, ec); !ec && it != fs::recursive_directory_iterator();
         it.increment(ec)) {
      if (it->is_directory(ec)) folders_before_.insert(it->path());
    }
  }
  EnsureWritableDirectory(dir_);
  RemoveStaleTemporaries(dir_);  // of runs killed where no handler could remove them
}

OutputFolder::~OutputFolder() {
  if (std::uncaught_exceptions() <= exceptions_) return;
  std::error_code ec;
  std::vector<fs::path> made;
  for (auto it = fs::recursive_directory_iterator(dir_, ec); !ec && it != fs::recursive_directory_iterator();
       it.increment(ec)) {
    std::error_code type_ec;
    if (it->is_directory(type_ec) && !folders_before_.count(it->path())) made.push_back(it->path());
  }
  // Deepest first, so a folder whose only content was an empty folder goes too. remove()
  // deletes a folder only when it is empty.
  std::sort(made.begin(), made.end(), [](const fs::path& a, const fs::path& b) {
    return std::distance(a.begin(), a.end()) > std::distance(b.begin(), b.end());
  });
  for (const fs::path& folder : made) fs::remove(folder, ec);
  if (!existed_) fs::remove(dir_, ec);
}

uint64_t Fnv1a64(std::string_view bytes, uint64_t seed) {
  uint64_t hash = seed;
  for (unsigned char c : bytes) {
    hash ^= c;
    hash *= 0x100000001b3ULL;
  }
  return hash;
}

uint64_t HashFile(const fs::path& path) { return HashBytes(ReadFileToString(path)); }

std::string HexString(uint64_t value) { return fmt::format("{:016x}", value); }

uint64_t HashBytes(std::string_view bytes) { return XXH3_64bits(bytes.data(), bytes.size()); }

std::string CacheDamage(int failing, bool cut) {
  std::string text;
  if (failing > 0) {
    text = fmt::format("has {} {}", failing,
                       failing == 1 ? "entry that fails its checksum" : "entries that fail their checksum");
  }
  if (cut) text += std::string(text.empty() ? "" : " and ") + "is cut short";
  return text;
}

}  // namespace f2c
