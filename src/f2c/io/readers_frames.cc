// Layouts of numbered frame files: 7-Scenes / 3DMatch (frame-XXXXXX.{color,depth,pose}),
// Redwood / Open3D (color/ + depth/), SUN3D (image/ + depth/ + intrinsics.txt).

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <map>
#include <regex>

#include "f2c/io/readers.h"
#include "f2c/util/error.h"
#include "f2c/util/file.h"
#include "f2c/util/text.h"

namespace f2c::internal {
namespace fs = std::filesystem;

std::vector<fs::path> ListImages(const fs::path& dir) {
  std::vector<fs::path> images;
  if (!fs::is_directory(dir)) return images;
  for (const auto& e : fs::directory_iterator(dir)) {
    std::string ext = e.path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
    if (e.is_regular_file() && (ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".ppm" || ext == ".pgm")) {
      images.push_back(e.path());
    }
  }
  std::sort(images.begin(), images.end());
  return images;
}

namespace {

Eigen::Matrix4d ReadMatrix4File(const fs::path& path) {
  const std::vector<double> v = ReadNumberFile(path, 16, "a 4x4 pose matrix");
  Eigen::Matrix4d m;
  for (int i = 0; i < 16; ++i) m(i / 4, i % 4) = v[i];
  return m;
}

// 7-Scenes frames of one folder: frame number -> (colour, depth, pose) paths.
struct NumberedFrame {
  long number;
  fs::path color, depth, pose;
};

std::vector<NumberedFrame> ListNumberedFrames(const fs::path& dir) {
  static const std::regex kDepth(R"(frame-(\d+)\.depth\.png)");
  std::vector<NumberedFrame> frames;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    std::smatch m;
    if (!std::regex_match(name, m, kDepth)) continue;
    NumberedFrame f;
    f.number = std::stol(m[1]);
    const std::string stem = "frame-" + m[1].str();
    f.depth = e.path();
    f.color = dir / (stem + ".color.png");
    if (!fs::exists(f.color)) f.color = dir / (stem + ".color.jpg");
    if (!fs::exists(f.color)) ThrowInputError(dir / (stem + ".color.png"), "missing colour image for " + name);
    f.pose = dir / (stem + ".pose.txt");
    frames.push_back(f);
  }
  std::sort(frames.begin(), frames.end(),
            [](const NumberedFrame& a, const NumberedFrame& b) { return a.number < b.number; });
  return frames;
}

}  // namespace

RgbdSequence ReadSevenScenes(const fs::path& dir, const IoOptions& options) {
  RgbdSequence seq;
  seq.depth_scale = 0.001;
  seq.invalid_depth_values = {0, 65535};
  std::vector<fs::path> folders;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.is_directory() && e.path().filename().string().rfind("seq-", 0) == 0) {
      folders.push_back(e.path());
    }
  }
  std::sort(folders.begin(), folders.end());
  if (!options.sequence.empty()) {
    const fs::path chosen = dir / options.sequence;
    if (std::find(folders.begin(), folders.end(), chosen) == folders.end()) {
      std::vector<std::string> names;
      for (const fs::path& f : folders) names.push_back(f.filename().string());
      ThrowInputError(dir,
                      fmt::format("no sequence folder '{}' (it has: {})", options.sequence,
                                  names.empty() ? std::string("none") : fmt::format("{}", fmt::join(names, ", "))));
    }
    folders = {chosen};
  } else {
    if (folders.size() > 1) {
      spdlog::warn(
          "{}: {} seq-XX folders joined into one sequence; the pair across each join is not a real "
          "motion (--sequence NAME reads one)",
          dir.string(), folders.size());
    }
    folders.insert(folders.begin(), dir);
  }
  Trajectory gt;
  long number_offset = 0;  // keeps time stamps increasing across seq-XX folders
  for (const fs::path& folder : folders) {
    const auto frames = ListNumberedFrames(folder);
    for (const NumberedFrame& f : frames) {
      RgbdFrame frame;
      frame.timestamp = (number_offset + f.number) / options.assumed_fps;
      frame.color_path = f.color;
      frame.depth_path = f.depth;
      frame.name = f.depth.filename().string();
      seq.frames.push_back(frame);
      if (fs::exists(f.pose)) {
        gt.Add(frame.timestamp, RigidFromMatrixOrThrow(ReadMatrix4File(f.pose), f.pose, 0));
      }
    }
    if (!frames.empty()) number_offset += frames.back().number + 1;
  }
  if (!gt.empty()) {
    seq.ground_truth = std::move(gt);
    seq.ground_truth_source = dir / "frame-*.pose.txt";
  }
  for (const fs::path& candidate : {dir / "camera-intrinsics.txt", folders.back() / "camera-intrinsics.txt"}) {
    if (fs::exists(candidate)) {
      seq.intrinsics = ReadIntrinsicsMatrixFile(candidate);
      seq.intrinsics_source = candidate.string();
      break;
    }
  }
  return seq;
}

CameraIntrinsics ReadOpen3dIntrinsics(const fs::path& path) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(ReadFileToString(path));
  } catch (const nlohmann::json::exception& e) {
    ThrowInputError(path, std::string("not valid JSON: ") + e.what());
  }
  if (!j.contains("intrinsic_matrix") || !j["intrinsic_matrix"].is_array() || j["intrinsic_matrix"].size() != 9) {
    ThrowInputError(path, "expected 'intrinsic_matrix' with 9 numbers (Open3D intrinsic JSON)");
  }
  std::vector<double> m;
  for (const auto& v : j["intrinsic_matrix"]) {
    if (!v.is_number()) ThrowInputError(path, "'intrinsic_matrix' holds a non-number");
    m.push_back(v.get<double>());
  }
  for (const char* key : {"width", "height"}) {
    if (j.contains(key) &&
        (!j[key].is_number_integer() || j[key].get<int64_t>() <= 0 || j[key].get<int64_t>() > 100000)) {
      ThrowInputError(path, std::string("'") + key + "' must be a whole number of pixels (1 to 100000)");
    }
  }
  CameraIntrinsics k{m[0], m[4], m[6], m[7], j.value("width", 640), j.value("height", 480)};
  k.Validate(path.string());
  return k;
}

RgbdSequence ReadRedwood(const fs::path& dir, const IoOptions& options) {
  RgbdSequence seq;
  seq.depth_scale = 0.001;
  const fs::path color_dir = fs::is_directory(dir / "color") ? dir / "color" : dir / "image";
  const auto colors = ListImages(color_dir);
  const auto depths = ListImages(dir / "depth");
  if (depths.empty()) ThrowInputError(dir / "depth", "holds no depth image");
  if (colors.size() != depths.size()) {
    ThrowInputError(dir, fmt::format("{} colour images in {} but {} depth images in depth/", colors.size(),
                                     color_dir.filename().string(), depths.size()));
  }
  for (size_t i = 0; i < colors.size(); ++i) {
    RgbdFrame frame;
    frame.timestamp = i / options.assumed_fps;
    frame.color_path = colors[i];
    frame.depth_path = depths[i];
    frame.name = depths[i].filename().string();
    seq.frames.push_back(frame);
  }
  for (const char* name : {"camera_intrinsic.json", "intrinsic.json", "intrinsics.json"}) {
    if (fs::exists(dir / name)) {
      seq.intrinsics = ReadOpen3dIntrinsics(dir / name);
      seq.intrinsics_source = (dir / name).string();
    }
  }
  if (!seq.intrinsics) {
    // Open3D's own default for these folders: the nominal PrimeSense camera.
    seq.intrinsics = ParseIntrinsics("primesense", "primesense");
    seq.intrinsics_source = "primesense (default; no intrinsic JSON in the folder)";
  }
  if (fs::exists(dir / "trajectory.log")) {
    Trajectory log = ReadLogTrajectory(dir / "trajectory.log");
    Trajectory gt;
    for (size_t i = 0; i < log.size(); ++i) {
      const auto id = static_cast<long>(log.timestamps[i]);
      if (id < 0 || id >= static_cast<long>(seq.frames.size())) {
        ThrowInputError(dir / "trajectory.log",
                        fmt::format("pose for frame {} but the folder has {} frames", id, seq.frames.size()));
      }
      gt.Add(seq.frames[id].timestamp, log.world_from_camera[i]);
    }
    seq.ground_truth = std::move(gt);
    seq.ground_truth_source = dir / "trajectory.log";
  }
  return seq;
}

namespace {

// SUN3D names frames `%07d-%012d.ext`: frame number, then time stamp in microseconds.
bool Sun3dTimestamp(const fs::path& path, double* seconds) {
  static const std::regex kName(R"(\d+-(\d+))");
  std::smatch m;
  const std::string stem = path.stem().string();
  if (!std::regex_match(stem, m, kName)) return false;
  *seconds = std::stod(m[1]) * 1e-6;
  return true;
}

}  // namespace

RgbdSequence ReadSun3d(const fs::path& dir, const IoOptions& options) {
  RgbdSequence seq;
  seq.depth_scale = 0.001;
  seq.depth_encoding = DepthEncoding::kSun3dBitRotated;
  seq.intrinsics = ReadIntrinsicsMatrixFile(dir / "intrinsics.txt");
  seq.intrinsics_source = (dir / "intrinsics.txt").string();
  const auto colors = ListImages(dir / "image");
  const auto depths = ListImages(dir / "depth");
  if (colors.empty()) ThrowInputError(dir / "image", "holds no colour image");
  if (depths.empty()) ThrowInputError(dir / "depth", "holds no depth image");
  std::vector<double> tc, td;
  bool stamped = true;
  for (const auto& p : colors) stamped = stamped && Sun3dTimestamp(p, &tc.emplace_back());
  for (const auto& p : depths) stamped = stamped && Sun3dTimestamp(p, &td.emplace_back());
  if (stamped) {
    // SUN3D's own tools pair each colour image with the depth image nearest in time.
    for (size_t i = 0; i < colors.size(); ++i) {
      const auto it = std::lower_bound(td.begin(), td.end(), tc[i]);
      size_t j = std::min<size_t>(it - td.begin(), td.size() - 1);
      if (j > 0 && std::abs(td[j - 1] - tc[i]) <= std::abs(td[j] - tc[i])) --j;
      seq.frames.push_back({tc[i], colors[i], depths[j], depths[j].filename().string(), {}, {}});
    }
  } else {
    if (colors.size() != depths.size()) {
      ThrowInputError(dir, fmt::format("{} colour images but {} depth images, and the names carry "
                                       "no time stamps to pair them",
                                       colors.size(), depths.size()));
    }
    for (size_t i = 0; i < colors.size(); ++i) {
      seq.frames.push_back({i / options.assumed_fps, colors[i], depths[i], depths[i].filename().string(), {}, {}});
    }
  }
  // extrinsics/: the newest file (by name) holds one 3x4 camera-to-world per colour frame.
  const auto extrinsics = fs::is_directory(dir / "extrinsics") ? dir / "extrinsics" : fs::path();
  if (!extrinsics.empty()) {
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(extrinsics)) {
      if (e.is_regular_file() && e.path().extension() == ".txt") files.push_back(e.path());
    }
    std::sort(files.begin(), files.end());
    if (!files.empty()) {
      const fs::path& file = files.back();
      const auto lines = ReadDataLines(file);
      if (lines.size() != 3 * seq.frames.size()) {
        ThrowInputError(file, fmt::format("expected 3 lines (a 3x4 pose) per frame for {} frames, "
                                          "got {} lines",
                                          seq.frames.size(), lines.size()));
      }
      Trajectory gt;
      for (size_t f = 0; f < seq.frames.size(); ++f) {
        Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
        for (int r = 0; r < 3; ++r) {
          const TextLine& line = lines[3 * f + r];
          const auto tokens = SplitWhitespace(line.text);
          if (tokens.size() != 4) ThrowInputError(file, line.number, "expected a pose row of 4 numbers");
          const auto v = ParseDoublesOrThrow(tokens, 0, file, line.number, "a pose row of 4 numbers");
          m.row(r) << v[0], v[1], v[2], v[3];
        }
        gt.Add(seq.frames[f].timestamp, RigidFromMatrixOrThrow(m, file, lines[3 * f].number));
      }
      seq.ground_truth = std::move(gt);
      seq.ground_truth_source = file;
    }
  }
  return seq;
}

}  // namespace f2c::internal
