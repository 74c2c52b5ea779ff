#include "f2c/testing/ros2_writer.h"

#include <fmt/format.h>
#include <lz4frame.h>
#include <sqlite3.h>
#include <zstd.h>

#include <cstring>
#include <map>
#include <opencv2/imgcodecs.hpp>  // the IMREAD_ flags (an enum; nothing of the library is linked)
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "f2c/io/image.h"
#include "f2c/io/sequence.h"
#include "f2c/util/file.h"

namespace f2c::testing {
namespace {
namespace fs = std::filesystem;

// CDR (little-endian, encapsulation 00 01 00 00): each primitive aligned to its size from the
// end of the 4-byte header; strings carry their closing NUL in their length.
class Cdr {
 public:
  template <class T>
  void Put(T v) {
    Align(sizeof(T));
    b_.append(reinterpret_cast<const char*>(&v), sizeof(T));
  }
  void String(const std::string& s) {
    Put<uint32_t>(static_cast<uint32_t>(s.size() + 1));
    b_ += s;
    b_ += '\0';
  }
  void Bytes(const void* data, size_t n) {
    Put<uint32_t>(static_cast<uint32_t>(n));
    b_.append(static_cast<const char*>(data), n);
  }
  void Header(int64_t ns, const std::string& frame) {
    Put<int32_t>(static_cast<int32_t>(ns / 1000000000)), Put<uint32_t>(static_cast<uint32_t>(ns % 1000000000));
    String(frame);
  }
  const std::string& bytes() const { return b_; }

 private:
  void Align(size_t n) {
    while ((b_.size() - 4) % n != 0) b_ += '\0';
  }
  std::string b_ = std::string("\0\1\0\0", 4);
};

std::string ImageMessage(const cv::Mat& pixels, const std::string& encoding, int64_t ns, const std::string& frame) {
  Cdr c;
  c.Header(ns, frame);
  c.Put<uint32_t>(pixels.rows), c.Put<uint32_t>(pixels.cols);
  c.String(encoding);
  c.Put<uint8_t>(0);
  c.Put<uint32_t>(static_cast<uint32_t>(pixels.step[0]));
  c.Bytes(pixels.data, pixels.total() * pixels.elemSize());
  return c.bytes();
}

std::string CameraInfoMessage(const CameraIntrinsics& k, int64_t ns, const std::string& frame) {
  Cdr c;
  c.Header(ns, frame);
  c.Put<uint32_t>(k.height), c.Put<uint32_t>(k.width);
  c.String("plumb_bob");
  c.Put<uint32_t>(5);
  for (int i = 0; i < 5; ++i) c.Put<double>(0);
  for (double v : {k.fx, 0.0, k.cx, 0.0, k.fy, k.cy, 0.0, 0.0, 1.0}) c.Put<double>(v);
  for (double v : {1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0}) c.Put<double>(v);
  for (double v : {k.fx, 0.0, k.cx, 0.0, 0.0, k.fy, k.cy, 0.0, 0.0, 0.0, 1.0, 0.0}) c.Put<double>(v);
  for (int i = 0; i < 6; ++i) c.Put<uint32_t>(0);  // binning, region of interest
  c.Put<uint8_t>(0);
  return c.bytes();
}

struct Message {
  std::string topic;
  int64_t ns = 0;
  std::string data;
};

const std::vector<std::pair<std::string, std::string>> kTopics = {
    {"/camera/color/image_raw", "sensor_msgs/msg/Image"},
    {"/camera/color/camera_info", "sensor_msgs/msg/CameraInfo"},
    {"/camera/depth/image_rect_raw", "sensor_msgs/msg/Image"},
    {"/camera/depth/camera_info", "sensor_msgs/msg/CameraInfo"},
    {"/tf_static", "tf2_msgs/msg/TFMessage"}};

// camera_link -> each camera's optical frame: the depth camera at camera_link, the colour
// camera at `color_in_depth`.
std::string TfStaticMessage(const Eigen::Vector3d& color_in_depth, int64_t ns) {
  Cdr c;
  c.Put<uint32_t>(2);
  for (const auto& [child, t] : {std::pair(std::string("camera_depth_optical_frame"), Eigen::Vector3d::Zero().eval()),
                                 std::pair(std::string("camera_color_optical_frame"), color_in_depth)}) {
    c.Header(ns, "camera_link");
    c.String(child);
    for (int i = 0; i < 3; ++i) c.Put<double>(t[i]);
    for (double q : {0.0, 0.0, 0.0, 1.0}) c.Put<double>(q);
  }
  return c.bytes();
}

// One frame's messages (colour, depth; the camera infos with the first).
std::vector<std::vector<Message>> FrameMessages(const fs::path& tum_dir, const Ros2BagOptions& o) {
  const CameraIntrinsics& k = o.intrinsics;
  IoOptions io;
  io.intrinsics = fmt::format("{},{},{},{}", k.fx, k.fy, k.cx, k.cy);
  const RgbdSequence seq = ReadSequence(tum_dir, io);
  std::vector<std::vector<Message>> frames;
  for (size_t i = 0; i < seq.frames.size(); ++i) {
    const RgbdFrame& f = seq.frames[i];
    const auto ns = static_cast<int64_t>(std::llround(f.timestamp * 1e9));  // the depth image's
    const auto color_ns = static_cast<int64_t>(std::llround((f.timestamp + f.color_time) * 1e9));
    cv::Mat bgr = DecodeImageFile(f.color_path, cv::IMREAD_COLOR), rgb;
    cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
    const cv::Mat raw = DecodeImageFile(f.depth_path, cv::IMREAD_ANYDEPTH | cv::IMREAD_ANYCOLOR);
    cv::Mat metres(raw.size(), CV_32F);
    for (int y = 0; y < raw.rows; ++y) {
      for (int x = 0; x < raw.cols; ++x) {
        const uint16_t v = raw.at<uint16_t>(y, x);
        metres.at<float>(y, x) =
            v == 0 ? std::numeric_limits<float>::quiet_NaN() : static_cast<float>(v * seq.depth_scale);
      }
    }
    std::vector<Message> m;
    if (i == 0) {
      m.push_back(
          {kTopics[1].first, ns, CameraInfoMessage(o.color_intrinsics.value_or(k), ns, "camera_color_optical_frame")});
      m.push_back({kTopics[3].first, ns, CameraInfoMessage(k, ns, "camera_depth_optical_frame")});
      if (o.color_intrinsics) m.push_back({kTopics[4].first, ns, TfStaticMessage(o.color_in_depth, ns)});
    }
    m.push_back({kTopics[0].first, color_ns, ImageMessage(rgb, "rgb8", color_ns, "camera_color_optical_frame")});
    m.push_back({kTopics[2].first, ns, ImageMessage(metres, "32FC1", ns, "camera_depth_optical_frame")});
    frames.push_back(m);
  }
  return frames;
}

void Check(int status, sqlite3* db) {
  if (status != SQLITE_OK && status != SQLITE_DONE) throw std::runtime_error(sqlite3_errmsg(db));
}

void WriteDb3(const fs::path& path, const std::vector<std::vector<Message>>& frames) {
  fs::remove(path);
  sqlite3* db = nullptr;
  Check(sqlite3_open(path.c_str(), &db), db);
  Check(sqlite3_exec(db,
                     "CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL, "
                     "serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL);"
                     "CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL, timestamp INTEGER "
                     "NOT NULL, data BLOB NOT NULL);",
                     nullptr, nullptr, nullptr),
        db);
  for (size_t t = 0; t < kTopics.size(); ++t) {
    const std::string sql =
        fmt::format("INSERT INTO topics VALUES({}, '{}', '{}', 'cdr', '')", t + 1, kTopics[t].first, kTopics[t].second);
    Check(sqlite3_exec(db, sql.c_str(), nullptr, nullptr, nullptr), db);
  }
  sqlite3_stmt* insert = nullptr;
  Check(sqlite3_prepare_v2(db, "INSERT INTO messages(topic_id, timestamp, data) VALUES(?, ?, ?)", -1, &insert, nullptr),
        db);
  for (const auto& frame : frames) {
    for (const Message& m : frame) {
      int topic = 0;
      while (kTopics[topic].first != m.topic) ++topic;
      sqlite3_reset(insert);
      sqlite3_bind_int(insert, 1, topic + 1);
      sqlite3_bind_int64(insert, 2, m.ns);
      sqlite3_bind_blob(insert, 3, m.data.data(), static_cast<int>(m.data.size()), SQLITE_STATIC);
      Check(sqlite3_step(insert), db);
    }
  }
  sqlite3_finalize(insert);
  sqlite3_close(db);
}

template <class T>
void PutLe(std::string* out, T v) {
  out->append(reinterpret_cast<const char*>(&v), sizeof(T));
}
void PutString(std::string* out, const std::string& s) {
  PutLe<uint32_t>(out, static_cast<uint32_t>(s.size()));
  *out += s;
}
void Record(std::string* out, uint8_t op, const std::string& body) {
  PutLe<uint8_t>(out, op);
  PutLe<uint64_t>(out, body.size());
  *out += body;
}

std::string Compress(const std::string& in, const std::string& compression) {
  if (compression == "zstd") {
    std::string out(ZSTD_compressBound(in.size()), '\0');
    out.resize(ZSTD_compress(out.data(), out.size(), in.data(), in.size(), 3));
    return out;
  }
  if (compression == "lz4") {
    std::string out(LZ4F_compressFrameBound(in.size(), nullptr), '\0');
    out.resize(LZ4F_compressFrame(out.data(), out.size(), in.data(), in.size(), nullptr));
    return out;
  }
  return in;
}

void WriteMcap(const fs::path& path, const std::vector<std::vector<Message>>& frames, const std::string& compression) {
  std::string out("\x89MCAP0\r\n", 8);
  std::string header;
  PutString(&header, "ros2");
  PutString(&header, "fine2coarse test");
  Record(&out, 0x01, header);
  std::string schemas_and_channels;
  std::map<std::string, uint16_t> channel_of;
  std::map<std::string, uint16_t> schema_of;
  for (const auto& [topic, type] : kTopics) {
    if (!schema_of.count(type)) {
      const uint16_t id = static_cast<uint16_t>(schema_of.size() + 1);
      schema_of[type] = id;
      std::string body;
      PutLe<uint16_t>(&body, id);
      PutString(&body, type);
      PutString(&body, "ros2msg");
      PutString(&body, "");  // the definition: not needed to read
      Record(&schemas_and_channels, 0x03, body);
    }
    const uint16_t id = static_cast<uint16_t>(channel_of.size() + 1);
    channel_of[topic] = id;
    std::string body;
    PutLe<uint16_t>(&body, id);
    PutLe<uint16_t>(&body, schema_of[type]);
    PutString(&body, topic);
    PutString(&body, "cdr");
    PutLe<uint32_t>(&body, 0);  // metadata
    Record(&schemas_and_channels, 0x04, body);
  }
  out += schemas_and_channels;
  std::string chunk_indexes;
  uint32_t sequence = 0;
  for (const auto& frame : frames) {
    std::string records;
    std::map<uint16_t, std::vector<std::pair<uint64_t, uint64_t>>> index;
    for (const Message& m : frame) {
      const uint16_t channel = channel_of[m.topic];
      index[channel].emplace_back(m.ns, records.size());
      std::string body;
      PutLe<uint16_t>(&body, channel);
      PutLe<uint32_t>(&body, sequence++);
      PutLe<uint64_t>(&body, m.ns), PutLe<uint64_t>(&body, m.ns);
      body += m.data;
      Record(&records, 0x05, body);
    }
    const std::string stored = Compress(records, compression);
    const uint64_t chunk_start = out.size();
    std::string body;
    PutLe<uint64_t>(&body, frame.front().ns), PutLe<uint64_t>(&body, frame.back().ns);
    PutLe<uint64_t>(&body, records.size());
    PutLe<uint32_t>(&body, 0);
    PutString(&body, compression);
    PutLe<uint64_t>(&body, stored.size());
    body += stored;
    Record(&out, 0x06, body);
    const uint64_t chunk_length = out.size() - chunk_start;
    std::string offsets;
    const uint64_t indexes_start = out.size();
    for (const auto& [channel, entries] : index) {
      PutLe<uint16_t>(&offsets, channel);
      PutLe<uint64_t>(&offsets, out.size());
      std::string ix;
      PutLe<uint16_t>(&ix, channel);
      PutLe<uint32_t>(&ix, static_cast<uint32_t>(entries.size() * 16));
      for (const auto& [time, offset] : entries) PutLe<uint64_t>(&ix, time), PutLe<uint64_t>(&ix, offset);
      Record(&out, 0x07, ix);
    }
    std::string ci;
    PutLe<uint64_t>(&ci, frame.front().ns), PutLe<uint64_t>(&ci, frame.back().ns);
    PutLe<uint64_t>(&ci, chunk_start), PutLe<uint64_t>(&ci, chunk_length);
    PutLe<uint32_t>(&ci, static_cast<uint32_t>(offsets.size()));
    ci += offsets;
    PutLe<uint64_t>(&ci, out.size() - indexes_start);
    PutString(&ci, compression);
    PutLe<uint64_t>(&ci, stored.size()), PutLe<uint64_t>(&ci, records.size());
    Record(&chunk_indexes, 0x08, ci);
  }
  std::string data_end;
  PutLe<uint32_t>(&data_end, 0);
  Record(&out, 0x0F, data_end);
  const uint64_t summary_start = out.size();
  out += schemas_and_channels;
  out += chunk_indexes;
  std::string footer;
  PutLe<uint64_t>(&footer, summary_start), PutLe<uint64_t>(&footer, 0), PutLe<uint32_t>(&footer, 0);
  Record(&out, 0x02, footer);
  out += std::string("\x89MCAP0\r\n", 8);
  WriteFileAtomic(path, out);
}

}  // namespace

fs::path WriteRos2Bag(const fs::path& tum_dir, const fs::path& out_dir, const Ros2BagOptions& o) {
  fs::create_directories(out_dir);
  const auto frames = FrameMessages(tum_dir, o);
  const fs::path file = out_dir / ("scan." + o.storage);
  if (o.storage == "db3") {
    WriteDb3(file, frames);
  } else {
    WriteMcap(file, frames, o.compression);
  }
  WriteFileAtomic(out_dir / "metadata.yaml",
                  fmt::format("rosbag2_bagfile_information:\n  version: 5\n  storage_identifier: {}\n"
                              "  relative_file_paths:\n    - {}\n",
                              o.storage == "db3" ? "sqlite3" : "mcap", file.filename().string()));
  return file;
}

}  // namespace f2c::testing
