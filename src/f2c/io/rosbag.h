#pragma once
// ROS 1 bags (format 2.0), read by their index: the connections (topics and message types),
// the chunks (uncompressed, bz2 or lz4) and, per chunk, where each message lies in it. Only
// the index is read when a bag is opened; a message's bytes are read when asked for, so a bag
// of any size opens in memory proportional to its messages. The format (docs/formats.md):
//
//   "#ROSBAG V2.0\n", then records: int32 header length, header (fields: int32 length,
//   "name=value"), int32 data length, data. The header's op field says the record's kind:
//   0x03 bag header (index_pos: where the connections and chunk infos start), 0x05 chunk
//   (compression, uncompressed size; its data holds message records 0x02 and connection
//   records 0x07), 0x04 index data after each chunk (per connection: time and offset of each
//   message in the uncompressed chunk), 0x07 connection (topic; data: type, md5sum, message
//   definition), 0x06 chunk info (chunk_pos, message counts per connection).

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "f2c/io/sequence.h"

namespace f2c::rosbag {

struct Connection {
  uint32_t id = 0;
  std::string topic;
  std::string type;  // e.g. sensor_msgs/Image
};

// One message: its record's place (in its chunk's uncompressed bytes) and its receive time.
struct MessageRef {
  uint32_t connection = 0;
  double time = 0;      // seconds, as the index stores it (the recorder's clock)
  size_t chunk = 0;     // index into the recording's chunks
  uint64_t offset = 0;  // of the message record within the uncompressed chunk
  int64_t row = -1;     // ROS 2 .db3: the message's row in the messages table
};

struct Chunk {
  uint64_t position = 0;       // of the chunk record in the file
  EmbeddedImage::Block block;  // its data: where, how compressed, how large uncompressed
};

// A message's data (its serialised ROS message): `bytes` holds the first bytes asked for;
// `location` says where all `size` bytes lie (in the file, or in a chunk's uncompressed bytes).
struct MessageData {
  std::string bytes;
  uint64_t size = 0;
  uint64_t offset = 0;  // in the file (block empty), the block's uncompressed bytes or the row's blob
  std::optional<EmbeddedImage::Block> block;
  int64_t sqlite_row = -1;  // ROS 2 .db3: the blob of this row of the messages table holds it
};

// A recording of ROS messages, whatever its container: a ROS 1 bag (Bag), a ROS 2 bag's
// SQLite .db3 or MCAP file (ros2bag.h). Message types are ROS 1's names
// ("sensor_msgs/Image"; ROS 2's "sensor_msgs/msg/Image" is read as that).
class Recording {
 public:
  virtual ~Recording() = default;
  virtual const std::filesystem::path& path() const = 0;
  virtual const std::vector<Connection>& connections() const = 0;
  // The messages of the connections on `topic`, in the order of their times.
  virtual std::vector<MessageRef> Messages(const std::string& topic) const = 0;
  // The first `max_bytes` of a message's data (all of it when max_bytes is 0).
  virtual MessageData Read(const MessageRef& message, uint64_t max_bytes = 0) const = 0;
  // Whether messages are CDR-serialised (ROS 2) rather than ROS 1's serialisation.
  virtual bool cdr() const = 0;
  // The container, for `info`: "ROS 1 bag (2.0)", "ROS 2 bag (SQLite .db3)", ...
  virtual std::string format() const = 0;
};

class Bag : public Recording {
 public:
  // Reads the bag header, the connections, the chunk infos and each chunk's index.
  // InputError naming the file: not a bag, another format version, not indexed, cut short,
  // an index that points past the end, an unknown compression.
  explicit Bag(const std::filesystem::path& path);

  const std::filesystem::path& path() const override { return path_; }
  const std::vector<Connection>& connections() const override { return connections_; }
  const std::vector<Chunk>& chunks() const { return chunks_; }
  std::vector<MessageRef> Messages(const std::string& topic) const override;
  MessageData Read(const MessageRef& message, uint64_t max_bytes = 0) const override;
  bool cdr() const override { return false; }
  std::string format() const override { return "format: ROS 1 bag (2.0)"; }

 private:
  std::filesystem::path path_;
  uint64_t size_ = 0;
  std::shared_ptr<std::ifstream> in_;  // shared: a Bag is copied into what reads it
  std::vector<Connection> connections_;
  std::vector<Chunk> chunks_;
  std::vector<MessageRef> messages_;
};

// Whether the file starts as a ROS bag ("#ROSBAG V", any version).
bool LooksLikeBag(const std::filesystem::path& path);
// Whether `path` is a ROS 2 bag: a folder with metadata.yaml, or a .db3 (SQLite) or MCAP file
// (ros2bag.cc).
bool LooksLikeRos2Bag(const std::filesystem::path& path);
// The recording at `path`: a ROS 1 bag, or a ROS 2 bag (folder, .db3 or .mcap).
std::unique_ptr<Recording> OpenRecording(const std::filesystem::path& path);

// The messages of `topic` among `messages` (sorted by time), by the connections on it.
std::vector<MessageRef> MessagesOn(const std::vector<Connection>& connections, const std::vector<MessageRef>& messages,
                                   const std::string& topic);

// A little-endian reader over a message's bytes: ROS 1's serialisation (uint32-prefixed
// strings and arrays), or CDR (ROS 2: a 4-byte encapsulation header, each primitive aligned
// to its size from the end of that header, strings counted with their closing NUL).
// InputError naming `where` when the bytes end early.
class MessageReader {
 public:
  MessageReader(const std::string& bytes, std::string where, bool cdr = false);
  template <class T>
  T Get();
  std::string String();
  // Skips `n` bytes.
  void Skip(uint64_t n);
  // A std_msgs/Header's stamp (seconds; ROS 1's seq before it); its frame_id into `frame_id`
  // where one is given.
  double Stamp(std::string* frame_id = nullptr);
  uint64_t position() const { return pos_; }

 private:
  void Need(uint64_t n);
  void Align(uint64_t n);
  const std::string& bytes_;
  std::string where_;
  bool cdr_ = false;
  uint64_t pos_ = 0;
};

}  // namespace f2c::rosbag
