// A dataset folder rewritten as a ScanNet .sens recording, and how fast each reads: depth
// zlib-compressed (as ScanNet's), colour the folder's own encoded bytes, the intrinsics and
// ground-truth poses of the folder (frames without a pose get ScanNet's -inf). Then every
// frame's depth and colour are decoded from the folder and from the recording, and the
// frames per second of each printed as a table row. Registering the folder and the
// recording gives the same trajectory (the same pixels, time stamps and intrinsics).
//   ./build/bench/sens_bench DATASET OUT.sens [--intrinsics ...]

#include <fmt/format.h>
#include <libdeflate.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <opencv2/imgcodecs.hpp>  // the IMREAD_ flags (an enum; nothing of the library is linked)
#include <string>

#include "f2c/io/image.h"
#include "f2c/io/sequence.h"
#include "f2c/util/error.h"
#include "f2c/util/file.h"
#include "f2c/util/timer.h"

namespace {
using namespace f2c;

template <class T>
void Put(std::ofstream& out, T value) {
  out.write(reinterpret_cast<const char*>(&value), sizeof(T));
}

void PutMatrix(std::ofstream& out, const Eigen::Matrix4d& m) {
  for (int i = 0; i < 16; ++i) Put<float>(out, static_cast<float>(m(i / 4, i % 4)));
}

double DecodeAll(const RgbdSequence& seq) {
  Timer timer;
  for (const RgbdFrame& f : seq.frames) {
    const cv::Mat depth = LoadDepthMeters(seq, f);
    LoadColor(seq, f, depth.size());
  }
  return seq.frames.size() / timer.Seconds();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: sens_bench DATASET OUT.sens [--intrinsics ...]\n");
    return 2;
  }
  try {
    IoOptions io;
    if (argc > 4 && std::string(argv[3]) == "--intrinsics") io.intrinsics = argv[4];
    const RgbdSequence seq = ReadSequence(argv[1], io);
    const CameraIntrinsics& k = RequireIntrinsics(seq);
    if (k.HasDistortion() || seq.depth_encoding != DepthEncoding::kPlain) {
      std::fprintf(stderr, "sens_bench: a .sens holds pinhole intrinsics and plain depth only\n");
      return 1;
    }
    // Each frame's ground-truth pose: the nearest in time within the association window.
    std::vector<std::optional<Rigid3d>> poses(seq.frames.size());
    if (seq.ground_truth) {
      for (size_t i = 0; i < seq.frames.size(); ++i) {
        double best = io.max_time_difference;
        for (size_t j = 0; j < seq.ground_truth->size(); ++j) {
          const double dt = std::abs(seq.ground_truth->timestamps[j] - seq.frames[i].timestamp);
          if (dt <= best) best = dt, poses[i] = seq.ground_truth->world_from_camera[j];
        }
      }
    }
    const std::filesystem::path out_path = argv[2];
    std::ofstream out(out_path, std::ios::binary | std::ios::trunc);
    Put<uint32_t>(out, 4);
    const std::string name = "fine2coarse sens_bench";
    Put<uint64_t>(out, name.size());
    out.write(name.data(), static_cast<std::streamsize>(name.size()));
    Eigen::Matrix4d km = Eigen::Matrix4d::Identity();
    km(0, 0) = k.fx, km(1, 1) = k.fy, km(0, 2) = k.cx, km(1, 2) = k.cy;
    PutMatrix(out, km);
    PutMatrix(out, Eigen::Matrix4d::Identity());
    PutMatrix(out, km);
    PutMatrix(out, Eigen::Matrix4d::Identity());
    const std::string first_color = ReadFileToString(seq.frames[0].color_path);
    const bool png = first_color.rfind("\x89PNG", 0) == 0;
    Put<int32_t>(out, png ? 1 : 2);
    Put<int32_t>(out, 1);
    Put<uint32_t>(out, k.width), Put<uint32_t>(out, k.height), Put<uint32_t>(out, k.width),
        Put<uint32_t>(out, k.height);
    Put<float>(out, static_cast<float>(1.0 / seq.depth_scale));
    Put<uint64_t>(out, seq.frames.size());
    libdeflate_compressor* compressor = libdeflate_alloc_compressor(6);
    for (size_t i = 0; i < seq.frames.size(); ++i) {
      const RgbdFrame& f = seq.frames[i];
      cv::Mat raw = DecodeImageFile(f.depth_path, cv::IMREAD_ANYDEPTH | cv::IMREAD_ANYCOLOR);
      for (uint16_t invalid : seq.invalid_depth_values) raw.setTo(0, raw == invalid);
      std::string depth(libdeflate_zlib_compress_bound(compressor, raw.total() * 2), '\0');
      depth.resize(libdeflate_zlib_compress(compressor, raw.data, raw.total() * 2, depth.data(), depth.size()));
      const std::string color = ReadFileToString(f.color_path);
      Eigen::Matrix4d pose = Eigen::Matrix4d::Constant(-std::numeric_limits<double>::infinity());
      if (poses[i]) pose = poses[i]->matrix();
      PutMatrix(out, pose);
      const auto stamp = static_cast<uint64_t>(std::llround(f.timestamp * 1e6));  // microseconds
      Put<uint64_t>(out, stamp), Put<uint64_t>(out, stamp);
      Put<uint64_t>(out, color.size()), Put<uint64_t>(out, depth.size());
      out.write(color.data(), static_cast<std::streamsize>(color.size()));
      out.write(depth.data(), static_cast<std::streamsize>(depth.size()));
    }
    libdeflate_free_compressor(compressor);
    Put<uint64_t>(out, 0);
    out.close();
    const RgbdSequence recording = ReadSequence(out_path, io);
    const double folder_fps = DecodeAll(seq), sens_fps = DecodeAll(recording);
    std::printf("| %s | %zu | %.1f | %.1f | %.1f |\n", std::filesystem::path(argv[1]).filename().c_str(),
                seq.frames.size(), folder_fps, sens_fps, std::filesystem::file_size(out_path) / 1e6);
  } catch (const InputError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
