#include "f2c/io/sequence.h"

#include "f2c/io/image.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <opencv2/imgcodecs.hpp>

#include "f2c/io/conf.h"
#include "f2c/io/readers.h"
#include "f2c/util/error.h"
#include "f2c/util/file.h"

namespace f2c {
namespace fs = std::filesystem;

std::string LayoutName(DatasetLayout layout) {
  switch (layout) {
    case DatasetLayout::kTum:
      return "tum";
    case DatasetLayout::kSevenScenes:
      return "7scenes";
    case DatasetLayout::kRedwood:
      return "redwood";
    case DatasetLayout::kSun3d:
      return "sun3d";
    case DatasetLayout::kConf:
      return "conf";
    case DatasetLayout::kSens:
      return "sens";
    case DatasetLayout::kRosbag:
      return "rosbag";
  }
  return "?";
}

void IoOptions::Check() const {
  CheckFields(*this);
  if (last >= 0 && last < first) {
    ThrowInputError("--last", fmt::format("{} is before --first {}", last, first));
  }
  if (!intrinsics.empty()) ParseIntrinsics(intrinsics, "--intrinsics");
}

namespace {

bool HasSevenScenesFrames(const fs::path& dir) {
  auto has_depth_frames = [](const fs::path& d) {
    for (const auto& e : fs::directory_iterator(d)) {
      const std::string name = e.path().filename().string();
      if (name.rfind("frame-", 0) == 0 && name.ends_with(".depth.png")) return true;
    }
    return false;
  };
  if (has_depth_frames(dir)) return true;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.is_directory() && e.path().filename().string().rfind("seq-", 0) == 0 && has_depth_frames(e.path())) {
      return true;
    }
  }
  return false;
}

std::vector<fs::path> ConfFilesIn(const fs::path& dir) {
  std::vector<fs::path> confs;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.is_regular_file() && e.path().extension() == ".conf") confs.push_back(e.path());
  }
  return confs;
}

void SelectFrames(const fs::path& path, const IoOptions& options, RgbdSequence* sequence) {
  const int n = static_cast<int>(sequence->frames.size());
  const int last = options.last < 0 ? n - 1 : std::min(options.last, n - 1);
  std::vector<RgbdFrame> selected;
  for (int i = options.first; i <= last; i += options.every) selected.push_back(sequence->frames[i]);
  if (selected.empty()) {
    ThrowInputError(path, fmt::format("frame selection --first {} --last {} leaves no frame "
                                      "(the sequence has {})",
                                      options.first, options.last, n));
  }
  sequence->frames = std::move(selected);
}

void CheckFilesExist(const RgbdSequence& sequence) {
  for (const RgbdFrame& frame : sequence.frames) {
    for (const fs::path& p : {frame.color_path, frame.depth_path}) {
      if (!fs::is_regular_file(p)) ThrowInputError(p, "missing frame image (listed in the dataset)");
    }
  }
}

}  // namespace

DatasetLayout DetectLayout(const fs::path& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) ThrowInputError(path, "no such file or folder");
  if (fs::is_regular_file(path)) {
    if (path.extension() == ".conf") return DatasetLayout::kConf;
    // Recordings by their content, whatever their names.
    if (internal::LooksLikeSens(path)) return DatasetLayout::kSens;
    if (internal::LooksLikeRosbag(path)) return DatasetLayout::kRosbag;
    ThrowInputError(path, "not a dataset folder, .conf, .sens or ROS bag file");
  }
  if (fs::is_empty(path, ec)) ThrowInputError(path, "folder is empty");
  if (fs::exists(path / "rgb.txt") && fs::exists(path / "depth.txt")) return DatasetLayout::kTum;
  if (HasSevenScenesFrames(path)) return DatasetLayout::kSevenScenes;
  if (fs::is_directory(path / "image") && fs::is_directory(path / "depth") && fs::exists(path / "intrinsics.txt")) {
    return DatasetLayout::kSun3d;
  }
  if ((fs::is_directory(path / "color") || fs::is_directory(path / "image")) && fs::is_directory(path / "depth")) {
    return DatasetLayout::kRedwood;
  }
  if (ConfFilesIn(path).size() == 1) return DatasetLayout::kConf;
  if (internal::LooksLikeRosbag(path)) return DatasetLayout::kRosbag;  // a ROS 2 bag folder
  ThrowInputError(path,
                  "unknown dataset layout (expected TUM rgb.txt + depth.txt, 7-Scenes/3DMatch "
                  "frame-*.depth.png, SUN3D image/ + depth/ + intrinsics.txt, Redwood color/ + "
                  "depth/, one .conf file, or a ROS 2 bag's metadata.yaml)");
}

RgbdSequence ReadSequence(const fs::path& path, const IoOptions& options) {
  options.Check();
  const DatasetLayout layout = DetectLayout(path);
  RgbdSequence sequence;
  switch (layout) {
    case DatasetLayout::kTum:
      sequence = internal::ReadTum(path, options);
      break;
    case DatasetLayout::kSevenScenes:
      sequence = internal::ReadSevenScenes(path, options);
      break;
    case DatasetLayout::kRedwood:
      sequence = internal::ReadRedwood(path, options);
      break;
    case DatasetLayout::kSun3d:
      sequence = internal::ReadSun3d(path, options);
      break;
    case DatasetLayout::kSens:
      sequence = internal::ReadSens(path, options);
      break;
    case DatasetLayout::kRosbag:
      sequence = internal::ReadRosbag(path, options);
      break;
    case DatasetLayout::kConf: {
      const fs::path conf_path = fs::is_directory(path) ? ConfFilesIn(path)[0] : path;
      ConfFile conf = ReadConf(conf_path, options.assumed_fps);
      sequence = std::move(conf.sequence);
      // The scan poses of a .conf are a trajectory, usually an estimate; they serve as
      // ground truth only when nothing better exists, which is how the authors use them.
      conf.trajectory.has_timestamps = true;
      for (size_t i = 0; i < conf.trajectory.size(); ++i) {
        conf.trajectory.timestamps[i] = sequence.frames[i].timestamp;
      }
      conf.trajectory.frame_names.clear();  // placed in time: its own frames
      sequence.ground_truth = std::move(conf.trajectory);
      sequence.ground_truth_source = conf_path;
      break;
    }
  }
  sequence.root = path;
  sequence.layout = layout;
  if (!options.intrinsics.empty()) {
    sequence.intrinsics = ParseIntrinsics(options.intrinsics, "--intrinsics");
    sequence.intrinsics_source = "--intrinsics " + options.intrinsics;
  }
  if (sequence.frames.empty()) ThrowInputError(path, "dataset holds no frame");
  // Depth into the colour camera: the colour camera becomes the sequence's.
  if (options.align_to == AlignTo::kColor && sequence.color_camera && sequence.intrinsics) {
    sequence.depth_camera = DepthCamera{*sequence.intrinsics, sequence.color_camera->color_from_depth};
    sequence.intrinsics = sequence.color_camera->intrinsics;
    sequence.intrinsics_source += " (the colour camera: --align-to color)";
    // Poses, the recording's of its depth camera, become the colour camera's.
    if (sequence.ground_truth) {
      const Rigid3d depth_from_color = sequence.color_camera->color_from_depth.inverse();
      for (Rigid3d& world_from_depth : sequence.ground_truth->world_from_camera) {
        world_from_depth = world_from_depth * depth_from_color;
      }
    }
    sequence.color_camera.reset();
  }
  SelectFrames(path, options, &sequence);
  if (options.check_files) {
    CheckFilesExist(sequence);
    // Intrinsics without an image size (a 3x3 matrix, fx,fy,cx,cy) take the first depth
    // image's; every frame is then checked against it when decoded.
    if (sequence.intrinsics && !sequence.intrinsics->size_known) {
      const RgbdFrame& first = sequence.frames.front();
      const cv::Mat depth = ReadFrameImage(first.depth_path, first.depth_embedded, cv::IMREAD_UNCHANGED);
      sequence.intrinsics->width = depth.cols;
      sequence.intrinsics->height = depth.rows;
      sequence.intrinsics->size_known = true;
      sequence.intrinsics->Validate(sequence.intrinsics_source);
    }
  }
  return sequence;
}

const CameraIntrinsics& RequireIntrinsics(const RgbdSequence& seq) {
  if (!seq.intrinsics) {
    ThrowInputError(seq.root,
                    "no intrinsics: pass --intrinsics (a preset: tum-fr1, tum-fr2, "
                    "tum-fr3, primesense; or fx,fy,cx,cy)");
  }
  return *seq.intrinsics;
}

namespace {

uint64_t HashImage(const fs::path& path, const std::optional<EmbeddedImage>& embedded) {
  if (!embedded) return HashFile(path);
  return HashBytes(ReadEmbeddedBytes(path, *embedded));
}

}  // namespace

uint64_t HashFrameDepth(const RgbdFrame& frame) { return HashImage(frame.depth_path, frame.depth_embedded); }

uint64_t HashFrameFiles(const RgbdFrame& frame) {
  return HashFrameDepth(frame) ^ (HashImage(frame.color_path, frame.color_embedded) * 31);
}

std::string CacheContext(const RgbdSequence& seq, const std::string& options_json) {
  std::string context = options_json;
  if (seq.intrinsics) {
    const CameraIntrinsics& k = *seq.intrinsics;
    context += fmt::format("|K {:.17g} {:.17g} {:.17g} {:.17g} {} {}", k.fx, k.fy, k.cx, k.cy, k.width, k.height);
    if (k.HasDistortion()) context += fmt::format("|D {:.17g}", fmt::join(k.distortion, " "));
  }
  context += fmt::format("|depth {:.17g} {} {}", seq.depth_scale, static_cast<int>(seq.depth_encoding),
                         fmt::join(seq.invalid_depth_values, ","));
  if (seq.color_camera) {  // colour resampled from another camera: what SIFT sees depends on it
    const CameraIntrinsics& c = seq.color_camera->intrinsics;
    const Eigen::Matrix4d m = seq.color_camera->color_from_depth.matrix();
    context += fmt::format("|C {:.17g} {:.17g} {:.17g} {:.17g} {} {} {:.17g} {:.17g}", c.fx, c.fy, c.cx, c.cy, c.width,
                           c.height, fmt::join(m.data(), m.data() + 16, " "), fmt::join(c.distortion, " "));
  }
  if (seq.depth_camera) {  // depth warped from another camera: what every stage sees depends on it
    const CameraIntrinsics& d = seq.depth_camera->intrinsics;
    const Eigen::Matrix4d m = seq.depth_camera->color_from_depth.matrix();
    context += fmt::format("|W {:.17g} {:.17g} {:.17g} {:.17g} {} {} {:.17g} {:.17g}", d.fx, d.fy, d.cx, d.cy, d.width,
                           d.height, fmt::join(d.distortion, " "), fmt::join(m.data(), m.data() + 16, " "));
  }
  return context;
}

std::vector<std::string> FrameNames(const RgbdSequence& sequence) {
  std::vector<std::string> names;
  names.reserve(sequence.frames.size());
  for (const RgbdFrame& f : sequence.frames) names.push_back(f.name);
  return names;
}

Trajectory PlaceAtFrames(Trajectory trajectory, const RgbdSequence& sequence, const fs::path& path) {
  if (trajectory.has_timestamps) return trajectory;
  const std::vector<long> frames = FramesOfPoses(trajectory, FrameNames(sequence), path);
  Trajectory placed;
  for (size_t i = 0; i < frames.size(); ++i) {
    if (frames[i] >= 0) placed.Add(sequence.frames[frames[i]].timestamp, trajectory.world_from_camera[i]);
  }
  return placed;
}

bool IsRecordingFile(const fs::path& path) {
  return fs::is_regular_file(path) && (internal::LooksLikeSens(path) || internal::LooksLikeRosbag(path));
}

Trajectory LoadGroundTruth(const fs::path& path, IoOptions io, std::optional<RgbdSequence>* dataset) {
  if (fs::is_directory(path) || path.extension() == ".conf" || IsRecordingFile(path)) {
    io.check_files = false;
    *dataset = ReadSequence(path, io);
    if (!(*dataset)->ground_truth) ThrowInputError(path, "dataset has no ground-truth trajectory");
    return *(*dataset)->ground_truth;
  }
  return ReadTrajectoryFile(path);
}

}  // namespace f2c
