#include "f2c/io/rosbag.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <memory>

#include "f2c/io/block.h"
#include "f2c/util/error.h"

namespace f2c::rosbag {
namespace fs = std::filesystem;

namespace {

constexpr std::string_view kMagic = "#ROSBAG V2.0\n";
// A record header holds a few fields (a connection's message definition is its data, not
// its header): past 1 MiB it is damage.
constexpr uint64_t kMaxHeaderBytes = uint64_t{1} << 20;
// Connection records' data (type, md5sum, the message definition: a few KiB).
constexpr uint64_t kMaxConnectionBytes = uint64_t{16} << 20;

using Fields = std::map<std::string, std::string>;

template <class T>
T As(const std::string& bytes, size_t at = 0) {
  T value;
  std::memcpy(&value, bytes.data() + at, sizeof(T));
  return value;
}

// Thrown where a chunk's decompressed prefix is too short for what is read: read it whole.
struct NeedMore {};

// Reads bytes from the file or from (a prefix of) a chunk's uncompressed bytes, bounded by `end`.
struct Source {
  std::ifstream* file = nullptr;
  const std::string* bytes = nullptr;
  uint64_t end = 0;  // bytes past this are not the source's
  std::string where;
  std::string Read(uint64_t pos, uint64_t n, const std::string& what) const {
    if (pos > end || n > end - pos) {
      ThrowInputError(
          where, fmt::format("cut short: {} ({} bytes at byte {}) lies past the end ({} bytes)", what, n, pos, end));
    }
    if (bytes != nullptr) {
      if (n > bytes->size() || pos > bytes->size() - n) throw NeedMore{};  // a prefix of the chunk, short
      return bytes->substr(pos, n);
    }
    std::string out(n, '\0');
    file->clear();
    file->seekg(static_cast<std::streamoff>(pos));
    if (!file->read(out.data(), static_cast<std::streamsize>(n))) {
      ThrowInputError(where, fmt::format("cannot read {} ({} bytes at byte {})", what, n, pos));
    }
    return out;
  }
};

Fields ParseFields(const std::string& header, const std::string& where, uint64_t at) {
  Fields fields;
  size_t pos = 0;
  while (pos < header.size()) {
    if (header.size() - pos < 4) ThrowInputError(where, fmt::format("record at byte {}: header field cut short", at));
    const uint32_t n = As<uint32_t>(header, pos);
    pos += 4;
    if (n > header.size() - pos) {
      ThrowInputError(where, fmt::format("record at byte {}: header field of {} bytes past its header", at, n));
    }
    const std::string field = header.substr(pos, n);
    pos += n;
    const size_t eq = field.find('=');
    if (eq == std::string::npos) {
      ThrowInputError(where, fmt::format("record at byte {}: header field without '='", at));
    }
    fields[field.substr(0, eq)] = field.substr(eq + 1);
  }
  return fields;
}

struct Record {
  Fields header;
  uint64_t data_pos = 0, data_size = 0;
  uint64_t end() const { return data_pos + data_size; }
};

Record ReadRecord(const Source& source, uint64_t pos, const std::string& what) {
  const uint32_t header_size = As<uint32_t>(source.Read(pos, 4, what + "'s header length"));
  if (header_size > kMaxHeaderBytes) {
    ThrowInputError(source.where, fmt::format("{} at byte {}: header of {} bytes (damaged)", what, pos, header_size));
  }
  Record r;
  r.header = ParseFields(source.Read(pos + 4, header_size, what + "'s header"), source.where, pos);
  r.data_size = As<uint32_t>(source.Read(pos + 4 + header_size, 4, what + "'s data length"));
  r.data_pos = pos + 8 + header_size;
  if (r.data_pos > source.end || r.data_size > source.end - r.data_pos) {
    ThrowInputError(source.where, fmt::format("cut short: {} at byte {} says {} bytes of data, past the end ({} bytes)",
                                              what, pos, r.data_size, source.end));
  }
  return r;
}

template <class T>
T Field(const Fields& fields, const std::string& name, const std::string& where, uint64_t at) {
  const auto it = fields.find(name);
  if (it == fields.end() || it->second.size() != sizeof(T)) {
    ThrowInputError(where, fmt::format("record at byte {}: no {}-byte field '{}'", at, sizeof(T), name));
  }
  return As<T>(it->second);
}

uint8_t Op(const Fields& fields, const std::string& where, uint64_t at) {
  return Field<uint8_t>(fields, "op", where, at);
}

double Seconds(uint64_t stamp) {
  return static_cast<double>(stamp & 0xffffffffu) + static_cast<double>(stamp >> 32) * 1e-9;
}

}  // namespace

bool LooksLikeBag(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  char start[9] = {};
  return in.read(start, 9) && std::string_view(start, 9) == "#ROSBAG V";
}

Bag::Bag(const fs::path& path) : path_(path) {
  auto in = std::make_shared<std::ifstream>(path, std::ios::binary);
  if (!*in) ThrowInputError(path, "cannot open the bag");
  in->seekg(0, std::ios::end);
  size_ = static_cast<uint64_t>(in->tellg());
  Source file{in.get(), nullptr, size_, path.string()};
  const std::string where = path.string();
  {
    std::string line = file.Read(0, std::min<uint64_t>(size_, kMagic.size()), "its version line");
    if (line != kMagic) {
      const size_t newline = line.find('\n');
      if (line.rfind("#ROSBAG V", 0) == 0 && newline != std::string::npos) {
        ThrowInputError(path, fmt::format("ROS bag format {} (fine2coarse reads 2.0; `rosbag fix` converts older bags)",
                                          line.substr(9, newline - 9)));
      }
      ThrowInputError(path, "not a ROS bag (no \"#ROSBAG V2.0\" line)");
    }
  }
  const Record bag_header = ReadRecord(file, kMagic.size(), "the bag header");
  if (Op(bag_header.header, where, kMagic.size()) != 0x03) {
    ThrowInputError(path, "the first record is not the bag header");
  }
  const uint64_t index_pos = Field<uint64_t>(bag_header.header, "index_pos", where, kMagic.size());
  const uint32_t connection_count = Field<uint32_t>(bag_header.header, "conn_count", where, kMagic.size());
  const uint32_t chunk_count = Field<uint32_t>(bag_header.header, "chunk_count", where, kMagic.size());
  if (index_pos == 0) {
    ThrowInputError(path, "bag is not indexed (its recording did not end cleanly): `rosbag reindex` indexes it");
  }
  if (index_pos >= size_) {
    ThrowInputError(
        path, fmt::format("its index at byte {} lies past its end ({} bytes): the bag is cut short", index_pos, size_));
  }
  // The index: connection records, then one chunk info per chunk.
  std::vector<uint64_t> chunk_positions;
  for (uint64_t pos = index_pos; pos < size_;) {
    const Record r = ReadRecord(file, pos, "an index record");
    const uint8_t op = Op(r.header, where, pos);
    if (op == 0x07) {
      if (r.data_size > kMaxConnectionBytes) {
        ThrowInputError(path, fmt::format("connection at byte {}: {} bytes of data (damaged)", pos, r.data_size));
      }
      Connection c;
      c.id = Field<uint32_t>(r.header, "conn", where, pos);
      const auto topic = r.header.find("topic");
      if (topic == r.header.end()) ThrowInputError(path, fmt::format("connection at byte {} has no topic", pos));
      c.topic = topic->second;
      const Fields data = ParseFields(file.Read(r.data_pos, r.data_size, "a connection"), where, pos);
      const auto type = data.find("type");
      c.type = type == data.end() ? std::string() : type->second;
      connections_.push_back(c);
    } else if (op == 0x06) {
      if (Field<uint32_t>(r.header, "ver", where, pos) != 1) {
        ThrowInputError(path, fmt::format("chunk info at byte {} of a version other than 1", pos));
      }
      chunk_positions.push_back(Field<uint64_t>(r.header, "chunk_pos", where, pos));
    } else {
      ThrowInputError(
          path, fmt::format("record of kind {} at byte {} in its index (connections and chunk infos only)", op, pos));
    }
    pos = r.end();
  }
  if (connections_.size() != connection_count || chunk_positions.size() != chunk_count) {
    ThrowInputError(path, fmt::format("its index holds {} connections and {} chunks where its header says {} and {}",
                                      connections_.size(), chunk_positions.size(), connection_count, chunk_count));
  }
  std::sort(chunk_positions.begin(), chunk_positions.end());
  for (const uint64_t chunk_pos : chunk_positions) {
    if (chunk_pos >= index_pos) {
      ThrowInputError(path,
                      fmt::format("a chunk at byte {} lies past the chunks' end (byte {})", chunk_pos, index_pos));
    }
    const Record r = ReadRecord(file, chunk_pos, "a chunk");
    if (Op(r.header, where, chunk_pos) != 0x05) {
      ThrowInputError(path, fmt::format("its index points at byte {}, which is not a chunk", chunk_pos));
    }
    Chunk chunk;
    chunk.position = chunk_pos;
    chunk.block.offset = r.data_pos;
    chunk.block.size = r.data_size;
    chunk.block.uncompressed_size = Field<uint32_t>(r.header, "size", where, chunk_pos);
    const auto compression = r.header.find("compression");
    const std::string name = compression == r.header.end() ? "" : compression->second;
    if (name == "none") {
      chunk.block.compression = EmbeddedImage::Compression::kNone;
      if (chunk.block.size != chunk.block.uncompressed_size) {
        ThrowInputError(path, fmt::format("uncompressed chunk at byte {} holds {} bytes but says {}", chunk_pos,
                                          chunk.block.size, chunk.block.uncompressed_size));
      }
    } else if (name == "bz2") {
      chunk.block.compression = EmbeddedImage::Compression::kBz2;
    } else if (name == "lz4") {
      chunk.block.compression = EmbeddedImage::Compression::kLz4;
    } else {
      ThrowInputError(path, fmt::format("chunk at byte {} is compressed as '{}', which fine2coarse does not read "
                                        "(none, bz2, lz4)",
                                        chunk_pos, name));
    }
    const size_t chunk_index = chunks_.size();
    chunks_.push_back(chunk);
    // The chunk's index: one record per connection it holds messages of.
    for (uint64_t pos = r.end(); pos < index_pos;) {
      const Record ix = ReadRecord(file, pos, "a chunk's index");
      if (Op(ix.header, where, pos) != 0x04) break;
      if (Field<uint32_t>(ix.header, "ver", where, pos) != 1) {
        ThrowInputError(path, fmt::format("index data at byte {} of a version other than 1", pos));
      }
      const uint32_t connection = Field<uint32_t>(ix.header, "conn", where, pos);
      const uint32_t count = Field<uint32_t>(ix.header, "count", where, pos);
      if (ix.data_size != uint64_t{count} * 12) {
        ThrowInputError(path, fmt::format("index data at byte {}: {} bytes for {} messages", pos, ix.data_size, count));
      }
      const std::string entries = file.Read(ix.data_pos, ix.data_size, "a chunk's index");
      for (uint32_t k = 0; k < count; ++k) {
        MessageRef m;
        m.connection = connection;
        m.time = Seconds(As<uint64_t>(entries, 12 * k));
        m.chunk = chunk_index;
        m.offset = As<uint32_t>(entries, 12 * k + 8);
        if (m.offset >= chunk.block.uncompressed_size) {
          ThrowInputError(path, fmt::format("index data at byte {} points past its chunk ({} of {} bytes)", pos,
                                            m.offset, chunk.block.uncompressed_size));
        }
        messages_.push_back(m);
      }
      pos = ix.end();
    }
  }
  std::stable_sort(messages_.begin(), messages_.end(),
                   [](const MessageRef& a, const MessageRef& b) { return a.time < b.time; });
  in_ = std::move(in);
}

std::vector<MessageRef> MessagesOn(const std::vector<Connection>& connections, const std::vector<MessageRef>& messages,
                                   const std::string& topic) {
  std::vector<uint32_t> ids;
  for (const Connection& c : connections) {
    if (c.topic == topic) ids.push_back(c.id);
  }
  std::vector<MessageRef> out;
  for (const MessageRef& m : messages) {
    if (std::find(ids.begin(), ids.end(), m.connection) != ids.end()) out.push_back(m);
  }
  return out;
}

std::vector<MessageRef> Bag::Messages(const std::string& topic) const {
  return MessagesOn(connections_, messages_, topic);
}

MessageData Bag::Read(const MessageRef& message, uint64_t max_bytes) const {
  const Chunk& chunk = chunks_.at(message.chunk);
  const std::string where = fmt::format("{} (message in the chunk at byte {})", path_.string(), chunk.position);
  const bool compressed = chunk.block.compression != EmbeddedImage::Compression::kNone;
  // From a compressed chunk, first only as much as the message's start needs (its record
  // header is a few dozen bytes): a chunk of one large image is not decompressed to read its
  // header. The whole chunk where that was not enough.
  for (const bool whole : {false, true}) {
    if (!compressed && whole) break;
    MessageData out;
    std::shared_ptr<const std::string> block;
    Source source;
    source.where = where;
    uint64_t base = 0;
    if (!compressed) {
      source.file = in_.get();
      source.end = chunk.block.offset + chunk.block.size;
      base = chunk.block.offset;
    } else {
      const uint64_t prefix =
          max_bytes == 0 || whole ? chunk.block.uncompressed_size : message.offset + 8 + 4096 + max_bytes;
      block = ReadBlockPrefix(path_, chunk.block, prefix);
      source.bytes = block.get();
      source.end = chunk.block.uncompressed_size;
      out.block = chunk.block;
    }
    try {
      const Record r = ReadRecord(source, base + message.offset, "a message");
      if (Op(r.header, where, message.offset) != 0x02) {
        ThrowInputError(
            where, fmt::format("the index points at byte {} of the chunk, which is not a message", message.offset));
      }
      out.size = r.data_size;
      out.offset = r.data_pos;
      const uint64_t n = max_bytes == 0 ? r.data_size : std::min(max_bytes, r.data_size);
      out.bytes = source.Read(r.data_pos, n, "a message");
      return out;
    } catch (const NeedMore&) {
      if (whole) throw;
    }
  }
  ThrowInputError(where, "cannot read the message");
}

MessageReader::MessageReader(const std::string& bytes, std::string where, bool cdr)
    : bytes_(bytes), where_(std::move(where)), cdr_(cdr) {
  if (!cdr_) return;
  Need(4);
  // The encapsulation: 0x00 0x01 is little-endian plain CDR, what ROS 2 writes.
  if (bytes_[0] != 0 || bytes_[1] != 1) {
    ThrowInputError(where_, fmt::format("CDR encapsulation {:02x}{:02x} (fine2coarse reads little-endian CDR, 0001)",
                                        static_cast<uint8_t>(bytes_[0]), static_cast<uint8_t>(bytes_[1])));
  }
  pos_ = 4;
}

void MessageReader::Need(uint64_t n) {
  if (n > bytes_.size() - pos_) {
    ThrowInputError(where_, fmt::format("message cut short ({} bytes at byte {} of {})", n, pos_, bytes_.size()));
  }
}

void MessageReader::Align(uint64_t n) {
  if (!cdr_) return;
  const uint64_t from_origin = pos_ - 4;
  Skip((n - from_origin % n) % n);
}

template <class T>
T MessageReader::Get() {
  Align(sizeof(T));
  Need(sizeof(T));
  T value = As<T>(bytes_, pos_);
  pos_ += sizeof(T);
  return value;
}
template uint8_t MessageReader::Get<uint8_t>();
template uint32_t MessageReader::Get<uint32_t>();
template int32_t MessageReader::Get<int32_t>();
template float MessageReader::Get<float>();
template double MessageReader::Get<double>();

std::string MessageReader::String() {
  const uint32_t n = Get<uint32_t>();
  Need(n);
  std::string s = bytes_.substr(pos_, n);
  pos_ += n;
  if (cdr_ && !s.empty() && s.back() == '\0') s.pop_back();
  return s;
}

void MessageReader::Skip(uint64_t n) {
  Need(n);
  pos_ += n;
}

double MessageReader::Stamp(std::string* frame_id) {
  if (!cdr_) Get<uint32_t>();  // seq
  const uint32_t sec = Get<uint32_t>(), nsec = Get<uint32_t>();
  const std::string frame = String();
  if (frame_id != nullptr) *frame_id = frame;
  // The double nearest to the stamp's decimal value, as a TUM list's "1305031102.175304" is
  // read, so a bag and its folder stamp their frames alike.
  return std::strtod(fmt::format("{}.{:09d}", sec, nsec).c_str(), nullptr);
}

}  // namespace f2c::rosbag
