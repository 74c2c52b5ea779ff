#pragma once
// One RGB-D sequence, whatever layout it came in: frames (time stamp, colour and depth
// paths), depth intrinsics, how depth values map to metres, and optional ground truth.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "f2c/geometry/intrinsics.h"
#include "f2c/io/trajectory.h"
#include "f2c/util/fields.h"

namespace f2c {

enum class DatasetLayout { kTum, kSevenScenes, kRedwood, kSun3d, kConf, kSens, kRosbag };
std::string LayoutName(DatasetLayout layout);

// How the 16-bit values of a depth PNG are stored.
enum class DepthEncoding {
  kPlain,            // value * depth_scale metres
  kSun3dBitRotated,  // SUN3D: depth_mm = (v >> 3) | (v << 13) in 16 bits
};

// An image stored inside a recording (a ScanNet .sens file, a ROS bag) rather than in a file
// of its own: `size` bytes at `offset` of the frame's path, or of the uncompressed bytes of a
// compressed block of it (a bag's bz2 or lz4 chunk).
struct EmbeddedImage {
  enum class Format {
    kEncoded,  // PNG or JPEG bytes
    kRgb8,     // width x height x 3 bytes, R G B
    kBgr8,     // B G R
    kRgba8,    // R G B A
    kBgra8,    // B G R A
    kMono8,    // grey
    kYuyv,     // YUV 4:2:2, Y0 U Y1 V (ROS yuv422_yuy2, RealSense YUYV)
    kUyvy,     // YUV 4:2:2, U Y0 V Y1 (ROS yuv422)
    kRawU16,   // width x height uint16 (little-endian unless big_endian)
    kZlibU16,  // the same, zlib-compressed
    kFloat32,  // width x height float metres (ROS 32FC1): quantised to float_unit per uint16
    // ROS compressedDepth of 32FC1: a 16-bit PNG of inverse depth q, metres = quant_a /
    // (q - quant_b) (0: none), quantised to float_unit per uint16
    kInverseDepthPng,
  };
  enum class Compression { kNone, kBz2, kLz4, kZstd };
  struct Block {
    uint64_t offset = 0, size = 0;  // the compressed bytes in the file
    uint64_t uncompressed_size = 0;
    Compression compression = Compression::kNone;
  };
  uint64_t offset = 0;
  uint64_t size = 0;
  Format format = Format::kEncoded;
  int width = 0, height = 0;        // the raw formats'
  uint64_t step = 0;                // bytes per row of the raw formats (0: rows packed)
  bool big_endian = false;          // kRawU16 and kFloat32
  double float_unit = 0;            // kFloat32, kInverseDepthPng: metres per unit of the uint16 depth it becomes
  double quant_a = 0, quant_b = 0;  // kInverseDepthPng: the quantisation's constants
  std::optional<Block> block;
  int64_t sqlite_row = -1;  // ROS 2 .db3: offset and size are in this row's message blob
};

struct RgbdFrame {
  // Seconds: the depth image's time where colour and depth have their own (IoOptions::stamp),
  // since the geometry that fixes a pose is the depth's.
  double timestamp = 0;
  std::filesystem::path color_path;
  std::filesystem::path depth_path;
  std::string name;  // short name for logs and .conf files (the depth file's name)
  // Set when the image lies inside the file at color_path / depth_path.
  std::optional<EmbeddedImage> color_embedded, depth_embedded;
  double color_time = 0;  // the colour image's time stamp minus `timestamp` (s)
};

// A colour camera other than the depth camera (recordings whose two sensors differ in
// resolution, intrinsics or place): colour is resampled into the depth camera when it is
// read (LoadColor), so every stage sees one camera, the depth's.
struct ColorCamera {
  CameraIntrinsics intrinsics;  // with its image size and lens distortion (applied when sampling it)
  Rigid3d color_from_depth = Rigid3d::Identity();
};

// Depth from another camera warped into the colour camera (--align-to color): the sequence's
// camera (RgbdSequence::intrinsics) is then the colour camera, and this is the depth's.
struct DepthCamera {
  CameraIntrinsics intrinsics;  // as stored (with its distortion, if any)
  Rigid3d color_from_depth = Rigid3d::Identity();
};

// Whose time stamp a frame carries where colour and depth images have their own (TUM folders,
// ROS bags, .sens files).
enum class FrameStamp { kDepth, kColor };
F2C_ENUM_NAMES(FrameStamp, {{FrameStamp::kDepth, "depth"}, {FrameStamp::kColor, "color"}})

// Which camera the frames are seen from where depth and colour come from two (recordings).
enum class AlignTo { kDepth, kColor };
F2C_ENUM_NAMES(AlignTo, {{AlignTo::kDepth, "depth"}, {AlignTo::kColor, "color"}})

struct RgbdSequence {
  std::filesystem::path root;
  DatasetLayout layout = DatasetLayout::kTum;
  std::vector<RgbdFrame> frames;
  std::optional<CameraIntrinsics> intrinsics;  // the depth camera's; TUM folders carry none
  std::optional<ColorCamera> color_camera;     // only where colour is another camera
  std::optional<DepthCamera> depth_camera;     // only where depth is warped into the colour camera
  std::string intrinsics_source;               // file or option it came from
  double depth_scale = 0.001;                  // metres per unit (after decoding)
  std::vector<uint16_t> invalid_depth_values{0};
  DepthEncoding depth_encoding = DepthEncoding::kPlain;
  std::optional<Trajectory> ground_truth;  // camera-to-world
  std::filesystem::path ground_truth_source;
  // Recordings: the streams read ("depth: /camera/depth/image (32FC1, 798 images)"), for info.
  std::vector<std::string> streams;
};

struct IoOptions {
  // "fx,fy,cx,cy[,k1,k2,p1,p2[,k3]]" or a preset name (see IntrinsicsPresetNames()); empty:
  // the dataset's own.
  std::string intrinsics;
  // Frame selection, applied after reading: frames first..last (inclusive, 0-based; -1 = to
  // the end) of the associated sequence, then every N-th of those.
  int every = 1;
  int first = 0;
  int last = -1;
  // TUM colour/depth association: nearest time stamp within this (seconds), the TUM tools'
  // rule.
  double max_time_difference = 0.02;
  // Frame rate assumed for layouts without time stamps (7-Scenes, Redwood, SUN3D):
  // timestamp = frame_number / assumed_fps.
  double assumed_fps = 30.0;
  // 7-Scenes / 3DMatch folders with seq-XX subfolders: read only the one of this name
  // (empty: all of them, joined in order; the pair across each join is not a real motion).
  std::string sequence;
  // Check every listed image exists when reading (cheap; catches missing frames up front).
  bool check_files = true;
  // ROS bags: the topics to read (empty: found by name for RealSense recordings, else the one
  // depth and the one colour image topic) and the depth camera's CameraInfo topic (empty: the
  // depth topic's sibling camera_info).
  std::string depth_topic, color_topic, camera_info_topic;
  // ROS bags: metres per unit of 16-bit depth (0: the recording's own, else 0.001).
  double depth_scale = 0;
  // Recordings whose colour is another camera: colour resampled into the depth camera
  // (depth), or depth forward-warped into the colour camera (color). BENCHMARKS.md measures
  // both.
  AlignTo align_to = AlignTo::kDepth;
  // The time a frame (and its pose in every trajectory written) is stamped with: the depth
  // image's, whose geometry the registration measures, or the colour image's (the TUM tools'
  // convention; the two images are then taken as one moment, RgbdFrame::color_time 0).
  // Unsynchronised streams such as TUM's Kinect differ by up to 20 ms, which is up to 8 mm of
  // motion on a hand-held camera; BENCHMARKS.md ("Colour and depth moments") measures both.
  FrameStamp stamp = FrameStamp::kDepth;

  template <class V>
  void Fields(V& v) {
    v.Group("Frames");
    F2C_FIELD(
        v, intrinsics, "--intrinsics", {},
        "fx,fy,cx,cy[,k1,k2,p1,p2[,k3]] or a preset: tum-fr1, tum-fr2, tum-fr3, primesense (TUM folders carry none; "
        "overrides a dataset's own; with distortion, frames are resampled to the pinhole model)");
    F2C_FIELD(v, every, "--every", AtLeast(1), "use every N-th frame");
    F2C_FIELD(v, first, "--first", AtLeast(0), "first frame (0-based)");
    F2C_FIELD(v, last, "--last", AtLeast(-1), "last frame, inclusive (-1: the end)");
    F2C_FIELD(v, sequence, "--sequence", {},
              "7-Scenes/3DMatch: read only this seq-XX subfolder (default: all, joined)");
    F2C_FIELD(v, max_time_difference, "", Positive(),
              "TUM: colour and depth images this close in time (s) are a frame");
    F2C_FIELD(v, assumed_fps, "", Positive(), "frame rate of layouts without timestamps");
    F2C_FIELD(v, check_files, "", {}, "check that every listed image exists");
    F2C_FIELD(v, depth_topic, "--depth-topic", {},
              "ROS bags: the depth image topic (default: RealSense's, else the one depth image topic)");
    F2C_FIELD(v, color_topic, "--color-topic", {},
              "ROS bags: the colour image topic (default: RealSense's, else the one colour image topic)");
    F2C_FIELD(v, camera_info_topic, "--camera-info-topic", {},
              "ROS bags: the depth camera's CameraInfo topic (default: the depth topic's camera_info)");
    F2C_FIELD(v, align_to, "--align-to", {},
              "recordings with two cameras: depth (colour resampled into the depth camera) or color (depth warped "
              "into the colour camera, holes left empty)");
    F2C_FIELD(v, stamp, "--stamp", {},
              "depth or color: whose time stamp a frame and its pose carry where the two images have their own "
              "(color: the two are taken as one moment)");
    F2C_FIELD(v, depth_scale, "--depth-scale", AtLeast(0.0),
              "ROS bags: metres per unit of 16-bit depth (0: the recording's own, else 0.001)");
  }
  void Check() const;  // InputError naming the option when out of range
};

// Detects the layout of `path` (a folder, or an authors' .conf file) and reads it. Raises
// InputError with one line naming the file and what is wrong.
RgbdSequence ReadSequence(const std::filesystem::path& path, const IoOptions& options = {});

// Ground truth from a trajectory file or a dataset folder (or .conf; then `*dataset` holds
// it: its frame time stamps place estimates that carry frame ids, and its frames feed the
// report). InputError naming `path` when a dataset has none.
Trajectory LoadGroundTruth(const std::filesystem::path& path, IoOptions io, std::optional<RgbdSequence>* dataset);

// A trajectory without time stamps (.log by frame id, .conf by image name: FramesOfPoses)
// placed at the times of the sequence's frames; poses of frames the sequence does not hold
// are left out. A trajectory with time stamps is returned as it is.
Trajectory PlaceAtFrames(Trajectory trajectory, const RgbdSequence& sequence, const std::filesystem::path& path);

// The names of the sequence's frames (RgbdFrame::name), in order.
std::vector<std::string> FrameNames(const RgbdSequence& sequence);

// Whether `path` is a recording (a .sens file, by its content) rather than a trajectory file:
// a recording's poses are its ground truth, read with its frames.
bool IsRecordingFile(const std::filesystem::path& path);

// The layout of `path`, or InputError("<path>: unknown dataset layout ...").
DatasetLayout DetectLayout(const std::filesystem::path& path);

// The sequence's intrinsics, or InputError("<root>: no intrinsics: pass --intrinsics ...")
// for a folder that carries none (TUM).
const CameraIntrinsics& RequireIntrinsics(const RgbdSequence& sequence);

// What every cache key of one run shares: the options' JSON, intrinsics and depth decoding
// (the odometry's pair cache and the feature cache both key on it).
std::string CacheContext(const RgbdSequence& sequence, const std::string& options_json);

// A hash of one frame's depth and colour files' bytes (the caches' per-frame key part).
uint64_t HashFrameFiles(const RgbdFrame& frame);
// The hash of a frame's depth image alone (its bytes in a recording when it is embedded).
uint64_t HashFrameDepth(const RgbdFrame& frame);

}  // namespace f2c
