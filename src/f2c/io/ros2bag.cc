// ROS 2 bags: a folder with metadata.yaml and its storage file, or the storage file itself,
// SQLite (.db3: tables topics and messages, each message's CDR bytes a blob) or MCAP (records
// with a summary section at the end: schemas, channels and chunk indexes; after each chunk,
// per channel, the log time and offset of each message in the uncompressed chunk). Only the
// index is read when a bag opens; a message's bytes are read when needed. docs/formats.md.

#include <fmt/format.h>
#include <sqlite3.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <map>
#include <memory>
#include <string_view>

#include "f2c/io/block.h"
#include "f2c/io/image.h"
#include "f2c/io/rosbag.h"
#include "f2c/util/error.h"

namespace f2c {
namespace fs = std::filesystem;

namespace {

constexpr std::string_view kSqliteMagic("SQLite format 3\0", 16);
constexpr std::string_view kMcapMagic("\x89MCAP0\r\n", 8);

std::string Head(const fs::path& path, size_t n) {
  std::ifstream in(path, std::ios::binary);
  std::string bytes(n, '\0');
  in.read(bytes.data(), static_cast<std::streamsize>(n));
  bytes.resize(static_cast<size_t>(in.gcount()));
  return bytes;
}

// "sensor_msgs/msg/Image" (ROS 2) -> "sensor_msgs/Image" (ROS 1's name, what the reader asks for).
std::string Ros1Type(std::string type) {
  const size_t at = type.find("/msg/");
  if (at != std::string::npos) type.erase(at, 4);
  return type;
}

// A read-only SQLite connection per thread and file, for the blobs of a .db3's messages.
struct SqliteCache {
  std::string path;
  sqlite3* db = nullptr;
  ~SqliteCache() {
    if (db != nullptr) sqlite3_close(db);
  }
};

sqlite3* OpenReadOnly(const fs::path& path) {
  sqlite3* db = nullptr;
  if (sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY | SQLITE_OPEN_NOMUTEX, nullptr) != SQLITE_OK) {
    const std::string why = db != nullptr ? sqlite3_errmsg(db) : "out of memory";
    sqlite3_close(db);
    ThrowInputError(path, "cannot open the ROS 2 bag database (" + why + ")");
  }
  return db;
}

sqlite3* CachedDb(const fs::path& path) {
  thread_local SqliteCache cache;
  if (cache.db == nullptr || cache.path != path.string()) {
    if (cache.db != nullptr) sqlite3_close(cache.db), cache.db = nullptr;
    cache.db = OpenReadOnly(path);
    cache.path = path.string();
  }
  return cache.db;
}

}  // namespace

namespace {

// `size` bytes at `offset` of row `row`'s message blob (at most what it holds past `offset`
// when `clip`), and the blob's whole size in `*blob_bytes`.
std::string ReadBlob(const fs::path& path, int64_t row, uint64_t offset, uint64_t size, bool clip,
                     uint64_t* blob_bytes) {
  sqlite3* db = CachedDb(path);
  sqlite3_blob* blob = nullptr;
  if (sqlite3_blob_open(db, "main", "messages", "data", row, 0, &blob) != SQLITE_OK) {
    const std::string why = sqlite3_errmsg(db);
    sqlite3_blob_close(blob);
    ThrowInputError(path, fmt::format("message row {}: {}", row, why));
  }
  const uint64_t bytes = static_cast<uint64_t>(sqlite3_blob_bytes(blob));
  *blob_bytes = bytes;
  if (clip && offset <= bytes) size = std::min(size, bytes - offset);
  if (offset > bytes || size > bytes - offset || size > (uint64_t{1} << 31)) {
    sqlite3_blob_close(blob);
    ThrowInputError(path,
                    fmt::format("message row {}: {} bytes at {} lie past its {} bytes", row, size, offset, bytes));
  }
  std::string out(size, '\0');
  const int status = sqlite3_blob_read(blob, out.data(), static_cast<int>(size), static_cast<int>(offset));
  sqlite3_blob_close(blob);
  if (status != SQLITE_OK) ThrowInputError(path, fmt::format("message row {}: {}", row, sqlite3_errstr(status)));
  return out;
}

}  // namespace

std::string ReadSqliteBlob(const fs::path& path, int64_t row, uint64_t offset, uint64_t size) {
  uint64_t blob_bytes = 0;
  return ReadBlob(path, row, offset, size, false, &blob_bytes);
}

namespace rosbag {
namespace {

class Db3 : public Recording {
 public:
  explicit Db3(const fs::path& path) : path_(path) {
    sqlite3* db = OpenReadOnly(path);
    std::unique_ptr<sqlite3, decltype(&sqlite3_close)> guard(db, sqlite3_close);
    auto query = [&](const char* sql, auto&& row) {
      sqlite3_stmt* stmt = nullptr;
      if (sqlite3_prepare_v2(db, sql, -1, &stmt, nullptr) != SQLITE_OK) {
        const std::string why = sqlite3_errmsg(db);
        sqlite3_finalize(stmt);
        ThrowInputError(path, "not a ROS 2 bag database (" + why + ")");
      }
      int status;
      while ((status = sqlite3_step(stmt)) == SQLITE_ROW) row(stmt);
      sqlite3_finalize(stmt);
      if (status != SQLITE_DONE)
        ThrowInputError(path, std::string("damaged ROS 2 bag database (") + sqlite3_errstr(status) + ")");
    };
    auto text = [](sqlite3_stmt* s, int column) {
      const unsigned char* t = sqlite3_column_text(s, column);
      return t == nullptr ? std::string() : std::string(reinterpret_cast<const char*>(t));
    };
    query("SELECT id, name, type, serialization_format FROM topics", [&](sqlite3_stmt* s) {
      Connection c;
      c.id = static_cast<uint32_t>(sqlite3_column_int64(s, 0));
      c.topic = text(s, 1);
      // Only CDR messages are read: a topic in another serialisation has no type we know.
      c.type = text(s, 3) == "cdr" ? Ros1Type(text(s, 2)) : "";
      connections_.push_back(c);
    });
    query("SELECT id, topic_id, timestamp FROM messages ORDER BY timestamp, id", [&](sqlite3_stmt* s) {
      MessageRef m;
      m.row = sqlite3_column_int64(s, 0);
      m.connection = static_cast<uint32_t>(sqlite3_column_int64(s, 1));
      m.time = static_cast<double>(sqlite3_column_int64(s, 2)) * 1e-9;
      messages_.push_back(m);
    });
  }
  const fs::path& path() const override { return path_; }
  const std::vector<Connection>& connections() const override { return connections_; }
  std::vector<MessageRef> Messages(const std::string& topic) const override {
    return MessagesOn(connections_, messages_, topic);
  }
  MessageData Read(const MessageRef& message, uint64_t max_bytes) const override {
    MessageData out;
    out.sqlite_row = message.row;
    out.bytes = ReadBlob(path_, message.row, 0, max_bytes == 0 ? UINT64_MAX : max_bytes, true, &out.size);
    return out;
  }
  bool cdr() const override { return true; }
  std::string format() const override { return "format: ROS 2 bag (SQLite .db3, CDR)"; }

 private:
  fs::path path_;
  std::vector<Connection> connections_;
  std::vector<MessageRef> messages_;
};

// Little-endian fields of MCAP records, bounded by their record.
class Fields {
 public:
  Fields(std::string bytes, std::string where) : b_(std::move(bytes)), where_(std::move(where)) {}
  template <class T>
  T Get() {
    Need(sizeof(T));
    T v;
    std::memcpy(&v, b_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }
  std::string String() {
    const uint32_t n = Get<uint32_t>();
    Need(n);
    std::string s = b_.substr(pos_, n);
    pos_ += n;
    return s;
  }
  void Skip(uint64_t n) { Need(n), pos_ += n; }
  uint64_t position() const { return pos_; }

 private:
  void Need(uint64_t n) {
    if (n > b_.size() - pos_) ThrowInputError(where_, "MCAP record cut short");
  }
  std::string b_;
  std::string where_;
  uint64_t pos_ = 0;
};

class Mcap : public Recording {
 public:
  explicit Mcap(const fs::path& path) : path_(path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) ThrowInputError(path, "cannot open the MCAP file");
    in.seekg(0, std::ios::end);
    size_ = static_cast<uint64_t>(in.tellg());
    auto read = [&](uint64_t pos, uint64_t n, const char* what) {
      if (pos > size_ || n > size_ - pos) {
        ThrowInputError(path, fmt::format("MCAP cut short: {} ({} bytes at byte {}) lies past its end ({} bytes)", what,
                                          n, pos, size_));
      }
      std::string bytes(n, '\0');
      in.clear();
      in.seekg(static_cast<std::streamoff>(pos));
      in.read(bytes.data(), static_cast<std::streamsize>(n));
      return bytes;
    };
    const uint64_t footer_size = 1 + 8 + 20;
    if (size_ < 8 + footer_size + 8 || read(size_ - 8, 8, "its closing magic") != kMcapMagic) {
      ThrowInputError(path, "MCAP cut short (no footer and closing magic at its end)");
    }
    Fields footer(read(size_ - 8 - footer_size, footer_size, "its footer"), path.string());
    if (footer.Get<uint8_t>() != 0x02) ThrowInputError(path, "MCAP footer missing");
    footer.Get<uint64_t>();
    const uint64_t summary_start = footer.Get<uint64_t>();
    const uint64_t summary_offset_start = footer.Get<uint64_t>();
    if (summary_start == 0) {
      ThrowInputError(path, "MCAP file without a summary (not indexed): `mcap recover` rebuilds one");
    }
    const uint64_t summary_end = summary_offset_start != 0 ? summary_offset_start : size_ - 8 - footer_size;
    if (summary_start >= summary_end || summary_end > size_) {
      ThrowInputError(path, fmt::format("MCAP summary at byte {} lies past its end ({} bytes)", summary_start, size_));
    }
    std::map<uint16_t, std::string> schemas;
    struct ChunkIndex {
      uint64_t start = 0;
      std::vector<std::pair<uint16_t, uint64_t>> message_indexes;
    };
    std::vector<ChunkIndex> chunk_indexes;
    const std::string summary = read(summary_start, summary_end - summary_start, "its summary");
    for (uint64_t pos = 0; pos < summary.size();) {
      if (summary.size() - pos < 9) ThrowInputError(path, "MCAP summary record cut short");
      const uint8_t op = static_cast<uint8_t>(summary[pos]);
      uint64_t length;
      std::memcpy(&length, summary.data() + pos + 1, 8);
      if (length > summary.size() - pos - 9) ThrowInputError(path, "MCAP summary record cut short");
      Fields f(summary.substr(pos + 9, length), path.string());
      if (op == 0x03) {  // schema
        const uint16_t id = f.Get<uint16_t>();
        schemas[id] = f.String();
      } else if (op == 0x04) {  // channel
        Connection c;
        c.id = f.Get<uint16_t>();
        const uint16_t schema = f.Get<uint16_t>();
        c.topic = f.String();
        const std::string encoding = f.String();
        const auto it = schemas.find(schema);
        c.type = encoding == "cdr" && it != schemas.end() ? Ros1Type(it->second) : "";
        connections_.push_back(c);
      } else if (op == 0x08) {  // chunk index
        ChunkIndex ci;
        f.Get<uint64_t>(), f.Get<uint64_t>();
        ci.start = f.Get<uint64_t>();
        f.Get<uint64_t>();
        const uint32_t map_bytes = f.Get<uint32_t>();
        if (map_bytes % 10 != 0) ThrowInputError(path, "MCAP chunk index with a damaged message index map");
        for (uint32_t k = 0; k < map_bytes / 10; ++k) {
          const uint16_t channel = f.Get<uint16_t>();
          ci.message_indexes.emplace_back(channel, f.Get<uint64_t>());
        }
        chunk_indexes.push_back(ci);
      }
      pos += 9 + length;
    }
    for (const ChunkIndex& ci : chunk_indexes) {
      Fields head(read(ci.start, 9, "a chunk"), path.string());
      if (head.Get<uint8_t>() != 0x06) {
        ThrowInputError(path, fmt::format("its chunk index points at byte {}, which is not a chunk", ci.start));
      }
      const uint64_t length = head.Get<uint64_t>();
      Fields chunk(read(ci.start + 9, std::min<uint64_t>(length, 4096), "a chunk"), path.string());
      chunk.Get<uint64_t>(), chunk.Get<uint64_t>();
      Chunk c;
      c.position = ci.start;
      c.block.uncompressed_size = chunk.Get<uint64_t>();
      chunk.Get<uint32_t>();
      const std::string compression = chunk.String();
      c.block.size = chunk.Get<uint64_t>();
      c.block.offset = ci.start + 9 + chunk.position();
      if (c.block.offset > size_ || c.block.size > size_ - c.block.offset) {
        ThrowInputError(path, fmt::format("MCAP cut short: the chunk at byte {} lies past its end", ci.start));
      }
      if (compression.empty()) {
        c.block.compression = EmbeddedImage::Compression::kNone;
      } else if (compression == "zstd") {
        c.block.compression = EmbeddedImage::Compression::kZstd;
      } else if (compression == "lz4") {
        c.block.compression = EmbeddedImage::Compression::kLz4;
      } else {
        ThrowInputError(path, fmt::format("chunk at byte {} is compressed as '{}', which fine2coarse does not read "
                                          "(none, zstd, lz4)",
                                          ci.start, compression));
      }
      const size_t index = chunks_.size();
      chunks_.push_back(c);
      for (const auto& [channel, at] : ci.message_indexes) {
        Fields ih(read(at, 9, "a message index"), path.string());
        if (ih.Get<uint8_t>() != 0x07) ThrowInputError(path, fmt::format("byte {} is not a message index", at));
        const uint64_t n = ih.Get<uint64_t>();
        Fields ix(read(at + 9, n, "a message index"), path.string());
        ix.Get<uint16_t>();
        const uint32_t bytes = ix.Get<uint32_t>();
        if (bytes % 16 != 0) ThrowInputError(path, fmt::format("damaged message index at byte {}", at));
        for (uint32_t k = 0; k < bytes / 16; ++k) {
          MessageRef m;
          m.connection = channel;
          m.time = static_cast<double>(ix.Get<uint64_t>()) * 1e-9;
          m.offset = ix.Get<uint64_t>();
          m.chunk = index;
          if (m.offset >= c.block.uncompressed_size) {
            ThrowInputError(path, fmt::format("message index at byte {} points past its chunk", at));
          }
          messages_.push_back(m);
        }
      }
    }
    std::stable_sort(messages_.begin(), messages_.end(),
                     [](const MessageRef& a, const MessageRef& b) { return a.time < b.time; });
  }
  const fs::path& path() const override { return path_; }
  const std::vector<Connection>& connections() const override { return connections_; }
  std::vector<MessageRef> Messages(const std::string& topic) const override {
    return MessagesOn(connections_, messages_, topic);
  }
  MessageData Read(const MessageRef& message, uint64_t max_bytes) const override {
    const Chunk& chunk = chunks_.at(message.chunk);
    const std::string where = fmt::format("{} (message in the chunk at byte {})", path_.string(), chunk.position);
    MessageData out;
    // The message record: opcode, length, channel, sequence, log and publish times, data.
    constexpr uint64_t kHead = 1 + 8 + 2 + 4 + 8 + 8;
    auto parse = [&](const std::string& bytes, uint64_t base) {
      if (message.offset + kHead > bytes.size()) return false;
      uint64_t length;
      std::memcpy(&length, bytes.data() + message.offset + 1, 8);
      if (static_cast<uint8_t>(bytes[message.offset]) != 0x05 || length < kHead - 9 ||
          length > chunk.block.uncompressed_size - message.offset - 9) {
        ThrowInputError(where, fmt::format("its message index points at byte {} of the chunk, which is not a message",
                                           message.offset));
      }
      out.size = length - (kHead - 9);
      out.offset = base + message.offset + kHead;
      const uint64_t n = max_bytes == 0 ? out.size : std::min(max_bytes, out.size);
      if (message.offset + kHead + n > bytes.size()) return false;
      out.bytes = bytes.substr(message.offset + kHead, n);
      return true;
    };
    if (chunk.block.compression == EmbeddedImage::Compression::kNone) {
      const uint64_t n = std::min<uint64_t>(chunk.block.size,
                                            message.offset + kHead + (max_bytes == 0 ? chunk.block.size : max_bytes));
      if (!parse(ReadFileRange(path_, chunk.block.offset, n), chunk.block.offset)) {
        ThrowInputError(where, "message cut short");
      }
      return out;
    }
    out.block = chunk.block;
    const uint64_t prefix = max_bytes == 0 ? chunk.block.uncompressed_size : message.offset + kHead + max_bytes;
    if (parse(*ReadBlockPrefix(path_, chunk.block, prefix), 0)) return out;
    if (!parse(*ReadBlock(path_, chunk.block), 0)) ThrowInputError(where, "message cut short");
    return out;
  }
  bool cdr() const override { return true; }
  std::string format() const override { return "format: ROS 2 bag (MCAP, CDR)"; }

 private:
  fs::path path_;
  uint64_t size_ = 0;
  std::vector<Connection> connections_;
  std::vector<Chunk> chunks_;
  std::vector<MessageRef> messages_;
};

// A ROS 2 bag folder's storage file: its one .db3 or .mcap.
fs::path StorageFile(const fs::path& dir) {
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string ext = e.path().extension().string();
    if (e.is_regular_file() && (ext == ".db3" || ext == ".mcap")) files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  if (files.empty()) ThrowInputError(dir / "metadata.yaml", "ROS 2 bag folder without a .db3 or .mcap file");
  if (files.size() > 1) {
    ThrowInputError(dir, fmt::format("ROS 2 bag split into {} files; fine2coarse reads one (`ros2 bag convert` "
                                     "joins them)",
                                     files.size()));
  }
  return files.front();
}

}  // namespace

bool LooksLikeRos2Bag(const fs::path& path) {
  if (fs::is_directory(path)) return fs::is_regular_file(path / "metadata.yaml");
  const std::string head = Head(path, 16);
  return head == kSqliteMagic || head.substr(0, 8) == kMcapMagic;
}

std::unique_ptr<Recording> OpenRecording(const fs::path& path) {
  if (LooksLikeBag(path)) return std::make_unique<Bag>(path);
  const fs::path file = fs::is_directory(path) ? StorageFile(path) : path;
  const std::string head = Head(file, 16);
  if (head == kSqliteMagic) return std::make_unique<Db3>(file);
  if (head.substr(0, 8) == kMcapMagic) return std::make_unique<Mcap>(file);
  ThrowInputError(file, "not a ROS bag (.bag, .db3 or .mcap)");
}

}  // namespace rosbag
}  // namespace f2c
