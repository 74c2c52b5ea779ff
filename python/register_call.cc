#include "python/register_call.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cmath>
#include <mutex>
#include <opencv2/imgproc.hpp>
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>
#include <vector>

#include "f2c/io/image_write.h"
#include "f2c/pipeline/outputs.h"
#include "f2c/util/error.h"
#include "f2c/util/file.h"
#include "python/arguments.h"

namespace f2c::python {
namespace fs = std::filesystem;

nlohmann::json Result::Stats() const {
  OutputOptions outputs;
  outputs.input = input;
  outputs.io = io;
  return RunJson(result, options, outputs);
}

namespace {

// The registration's options from keyword arguments: the stages' fields by their long option
// names, and the few words of the command line that are not fields.
struct RegisterCall {
  IoOptions io;
  RegisterOptions options;
  std::optional<fs::path> initial_trajectory;
};

RegisterCall ParseRegisterOptions(const py::kwargs& kwargs) {
  RegisterCall call;
  RegisterOptions& o = call.options;
  o.quiet = true;
  o.fuse_mesh = false;
  Preset preset = Preset::kDefault;
  std::vector<std::string> given;  // "--flag" of each option set, which a preset leaves alone
  std::string stop_after = "refine";
  ForEachOption(kwargs, [&](const std::string& name, const std::string& flag, const py::handle& value) {
    const FieldValue v = ToFieldValue(flag, value);
    auto want_bool = [&] {
      if (!std::holds_alternative<bool>(v)) ThrowInputError("--" + flag, "must be True or False");
      return std::get<bool>(v);
    };
    if (name == "preset") {
      if (!std::holds_alternative<std::string>(v)) ThrowInputError("--preset", "must be a string");
      preset = FromName<Preset>(std::get<std::string>(v), "--preset");
    } else if (name == "stop_after") {
      if (!std::holds_alternative<std::string>(v) ||
          (std::get<std::string>(v) != "odometry" && std::get<std::string>(v) != "refine")) {
        ThrowInputError("--stop-after", "must be 'odometry' or 'refine'");
      }
      stop_after = std::get<std::string>(v);
    } else if (name == "mesh") {
      o.fuse_mesh = want_bool();
    } else if (name == "features") {
      o.extract_features = want_bool();
    } else if (name == "quiet") {
      o.quiet = want_bool();
    } else if (name == "save_iterations") {
      o.keep_iterations = want_bool();
    } else if (name == "threads") {
      if (!std::holds_alternative<int64_t>(v)) ThrowInputError("--threads", "must be a whole number");
      const int64_t t = std::get<int64_t>(v);
      if (t < 0 || t > 1024) ThrowInputError("--threads", "must be in [0, 1024], got " + std::to_string(t));
      o.threads = static_cast<int>(t);
    } else if (name == "initial_trajectory") {
      call.initial_trajectory = PathArg(py::reinterpret_borrow<py::object>(value), "--initial-trajectory", true);
    } else if (!SetFieldByFlag(call.io, flag, v) && !SetFieldByFlag(o.odometry, flag, v) &&
               !SetFieldByFlag(o.features, flag, v) && !SetFieldByFlag(o.refine, flag, v) &&
               !SetFieldByFlag(o.fusion, flag, v)) {
      ThrowInputError(name, "unknown option (register's options, with '_' for '-': fine2coarse register --help-all)");
    }
    given.push_back("--" + flag);
  });
  ApplyPreset(preset, &o, [&](const std::string& f) {
    for (const std::string& g : given) {
      if (g == f) return true;
    }
    return false;
  });
  o.preset = preset;
  o.refine_poses = stop_after == "refine";
  if (stop_after == "odometry") o.fuse_mesh = false;
  o.CheckStart(call.initial_trajectory.has_value());
  call.io.Check();
  o.Check();
  return call;
}

// The progress callback, called from the pipeline's threads with the GIL taken; the first
// exception it raises is kept and raised when register() returns.
struct ProgressBridge {
  py::object callback;
  std::mutex mutex;
  std::optional<py::error_already_set> error;

  ProgressListener Listener() {
    if (callback.is_none()) return nullptr;
    return [this](const std::string& stage, long done, long total) {
      py::gil_scoped_acquire gil;
      std::lock_guard<std::mutex> lock(mutex);
      if (error) return;
      try {
        callback(stage, done, total);
      } catch (py::error_already_set& e) {
        error.emplace(std::move(e));
      }
    };
  }
};

Result RegisterSequence(RgbdSequence sequence, RegisterCall call, const py::object& progress, std::string input) {
  ProgressBridge bridge;
  bridge.callback = progress;
  call.options.progress = bridge.Listener();
  Result r;
  r.io = call.io;
  r.input = std::move(input);
  if (call.initial_trajectory) {
    call.options.initial_poses = PosesFor(sequence, *call.initial_trajectory, call.io);
    call.options.initial_name = call.initial_trajectory->string();
  }
  {
    // quiet (the default here): the stages' log lines too, as register -q; restored after.
    struct LogLevel {
      spdlog::level::level_enum saved = spdlog::get_level();
      ~LogLevel() { spdlog::set_level(saved); }
    } log_level;
    if (call.options.quiet) spdlog::set_level(spdlog::level::warn);
    py::gil_scoped_release release;
    r.result = Register(std::move(sequence), call.options);
  }
  call.options.progress = nullptr;  // the callback must not outlive the call
  r.options = std::move(call.options);
  if (bridge.error) throw std::move(*bridge.error);
  return r;
}

// One image of a list or array of images, as a C-contiguous array of `dtype`; InputError
// naming the argument when its shape is not `channels` deep or its size differs.
template <class T>
py::array_t<T, py::array::c_style> ImageArg(const py::handle& item, const char* what, size_t k, int channels,
                                            py::ssize_t height, py::ssize_t width) {
  const auto array = py::array::ensure(item);
  if (!array) ThrowInputError(what, fmt::format("frame {}: not an array", k));
  if (!array.dtype().is(py::dtype::of<T>())) {
    ThrowInputError(what, fmt::format("frame {}: dtype {} (wanted {})", k, py::str(array.dtype()).cast<std::string>(),
                                      py::str(py::dtype::of<T>()).cast<std::string>()));
  }
  const bool shape_ok = channels == 1 ? array.ndim() == 2 : array.ndim() == 3 && array.shape(2) == channels;
  if (!shape_ok || (height > 0 && (array.shape(0) != height || array.shape(1) != width))) {
    ThrowInputError(what, fmt::format("frame {}: shape {} (wanted {}{})", k, ShapeText(array),
                                      height > 0 ? fmt::format("{} x {}", height, width) : std::string("H x W"),
                                      channels == 1 ? "" : " x 3"));
  }
  return py::array_t<T, py::array::c_style>::ensure(array);
}

}  // namespace

Result RegisterPath(const py::object& path, const py::object& progress, const py::kwargs& kwargs) {
  const fs::path input = PathArg(path, "path", true);
  RegisterCall call = ParseRegisterOptions(kwargs);
  RgbdSequence sequence = ReadSequence(input, call.io);
  return RegisterSequence(std::move(sequence), std::move(call), progress, fs::absolute(input).string());
}

// Frames in memory, written as a TUM folder (PNG colour, 16-bit PNG depth at TUM's 5000 units
// per metre, rgb.txt, depth.txt) in a temporary folder and registered from there: the one
// reader every stage already trusts. Depth: uint16 in units of depth_scale metres, or float32
// metres; stored at 0.2 mm, and beyond 13.1 m (the PNG's range at that unit) as invalid.
Result RegisterFrames(const py::sequence& colors, const py::sequence& depths, const py::object& intrinsics,
                      const py::object& timestamps, double depth_scale, const py::object& progress,
                      const py::kwargs& kwargs) {
  const size_t n = py::len(colors);
  if (py::len(depths) != n)
    ThrowInputError("depths", fmt::format("{} depth images for {} colour images", py::len(depths), n));
  if (n < 2) ThrowInputError("colors", "registration needs at least 2 frames");
  if (!(depth_scale > 0) || !std::isfinite(depth_scale)) {
    ThrowInputError("depth_scale", fmt::format("must be a positive number of metres per unit, got {}", depth_scale));
  }
  std::vector<double> times;
  if (!timestamps.is_none()) {
    times = py::array_t<double, py::array::forcecast>::ensure(timestamps).cast<std::vector<double>>();
    if (times.size() != n) ThrowInputError("timestamps", fmt::format("{} time stamps for {} frames", times.size(), n));
    for (size_t k = 0; k < n; ++k) {
      // Increasing as the list's microseconds show them.
      if (!std::isfinite(times[k]) || (k > 0 && times[k] - times[k - 1] < 1e-6)) {
        ThrowInputError("timestamps", fmt::format("must be finite and increasing (frame {})", k));
      }
    }
  } else {
    for (size_t k = 0; k < n; ++k) times.push_back(static_cast<double>(k) / 30.0);
  }
  std::array<double, 4> k4{};
  try {
    if (py::isinstance<py::dict>(intrinsics)) {
      const py::dict d = intrinsics;
      k4 = {d["fx"].cast<double>(), d["fy"].cast<double>(), d["cx"].cast<double>(), d["cy"].cast<double>()};
    } else {
      const auto v = intrinsics.cast<std::vector<double>>();
      if (v.size() != 4) throw py::cast_error();
      k4 = {v[0], v[1], v[2], v[3]};
    }
  } catch (const py::error_already_set&) {
    ThrowInputError("intrinsics", "must be (fx, fy, cx, cy) or a dict with fx, fy, cx, cy");
  } catch (const py::cast_error&) {
    ThrowInputError("intrinsics", "must be (fx, fy, cx, cy) or a dict with fx, fy, cx, cy");
  }
  RegisterCall call = ParseRegisterOptions(kwargs);
  call.io.intrinsics = fmt::format("{:.17g},{:.17g},{:.17g},{:.17g}", k4[0], k4[1], k4[2], k4[3]);

  static std::atomic<int> calls{0};
  const fs::path dir = fs::temp_directory_path() / fmt::format("fine2coarse_frames_{}_{}", getpid(), calls++);
  fs::remove_all(dir);
  fs::create_directories(dir / "rgb");
  fs::create_directories(dir / "depth");
  struct Cleanup {
    fs::path dir;
    ~Cleanup() {
      std::error_code ec;
      fs::remove_all(dir, ec);
    }
  } cleanup{dir};
  std::string rgb_txt = "# color images (fine2coarse.register_frames)\n", depth_txt = "# depth images\n";
  py::ssize_t height = 0, width = 0;
  for (size_t k = 0; k < n; ++k) {
    const auto c = ImageArg<uint8_t>(colors[k], "colors", k, 3, height, width);
    height = c.shape(0);
    width = c.shape(1);
    cv::Mat bgr;
    cv::cvtColor(cv::Mat(static_cast<int>(height), static_cast<int>(width), CV_8UC3, const_cast<uint8_t*>(c.data())),
                 bgr, cv::COLOR_RGB2BGR);
    cv::Mat units(static_cast<int>(height), static_cast<int>(width), CV_16U);
    const py::object d = depths[k];
    const auto as_float = py::array::ensure(d);
    if (as_float && as_float.dtype().is(py::dtype::of<float>())) {
      const auto m = ImageArg<float>(d, "depths", k, 1, height, width);
      for (int y = 0; y < units.rows; ++y) {
        for (int x = 0; x < units.cols; ++x) {
          const double v = std::round(static_cast<double>(*m.data(y, x)) * 5000.0);
          units.at<uint16_t>(y, x) = std::isfinite(v) && v > 0 && v <= 65535 ? static_cast<uint16_t>(v) : 0;
        }
      }
    } else {
      const auto u = ImageArg<uint16_t>(d, "depths", k, 1, height, width);
      for (int y = 0; y < units.rows; ++y) {
        for (int x = 0; x < units.cols; ++x) {
          const double v = std::round(*u.data(y, x) * depth_scale * 5000.0);
          units.at<uint16_t>(y, x) = v > 0 && v <= 65535 ? static_cast<uint16_t>(v) : 0;
        }
      }
    }
    const std::string name = fmt::format("{:06d}.png", k);
    WritePngFile(dir / "rgb" / name, bgr);
    WritePngFile(dir / "depth" / name, units);
    rgb_txt += fmt::format("{:.6f} rgb/{}\n", times[k], name);
    depth_txt += fmt::format("{:.6f} depth/{}\n", times[k], name);
  }
  WriteFileAtomic(dir / "depth.txt", depth_txt);
  WriteFileAtomic(dir / "rgb.txt", rgb_txt);
  RgbdSequence sequence = ReadSequence(dir, call.io);
  return RegisterSequence(std::move(sequence), std::move(call), progress, "(frames in memory)");
}

}  // namespace f2c::python
