#include "f2c/report/embed.h"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>

#include "f2c/features/point_grid.h"
#include "f2c/io/image.h"
#include "f2c/report/svg_plot.h"
#include "f2c/util/error.h"
#include "f2c/util/file.h"

namespace f2c {
namespace fs = std::filesystem;

std::string InlineImage(const std::string& bytes, const std::string& mime, const std::string& alt, int width) {
  return fmt::format("<img width=\"{}\" alt=\"{}\" src=\"data:{};base64,{}\">\n", width, EscapeXml(alt), mime,
                     Base64(bytes));
}

std::string ThreeJs() {
  // The library and its orbit controls (UMD builds: they attach to THREE).
  const fs::path dir = F2C_THREE_JS_DIR;
  const fs::path lib = dir / "three.min.js", controls = dir / "examples" / "js" / "controls" / "OrbitControls.js";
  if (!fs::exists(lib) || !fs::exists(controls)) return "";
  return ReadFileToString(lib) + "\n" + ReadFileToString(controls);
}

void AddSliceFrames(const RgbdSequence& seq, int frames, ReportInput* in) {
  const CameraIntrinsics* intrinsics = seq.intrinsics ? &*seq.intrinsics : nullptr;
  if (!intrinsics || seq.frames.empty()) return;
  PointGridOptions grid;
  grid.step = 8;
  grid.normal_radius_pixels = 16;
  const int n = static_cast<int>(seq.frames.size()), count = std::min(n, frames);
  for (int j = 0; j < count; ++j) {
    const RgbdFrame& frame = seq.frames[static_cast<size_t>(j) * n / count];
    try {
      const PointGrid g = BuildPointGrid(LoadDepthMeters(seq, frame), *intrinsics, grid);
      SliceFrame f;
      for (int i = 0; i < static_cast<int>(g.points.size()); ++i) {
        if (!g.Valid(i)) continue;
        f.points.push_back(g.points[i]);
        f.normals.push_back(g.normals[i]);
      }
      in->slice_timestamps.push_back(frame.timestamp);
      in->slice_frames.push_back(std::move(f));
    } catch (const InputError&) {
    }
  }
}

}  // namespace f2c
