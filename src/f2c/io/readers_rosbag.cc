// ROS 1 bags as RGB-D sequences: a depth and a colour image topic (sensor_msgs/Image or
// CompressedImage), the depth camera's sensor_msgs/CameraInfo, frames paired by the images'
// header stamps. RealSense SDK 2 recordings (rs-record, RealSense Viewer) are found by their
// topic names: /device_0/sensor_N/Depth_0/image/data and Color_0, their info/camera_info, the
// depth units option and the streams' extrinsics (tf/0). docs/formats.md says what is read.

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <regex>

#include "f2c/io/readers.h"
#include "f2c/io/rosbag.h"
#include "f2c/util/error.h"

namespace f2c::internal {
namespace fs = std::filesystem;
using Bag = rosbag::Recording;
using rosbag::MessageReader;
using rosbag::MessageRef;

namespace {

constexpr const char* kImage = "sensor_msgs/Image";
constexpr const char* kCompressedImage = "sensor_msgs/CompressedImage";
constexpr const char* kCameraInfo = "sensor_msgs/CameraInfo";
// 32FC1 depth (metres) becomes 16-bit depth in units of 0.2 mm, TUM's PNG unit (1/5000 m):
// far below any RGB-D sensor's noise, up to 13.1 m. A TUM bag's float depth holds its PNGs'
// values exactly, so the bag and the folder give the same frames.
constexpr double kFloatDepthUnit = 1.0 / 5000.0;
// The image header fields read before the pixels: seq, stamp, frame_id, size, encoding, ...
constexpr uint64_t kImagePrefixBytes = 4096;

std::string Join(const std::vector<std::string>& items) {
  if (items.empty()) return "none";
  std::string out;
  for (const std::string& s : items) out += (out.empty() ? "" : ", ") + s;
  return out;
}

std::string TypeOf(const Bag& bag, const std::string& topic) {
  for (const rosbag::Connection& c : bag.connections()) {
    if (c.topic == topic) return c.type;
  }
  return "";
}

std::vector<std::string> TopicsOfType(const Bag& bag, const std::vector<std::string>& types) {
  std::vector<std::string> topics;
  for (const rosbag::Connection& c : bag.connections()) {
    if (std::find(types.begin(), types.end(), c.type) != types.end() &&
        std::find(topics.begin(), topics.end(), c.topic) == topics.end()) {
      topics.push_back(c.topic);
    }
  }
  std::sort(topics.begin(), topics.end());
  return topics;
}

// One image message: its stamp and where its pixels (or encoded bytes) lie.
struct ImageMessage {
  double stamp = 0;
  std::string frame_id;  // its camera's tf frame
  std::string encoding;  // Image: its encoding; CompressedImage: its format
  EmbeddedImage image;
};

bool IsDepthEncoding(const std::string& type, const std::string& encoding) {
  if (type == kCompressedImage) return encoding.find("compressedDepth") != std::string::npos;
  return encoding == "16UC1" || encoding == "mono16" || encoding == "32FC1";
}

ImageMessage ReadImageMessage(const Bag& bag, const MessageRef& ref, const std::string& type,
                              const std::string& topic) {
  const rosbag::MessageData data = bag.Read(ref, kImagePrefixBytes);
  const std::string where = fmt::format("{} ({} at {:.6f} s)", bag.path().string(), topic, ref.time);
  MessageReader r(data.bytes, where, bag.cdr());
  ImageMessage m;
  m.stamp = r.Stamp(&m.frame_id);
  EmbeddedImage& e = m.image;
  e.block = data.block;
  e.sqlite_row = data.sqlite_row;
  if (type == kCompressedImage) {
    m.encoding = r.String();
    const uint32_t n = r.Get<uint32_t>();
    e.format = EmbeddedImage::Format::kEncoded;
    e.offset = data.offset + r.position();
    e.size = n;
    // compressed_depth_image_transport: a 12-byte header (format, quantisation) before the PNG.
    if (m.encoding.find("compressedDepth") != std::string::npos) {
      if (m.encoding.find("rvl") != std::string::npos) {
        ThrowInputError(where, "depth compressed as compressedDepth rvl, which fine2coarse does not read (png: yes)");
      }
      if (n < 12) ThrowInputError(where, "compressedDepth message without its 12-byte header");
      // The header: int32 format (0: inverse depth), float32 quantisation constants A and B.
      const int32_t format = r.Get<int32_t>();
      const float quant_a = r.Get<float>(), quant_b = r.Get<float>();
      if (m.encoding.find("32FC1") != std::string::npos) {
        if (format != 0 || !std::isfinite(quant_a) || !std::isfinite(quant_b) || quant_a == 0) {
          ThrowInputError(where,
                          fmt::format("compressedDepth 32FC1 header: format {}, quantisation {} and {} (expected "
                                      "format 0, inverse depth, and finite constants)",
                                      format, quant_a, quant_b));
        }
        e.format = EmbeddedImage::Format::kInverseDepthPng;
        e.quant_a = quant_a;
        e.quant_b = quant_b;
        e.float_unit = kFloatDepthUnit;
      }
      e.offset += 12;
      e.size -= 12;
    }
  } else {
    e.height = static_cast<int>(std::min<uint32_t>(r.Get<uint32_t>(), 1 << 20));
    e.width = static_cast<int>(std::min<uint32_t>(r.Get<uint32_t>(), 1 << 20));
    m.encoding = r.String();
    e.big_endian = r.Get<uint8_t>() != 0;
    e.step = r.Get<uint32_t>();
    const uint32_t n = r.Get<uint32_t>();
    e.offset = data.offset + r.position();
    e.size = n;
    using F = EmbeddedImage::Format;
    const std::string& enc = m.encoding;
    if (enc == "16UC1" || enc == "mono16") {
      e.format = F::kRawU16;
    } else if (enc == "32FC1") {
      e.format = F::kFloat32;
      e.float_unit = kFloatDepthUnit;
    } else if (enc == "rgb8") {
      e.format = F::kRgb8;
    } else if (enc == "bgr8") {
      e.format = F::kBgr8;
    } else if (enc == "rgba8") {
      e.format = F::kRgba8;
    } else if (enc == "bgra8") {
      e.format = F::kBgra8;
    } else if (enc == "mono8" || enc == "8UC1") {
      e.format = F::kMono8;
    } else if (enc == "yuv422_yuy2" || enc == "yuyv" || enc == "YUYV") {
      e.format = F::kYuyv;
    } else if (enc == "yuv422" || enc == "uyvy" || enc == "UYVY") {
      e.format = F::kUyvy;
    } else {
      ThrowInputError(where, fmt::format("image encoding '{}', which fine2coarse does not read (depth: 16UC1, mono16, "
                                         "32FC1; colour: rgb8, bgr8, rgba8, bgra8, mono8, yuv422, yuv422_yuy2)",
                                         enc));
    }
    if (e.width <= 0 || e.height <= 0 || uint64_t(e.width) * uint64_t(e.height) > (uint64_t{1} << 25)) {
      ThrowInputError(where, fmt::format("image of {} x {} pixels (1 to 32 megapixels)", e.width, e.height));
    }
  }
  if (e.size > data.size - (e.offset - data.offset)) {
    ThrowInputError(where, fmt::format("image of {} bytes in a message of {}", e.size, data.size));
  }
  return m;
}

// The images of a topic, ordered by stamp; every one of the first's size and encoding.
std::vector<ImageMessage> ReadImages(const Bag& bag, const std::string& topic) {
  const std::string type = TypeOf(bag, topic);
  std::vector<ImageMessage> images;
  for (const MessageRef& ref : bag.Messages(topic)) {
    images.push_back(ReadImageMessage(bag, ref, type, topic));
    const ImageMessage& first = images.front();
    const ImageMessage& m = images.back();
    if (m.encoding != first.encoding || m.image.width != first.image.width || m.image.height != first.image.height) {
      ThrowInputError(bag.path(), fmt::format("{}: the image at {:.6f} s is {}x{} {} where the first is {}x{} {}",
                                              topic, m.stamp, m.image.width, m.image.height, m.encoding,
                                              first.image.width, first.image.height, first.encoding));
    }
  }
  if (images.empty()) ThrowInputError(bag.path(), fmt::format("{}: no message", topic));
  std::stable_sort(images.begin(), images.end(),
                   [](const ImageMessage& a, const ImageMessage& b) { return a.stamp < b.stamp; });
  return images;
}

// A topic named by an option: present, and of one of `types`.
void RequireTopic(const Bag& bag, const std::string& topic, const std::vector<std::string>& types, const char* flag) {
  const std::string type = TypeOf(bag, topic);
  const std::vector<std::string> candidates = TopicsOfType(bag, types);
  if (type.empty()) {
    ThrowInputError(bag.path(), fmt::format("{}: no topic '{}' in the bag (its {} topics: {})", flag, topic,
                                            Join(types), Join(candidates)));
  }
  if (std::find(types.begin(), types.end(), type) == types.end()) {
    ThrowInputError(bag.path(), fmt::format("{}: topic '{}' holds {}, not {}", flag, topic, type, Join(types)));
  }
}

// The one depth or colour image topic of a bag without topic options: image topics sorted
// by their first message's encoding.
std::string FindImageTopic(const Bag& bag, bool depth) {
  std::vector<std::string> found, images = TopicsOfType(bag, {kImage, kCompressedImage});
  for (const std::string& topic : images) {
    const std::vector<MessageRef> refs = bag.Messages(topic);
    if (refs.empty()) continue;
    const std::string type = TypeOf(bag, topic);
    const rosbag::MessageData data = bag.Read(refs.front(), kImagePrefixBytes);
    MessageReader r(data.bytes, bag.path().string() + " (" + topic + ")", bag.cdr());
    r.Stamp();
    if (type == kImage) r.Get<uint32_t>(), r.Get<uint32_t>();  // height, width
    const std::string encoding = r.String();
    if (IsDepthEncoding(type, encoding) == depth) found.push_back(topic);
  }
  const char* what = depth ? "depth" : "colour";
  const char* flag = depth ? "--depth-topic" : "--color-topic";
  if (found.empty()) {
    ThrowInputError(bag.path(), fmt::format("no {} image topic (its image topics: {})", what, Join(images)));
  }
  if (found.size() > 1) {
    ThrowInputError(bag.path(),
                    fmt::format("{} {} image topics ({}): choose one with {}", found.size(), what, Join(found), flag));
  }
  return found.front();
}

struct CameraInfo {
  CameraIntrinsics intrinsics;
  std::string model;
  std::vector<double> d;
};

CameraInfo ReadCameraInfo(const Bag& bag, const std::string& topic) {
  const std::vector<MessageRef> refs = bag.Messages(topic);
  if (refs.empty()) ThrowInputError(bag.path(), fmt::format("{}: no message", topic));
  const rosbag::MessageData data = bag.Read(refs.front(), 1 << 16);
  const std::string where = fmt::format("{} ({})", bag.path().string(), topic);
  MessageReader r(data.bytes, where, bag.cdr());
  r.Stamp();
  CameraInfo info;
  const uint32_t height = r.Get<uint32_t>(), width = r.Get<uint32_t>();
  info.model = r.String();
  const uint32_t n = r.Get<uint32_t>();
  if (n > 64) ThrowInputError(where, fmt::format("camera info with {} distortion coefficients", n));
  for (uint32_t k = 0; k < n; ++k) info.d.push_back(r.Get<double>());
  double k[9];
  for (double& v : k) v = r.Get<double>();
  if (k[0] == 0 || k[4] == 0) {
    ThrowInputError(where, "camera info without a calibration (K is zero): pass --intrinsics");
  }
  if (width == 0 || height == 0 || width > (1 << 20) || height > (1 << 20)) {
    ThrowInputError(where, fmt::format("camera info for {} x {} pixels", width, height));
  }
  CameraIntrinsics& c = info.intrinsics;
  c.fx = k[0], c.fy = k[4], c.cx = k[2], c.cy = k[5];
  c.width = static_cast<int>(width), c.height = static_cast<int>(height);
  // plumb_bob and RealSense's Brown Conrady: k1, k2, p1, p2, k3; rational_polynomial's
  // first five are the same terms.
  const bool brown = info.model == "plumb_bob" || info.model == "Brown Conrady" || info.model == "rational_polynomial";
  bool other = false;
  for (size_t i = 0; i < info.d.size(); ++i) {
    if (info.d[i] == 0) continue;
    if (brown && i < 5) {
      c.distortion[i] = info.d[i];
    } else {
      other = true;
    }
  }
  if (other) {
    spdlog::warn("{}: distortion model '{}' with coefficients fine2coarse does not apply: read as a pinhole camera",
                 where, info.model);
  }
  c.Validate(where);
  return info;
}

// A RealSense stream's extrinsic to its reference (tf/0, geometry_msgs/Transform).
std::optional<Rigid3d> ReadExtrinsic(const Bag& bag, const std::string& topic) {
  const std::vector<MessageRef> refs = bag.Messages(topic);
  if (refs.empty()) return std::nullopt;
  const rosbag::MessageData data = bag.Read(refs.front());
  MessageReader r(data.bytes, fmt::format("{} ({})", bag.path().string(), topic), bag.cdr());
  Eigen::Vector3d t;
  for (int i = 0; i < 3; ++i) t[i] = r.Get<double>();
  double q[4];
  for (double& v : q) v = r.Get<double>();
  Eigen::Quaterniond rotation(q[3], q[0], q[1], q[2]);
  if (!t.allFinite() || std::abs(rotation.norm() - 1) > 1e-3) {
    ThrowInputError(bag.path(), fmt::format("{}: not a rigid transform", topic));
  }
  Rigid3d reference_from_stream = Rigid3d::Identity();
  reference_from_stream.linear() = rotation.normalized().toRotationMatrix();
  reference_from_stream.translation() = t;
  return reference_from_stream;
}

std::string Parent(const std::string& topic) { return topic.substr(0, topic.rfind('/')); }

// An image topic's camera_info sibling: image_transport publishes a compressed image under the
// raw topic's name ("/camera/depth/image/compressedDepth"), beside which there is none.
std::string CameraInfoOf(const std::string& image_topic) {
  std::string base = image_topic;
  for (const char* transport : {"/compressedDepth", "/compressed"}) {
    if (base.ends_with(transport)) base.resize(base.size() - std::string_view(transport).size());
  }
  return Parent(base) + "/camera_info";
}

// ROS 1 frame ids may carry a leading '/' (tf's old convention); tf2 drops it.
std::string FrameName(std::string frame) {
  while (!frame.empty() && frame.front() == '/') frame.erase(0, 1);
  return frame;
}

// color_from_depth from the static transforms (/tf_static, tf2_msgs/TFMessage: each a
// parent_from_child pose), through the tree both cameras' frames hang from; empty where
// the bag has none or the two frames are not joined.
std::optional<Rigid3d> TfColorFromDepth(const Bag& bag, const std::string& depth_frame,
                                        const std::string& color_frame) {
  std::map<std::string, std::pair<std::string, Rigid3d>> parent_of;  // child -> (parent, parent_from_child)
  for (const rosbag::Connection& c : bag.connections()) {
    if (c.type != "tf2_msgs/TFMessage" || (c.topic != "/tf_static" && c.topic != "tf_static")) continue;
    for (const MessageRef& ref : bag.Messages(c.topic)) {
      const rosbag::MessageData data = bag.Read(ref);
      MessageReader r(data.bytes, fmt::format("{} ({})", bag.path().string(), c.topic), bag.cdr());
      const uint32_t n = r.Get<uint32_t>();
      for (uint32_t k = 0; k < n && k < 100000; ++k) {
        std::string parent;
        r.Stamp(&parent);
        const std::string child = r.String();
        Eigen::Vector3d t;
        for (int i = 0; i < 3; ++i) t[i] = r.Get<double>();
        double q[4];
        for (double& v : q) v = r.Get<double>();
        const Eigen::Quaterniond rotation(q[3], q[0], q[1], q[2]);
        if (!t.allFinite() || !(std::abs(rotation.norm() - 1) < 1e-3)) continue;
        Rigid3d parent_from_child = Rigid3d::Identity();
        parent_from_child.linear() = rotation.normalized().toRotationMatrix();
        parent_from_child.translation() = t;
        parent_of[FrameName(child)] = {FrameName(parent), parent_from_child};
      }
    }
  }
  // A frame's pose in its tree's root, and the root's name.
  auto rooted = [&](std::string frame) {
    Rigid3d root_from_frame = Rigid3d::Identity();
    for (int depth = 0; depth < 64; ++depth) {
      const auto it = parent_of.find(frame);
      if (it == parent_of.end()) break;
      root_from_frame = it->second.second * root_from_frame;
      frame = it->second.first;
    }
    return std::pair(frame, root_from_frame);
  };
  const auto [depth_root, root_from_depth] = rooted(FrameName(depth_frame));
  const auto [color_root, root_from_color] = rooted(FrameName(color_frame));
  if (depth_root != color_root || FrameName(depth_frame).empty()) return std::nullopt;
  return root_from_color.inverse() * root_from_depth;
}

}  // namespace

bool LooksLikeRosbag(const fs::path& path) { return rosbag::LooksLikeBag(path) || rosbag::LooksLikeRos2Bag(path); }

RgbdSequence ReadRosbag(const fs::path& path, const IoOptions& options) {
  const std::unique_ptr<rosbag::Recording> recording = rosbag::OpenRecording(path);
  const Bag& bag = *recording;
  const std::vector<std::string> image_types = {kImage, kCompressedImage};
  std::string depth_topic = options.depth_topic, color_topic = options.color_topic;
  if (!depth_topic.empty()) RequireTopic(bag, depth_topic, image_types, "--depth-topic");
  if (!color_topic.empty()) RequireTopic(bag, color_topic, image_types, "--color-topic");
  // RealSense recordings: one Depth and one Color stream, found by name.
  static const std::regex realsense(R"(/device_(\d+)/sensor_(\d+)/(Depth|Color)_(\d+)/image/data)");
  std::vector<std::string> rs_depth, rs_color;
  for (const std::string& topic : TopicsOfType(bag, image_types)) {
    std::smatch m;
    if (std::regex_match(topic, m, realsense)) (m[3] == "Depth" ? rs_depth : rs_color).push_back(topic);
  }
  const bool is_realsense = rs_depth.size() == 1 && rs_color.size() == 1 &&
                            (depth_topic.empty() || depth_topic == rs_depth[0]) &&
                            (color_topic.empty() || color_topic == rs_color[0]);
  if (is_realsense) {
    depth_topic = rs_depth[0];
    color_topic = rs_color[0];
  }
  if (depth_topic.empty()) depth_topic = FindImageTopic(bag, true);
  if (color_topic.empty()) color_topic = FindImageTopic(bag, false);
  // "/device_0/sensor_0/Depth_0/image/data" -> "/device_0/sensor_0/Depth_0": the stream.
  const std::string depth_stream = is_realsense ? Parent(Parent(depth_topic)) : "";
  const std::string color_stream = is_realsense ? Parent(Parent(color_topic)) : "";

  RgbdSequence seq;
  seq.layout = DatasetLayout::kRosbag;
  const std::vector<ImageMessage> depths = ReadImages(bag, depth_topic);
  const std::vector<ImageMessage> colors = ReadImages(bag, color_topic);
  if (!IsDepthEncoding(TypeOf(bag, depth_topic), depths.front().encoding)) {
    ThrowInputError(path, fmt::format("--depth-topic: {} holds {} images, not depth (16UC1, mono16, 32FC1)",
                                      depth_topic, depths.front().encoding));
  }
  // Depth units: 32FC1 is metres (raw or compressedDepth); 16-bit depth is the recording's units
  // (RealSense's Depth Units option), else --depth-scale, else millimetres (the ROS convention).
  if (depths.front().image.format == EmbeddedImage::Format::kFloat32 ||
      depths.front().image.format == EmbeddedImage::Format::kInverseDepthPng) {
    seq.depth_scale = kFloatDepthUnit;
  } else if (options.depth_scale > 0) {
    seq.depth_scale = options.depth_scale;
  } else {
    seq.depth_scale = 0.001;
    if (is_realsense) {
      const std::string units = Parent(depth_stream) + "/option/Depth Units/value";
      const std::vector<MessageRef> refs = bag.Messages(units);
      if (!refs.empty()) {
        const rosbag::MessageData data = bag.Read(refs.front());
        MessageReader r(data.bytes, path.string() + " (" + units + ")", bag.cdr());
        const float value = r.Get<float>();
        if (!(std::isfinite(value) && value > 0 && value < 1)) {
          ThrowInputError(path, fmt::format("{}: depth units of {} m", units, value));
        }
        seq.depth_scale = value;
      }
    }
  }
  const EmbeddedImage& c0 = colors.front().image;
  const EmbeddedImage& d0 = depths.front().image;
  // The depth camera: --intrinsics, --camera-info-topic, the depth topic's own camera info.
  std::string info_topic = options.camera_info_topic;
  if (!info_topic.empty()) {
    RequireTopic(bag, info_topic, {kCameraInfo}, "--camera-info-topic");
  } else {
    const std::string sibling = is_realsense ? depth_stream + "/info/camera_info" : CameraInfoOf(depth_topic);
    if (TypeOf(bag, sibling) == kCameraInfo) info_topic = sibling;
  }
  if (!info_topic.empty()) {
    seq.intrinsics = ReadCameraInfo(bag, info_topic).intrinsics;
    seq.intrinsics_source = path.string() + " (" + info_topic + ")";
  } else if (options.intrinsics.empty()) {
    ThrowInputError(path, fmt::format("no camera info for {} (its CameraInfo topics: {}): pass --intrinsics or "
                                      "--camera-info-topic",
                                      depth_topic, Join(TopicsOfType(bag, {kCameraInfo}))));
  }
  if (seq.intrinsics && d0.format != EmbeddedImage::Format::kEncoded &&
      d0.format != EmbeddedImage::Format::kInverseDepthPng &&
      (seq.intrinsics->width != d0.width || seq.intrinsics->height != d0.height)) {
    ThrowInputError(path, fmt::format("depth ({}) is {}x{} but its camera info ({}) is for {}x{}", depth_topic,
                                      d0.width, d0.height, info_topic, seq.intrinsics->width, seq.intrinsics->height));
  }
  // The colour camera, where it is another one: its camera info, and for RealSense its place.
  const std::string color_info = is_realsense ? color_stream + "/info/camera_info" : CameraInfoOf(color_topic);
  if (TypeOf(bag, color_info) == kCameraInfo && color_info != info_topic && seq.intrinsics) {
    const CameraIntrinsics kc = ReadCameraInfo(bag, color_info).intrinsics;
    const CameraIntrinsics& kd = *seq.intrinsics;
    Rigid3d color_from_depth = Rigid3d::Identity();
    bool placed = true;
    if (is_realsense) {
      const auto ref_from_depth = ReadExtrinsic(bag, depth_stream + "/tf/0");
      const auto ref_from_color = ReadExtrinsic(bag, color_stream + "/tf/0");
      if (ref_from_depth && ref_from_color) color_from_depth = ref_from_color->inverse() * *ref_from_depth;
    } else if (const auto tf = TfColorFromDepth(bag, depths.front().frame_id, colors.front().frame_id)) {
      color_from_depth = *tf;
    } else {
      placed = depths.front().frame_id == colors.front().frame_id;
    }
    const bool same = kc.fx == kd.fx && kc.fy == kd.fy && kc.cx == kd.cx && kc.cy == kd.cy && kc.width == kd.width &&
                      kc.height == kd.height && color_from_depth.matrix().isIdentity(1e-12);
    if (!same) {
      seq.color_camera = ColorCamera{kc, color_from_depth};
      if (!placed) {
        spdlog::warn(
            "{}: colour (frame '{}') is another camera than depth (frame '{}'), and /tf_static does not join "
            "them: read as if at the depth camera's place",
            path.string(), colors.front().frame_id, depths.front().frame_id);
      }
    }
  }
  // (Sizes known from the messages: raw images; encoded ones are checked when decoded.)
  if (!seq.color_camera && c0.format != EmbeddedImage::Format::kEncoded &&
      d0.format != EmbeddedImage::Format::kEncoded && d0.format != EmbeddedImage::Format::kInverseDepthPng &&
      (c0.width != d0.width || c0.height != d0.height)) {
    ThrowInputError(path, fmt::format("colour ({}) is {}x{} and depth ({}) {}x{}, and the colour has no camera info",
                                      color_topic, c0.width, c0.height, depth_topic, d0.width, d0.height));
  }
  // Frames: each colour image with the depth image nearest in time (TUM's rule, as its folders).
  std::vector<double> tc, td;
  for (const ImageMessage& m : colors) tc.push_back(m.stamp);
  for (const ImageMessage& m : depths) td.push_back(m.stamp);
  for (const auto& [ic, id] : AssociateTimestamps(tc, td, options.max_time_difference)) {
    RgbdFrame frame;
    StampFrame(colors[ic].stamp, depths[id].stamp, options.stamp, frame);
    frame.color_path = frame.depth_path = bag.path();  // the storage file of a ROS 2 bag folder
    frame.color_embedded = colors[ic].image;
    frame.depth_embedded = depths[id].image;
    frame.name = fmt::format("depth-{:06d}", id);
    seq.frames.push_back(frame);
  }
  SortFramesByTime(seq.frames);
  if (seq.frames.empty()) {
    ThrowInputError(path, fmt::format("no depth image ({}) within {} s of a colour image ({})", depth_topic,
                                      options.max_time_difference, color_topic));
  }
  if (seq.frames.size() < colors.size()) {
    spdlog::warn("{}: {} of {} colour images have no depth image within {} s: left out", path.string(),
                 colors.size() - seq.frames.size(), colors.size(), options.max_time_difference);
  }
  seq.streams = {bag.format(),
                 fmt::format("depth: {} ({}, {} images)", depth_topic, depths.front().encoding, depths.size()),
                 fmt::format("colour: {} ({}, {} images)", color_topic, colors.front().encoding, colors.size())};
  if (!info_topic.empty()) seq.streams.push_back("camera info: " + info_topic);
  return seq;
}

}  // namespace f2c::internal
