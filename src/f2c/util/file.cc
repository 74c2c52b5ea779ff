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

void WriteFileAtomic(const fs::path& path, std::string_view content) {
  static std::atomic<int> counter{0};
  const fs::path tmp = path.string() + fmt::format(".tmp.{}.{}", static_cast<long>(getpid()), counter++);
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) ThrowInputError(path, fmt::format("cannot write ({})", std::strerror(errno)));
    out.write(content.data(), static_cast<std::streamsize>(content.size()));
    out.flush();
    if (!out) {
      std::error_code ignored;
      fs::remove(tmp, ignored);
      ThrowInputError(path, "write failed (disk full?)");
    }
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    ThrowInputError(path, "cannot rename temporary file into place: " + ec.message());
  }
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

uint64_t HashFile(const fs::path& path) {
  const std::string bytes = ReadFileToString(path);
  return XXH3_64bits(bytes.data(), bytes.size());
}

std::string HexString(uint64_t value) { return fmt::format("{:016x}", value); }

}  // namespace f2c
