#include "f2c/io/conf.h"

#include <fmt/format.h>

#include <cctype>
#include <unordered_map>

#include "f2c/util/error.h"
#include "f2c/util/file.h"
#include "f2c/util/text.h"

namespace f2c {
namespace fs = std::filesystem;

namespace {

// The depth decoding a dataset name selects; false for a name we do not know (a guess would
// read depth at the wrong scale: TUM's 1/5000 m read as millimetres is 5x too far).
bool SetDepthDecoding(std::string dataset, RgbdSequence* sequence) {
  for (char& c : dataset) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  sequence->depth_encoding = DepthEncoding::kPlain;
  sequence->depth_scale = 0.001;
  sequence->invalid_depth_values = {0};
  if (dataset == "tum") {
    sequence->depth_scale = 1.0 / 5000.0;
  } else if (dataset == "sun3d") {
    sequence->depth_encoding = DepthEncoding::kSun3dBitRotated;
  } else if (dataset == "7scenes" || dataset == "3dmatch") {
    sequence->invalid_depth_values = {0, 65535};
  } else if (dataset != "redwood") {
    return false;
  }
  return true;
}

}  // namespace

ConfFile ReadConf(const fs::path& path, double assumed_fps) {
  ConfFile conf;
  RgbdSequence& seq = conf.sequence;
  seq.root = path.parent_path();
  seq.layout = DatasetLayout::kConf;
  const fs::path dir = path.parent_path();
  fs::path depth_dir = dir, image_dir = dir;
  long n_images = -1;
  bool have_dataset = false;
  std::unordered_map<std::string, long> line_of_depth;  // a frame named twice is ambiguous
  for (const TextLine& line : ReadDataLines(path)) {
    const auto tokens = SplitWhitespace(line.text);
    if (tokens.empty()) continue;  // ReadDataLines keeps none such; a reader must not trust that
    const std::string& key = tokens[0];
    auto need = [&](size_t n, const char* what) {
      if (tokens.size() != n) {
        ThrowInputError(path, line.number, fmt::format("'{}' expects {}", key, what));
      }
    };
    if (key == "dataset") {
      need(2, "one name");
      if (!SetDepthDecoding(tokens[1], &seq)) {
        ThrowInputError(path, line.number,
                        fmt::format("unknown dataset '{}' (expected tum, sun3d, 7scenes, 3dmatch or redwood: it "
                                    "selects how depth is decoded)",
                                    tokens[1]));
      }
      have_dataset = true;
    } else if (key == "intrinsics") {
      need(2, "one file name");
      seq.intrinsics = ReadIntrinsicsMatrixFile(dir / tokens[1]);
      seq.intrinsics_source = (dir / tokens[1]).string();
    } else if (key == "intrinsics_matrix") {
      need(10, "9 numbers (a row-major 3x3 matrix)");
      const auto m = ParseDoublesOrThrow(tokens, 1, path, line.number, "9 numbers");
      CameraIntrinsics k{m[0], m[4], m[2], m[5], 640, 480, false};
      k.Validate(fmt::format("{}:{}", path.string(), line.number));
      seq.intrinsics = k;
      seq.intrinsics_source = path.string();
    } else if (key == "n_images") {
      need(2, "one integer");
      if (!ParseInt(tokens[1], &n_images) || n_images < 0) {
        ThrowInputError(path, line.number, "'n_images' expects a non-negative integer");
      }
    } else if (key == "depth_directory") {
      need(2, "one folder");
      depth_dir = dir / tokens[1];
    } else if (key == "image_directory") {
      need(2, "one folder");
      image_dir = dir / tokens[1];
    } else if (key == "scan") {
      if (tokens.size() != 19) {
        ThrowInputError(
            path, line.number,
            fmt::format("'scan' expects '<depth> <colour>' and 16 numbers, got {} fields", tokens.size() - 1));
      }
      const auto v = ParseDoublesOrThrow(tokens, 3, path, line.number, "16 matrix numbers");
      Eigen::Matrix4d m;
      for (int i = 0; i < 16; ++i) m(i / 4, i % 4) = v[i];
      const auto [named, first] = line_of_depth.emplace(tokens[1], line.number);
      if (!first) {
        ThrowInputError(path, line.number,
                        fmt::format("scan line names depth image '{}' again (line {})", tokens[1], named->second));
      }
      const int index = static_cast<int>(seq.frames.size());
      conf.trajectory.Add(index, RigidFromMatrixOrThrow(m, path, line.number));
      conf.trajectory.frame_names.push_back(tokens[1]);
      RgbdFrame frame;
      frame.timestamp = index / assumed_fps;
      frame.depth_path = depth_dir / tokens[1];
      frame.color_path = image_dir / tokens[2];
      frame.name = tokens[1];
      seq.frames.push_back(frame);
    } else {
      ThrowInputError(path, line.number,
                      fmt::format("unknown key '{}' (expected dataset, intrinsics, "
                                  "intrinsics_matrix, n_images, depth_directory, "
                                  "image_directory or scan)",
                                  key));
    }
  }
  conf.trajectory.has_timestamps = false;
  if (!have_dataset) ThrowInputError(path, "missing 'dataset' line");
  if (seq.frames.empty()) ThrowInputError(path, "no 'scan' line");
  if (n_images >= 0 && static_cast<size_t>(n_images) != seq.frames.size()) {
    ThrowInputError(path, fmt::format("n_images says {} but {} scan lines follow", n_images, seq.frames.size()));
  }
  return conf;
}

void WriteConf(const fs::path& path, const RgbdSequence& sequence, const Trajectory& trajectory) {
  F2C_CHECK(trajectory.size() == sequence.frames.size(), "one pose per frame");
  F2C_CHECK(!sequence.frames.empty(), "a sequence has frames");
  const fs::path depth_dir = fs::absolute(sequence.frames[0].depth_path).parent_path();
  const fs::path image_dir = fs::absolute(sequence.frames[0].color_path).parent_path();
  std::string dataset = "redwood";
  if (sequence.depth_encoding == DepthEncoding::kSun3dBitRotated) {
    dataset = "sun3d";
  } else if (sequence.depth_scale == 1.0 / 5000.0) {
    dataset = "tum";
  } else if (sequence.invalid_depth_values.size() > 1) {
    dataset = "7scenes";
  }
  std::string out = fmt::format("dataset {}\n", dataset);
  if (sequence.intrinsics) {
    const CameraIntrinsics& k = *sequence.intrinsics;
    out += fmt::format("intrinsics_matrix {:.6g} 0 {:.6g} 0 {:.6g} {:.6g} 0 0 1\n", k.fx, k.cx, k.fy, k.cy);
  }
  out += fmt::format("n_images {}\n", sequence.frames.size());
  out += fmt::format("depth_directory {}\n", depth_dir.string());
  out += fmt::format("image_directory {}\n", image_dir.string());
  for (size_t i = 0; i < sequence.frames.size(); ++i) {
    const RgbdFrame& f = sequence.frames[i];
    if (fs::absolute(f.depth_path).parent_path() != depth_dir ||
        fs::absolute(f.color_path).parent_path() != image_dir) {
      ThrowInputError(path, "cannot write a .conf: frames lie in more than one folder");
    }
    out += fmt::format("scan {} {}", f.depth_path.filename().string(), f.color_path.filename().string());
    const Eigen::Matrix4d m = trajectory.world_from_camera[i].matrix();
    for (int r = 0; r < 4; ++r) {
      for (int c = 0; c < 4; ++c) out += fmt::format(" {:.12g}", m(r, c));
    }
    out += '\n';
  }
  WriteFileAtomic(path, out);
}

}  // namespace f2c
