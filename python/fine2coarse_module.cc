// The Python module `fine2coarse` (docs/python.md): the library's pipeline (pipeline/register.h),
// evaluation and simulator, NumPy in and out. Options are keyword arguments named as the
// command line's long options, with '_' for '-' (util/fields_set.h); bad input raises
// fine2coarse.InputError (a ValueError) with the command line's one-line message, a missing
// path FileNotFoundError. The GIL is released while the pipeline works.

#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cerrno>
#include <cmath>
#include <filesystem>
#include <mutex>
#include <unistd.h>
#include <cstring>
#include <array>
#include <atomic>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "f2c/eval/correspondence_error.h"
#include "f2c/eval/trajectory_error.h"
#include "f2c/io/ply.h"
#include "f2c/io/image.h"
#include "f2c/io/sequence.h"
#include "f2c/io/trajectory.h"
#include "f2c/pipeline/outputs.h"
#include "f2c/pipeline/register.h"
#include "f2c/sim/simulate.h"
#include "f2c/util/error.h"
#include "f2c/util/fields_set.h"
#include "f2c/util/file.h"

namespace py = pybind11;
namespace fs = std::filesystem;

namespace f2c::python {
namespace {

// A path argument: str or os.PathLike; FileNotFoundError when it must exist and does not.
fs::path PathArg(const py::object& value, const char* what, bool must_exist) {
  if (!py::isinstance<py::str>(value) && !py::hasattr(value, "__fspath__")) {
    throw py::type_error(std::string(what) + ": must be a path (str or os.PathLike)");
  }
  const fs::path path = py::str(py::module_::import("os").attr("fspath")(value)).cast<std::string>();
  if (must_exist && !fs::exists(path)) {
    PyErr_SetObject(PyExc_FileNotFoundError,
                    py::make_tuple(ENOENT, path.string() + ": no such file or directory", path.string()).ptr());
    throw py::error_already_set();
  }
  return path;
}

// A Python keyword value as a field value: bool before int (a bool is an int in Python).
FieldValue ToFieldValue(const std::string& name, const py::handle& value) {
  if (py::isinstance<py::bool_>(value)) return value.cast<bool>();
  if (py::isinstance<py::int_>(value)) {
    try {
      return value.cast<int64_t>();
    } catch (const py::cast_error&) {
      ThrowInputError("--" + name,
                      "must be a whole number within the option's type, got " + py::str(value).cast<std::string>());
    }
  }
  if (py::isinstance<py::float_>(value)) return value.cast<double>();
  if (py::isinstance<py::str>(value)) return value.cast<std::string>();
  if (py::hasattr(value, "__fspath__"))
    return py::str(py::module_::import("os").attr("fspath")(value)).cast<std::string>();
  ThrowInputError("--" + name, "must be a bool, int, float, str or path, got " +
                                   py::str(py::type::of(value).attr("__name__")).cast<std::string>());
}

// Poses (N x 4 x 4, float64) of a trajectory.
py::array_t<double> PoseArray(const std::vector<Rigid3d, Eigen::aligned_allocator<Rigid3d>>& poses) {
  py::array_t<double> out({static_cast<py::ssize_t>(poses.size()), py::ssize_t{4}, py::ssize_t{4}});
  auto a = out.mutable_unchecked<3>();
  for (size_t k = 0; k < poses.size(); ++k) {
    const Eigen::Matrix4d m = poses[k].matrix();
    for (int r = 0; r < 4; ++r) {
      for (int c = 0; c < 4; ++c) a(k, r, c) = m(r, c);
    }
  }
  return out;
}

// An N x 4 x 4 array (any real dtype, any strides) as rigid transforms; InputError naming
// `what` for a wrong shape, a non-finite entry or a matrix that is not a rigid transform.
std::vector<Rigid3d, Eigen::aligned_allocator<Rigid3d>> PosesFromArray(const py::handle& value,
                                                                       const std::string& what) {
  py::array_t<double, py::array::forcecast> array;
  try {
    array = py::array_t<double, py::array::forcecast>::ensure(value);
  } catch (const py::error_already_set&) {
  }
  if (!array) ThrowInputError(what, "must be an array of N x 4 x 4 numbers");
  if (array.ndim() != 3 || array.shape(1) != 4 || array.shape(2) != 4) {
    std::string shape;
    for (py::ssize_t i = 0; i < array.ndim(); ++i) shape += (i ? " x " : "") + std::to_string(array.shape(i));
    ThrowInputError(what, "must have shape N x 4 x 4, got " + (shape.empty() ? std::string("a scalar") : shape));
  }
  std::vector<Rigid3d, Eigen::aligned_allocator<Rigid3d>> poses;
  auto a = array.unchecked<3>();
  for (py::ssize_t k = 0; k < array.shape(0); ++k) {
    Eigen::Matrix4d m;
    for (int r = 0; r < 4; ++r) {
      for (int c = 0; c < 4; ++c) m(r, c) = a(k, r, c);
    }
    poses.push_back(RigidFromMatrixOrThrow(m, what, static_cast<int>(k) + 1));
  }
  return poses;
}

// A trajectory from a path (TUM, .log, .conf) or from poses and time stamps.
Trajectory TrajectoryArg(const py::object& value, const py::object& timestamps, const std::string& what) {
  if (py::isinstance<py::str>(value) || py::hasattr(value, "__fspath__")) {
    return ReadTrajectoryFile(PathArg(value, what.c_str(), true));
  }
  Trajectory t;
  const auto poses = PosesFromArray(value, what);
  std::vector<double> times;
  if (!timestamps.is_none()) {
    times = py::array_t<double, py::array::forcecast>::ensure(timestamps).cast<std::vector<double>>();
    if (times.size() != poses.size()) {
      ThrowInputError(what,
                      std::to_string(times.size()) + " time stamps for " + std::to_string(poses.size()) + " poses");
    }
  } else {
    for (size_t k = 0; k < poses.size(); ++k) times.push_back(static_cast<double>(k));
  }
  for (size_t k = 0; k < poses.size(); ++k) {
    if (!std::isfinite(times[k])) ThrowInputError(what, "time stamp " + std::to_string(k) + " is not finite");
    t.Add(times[k], poses[k]);
  }
  t.has_timestamps = !timestamps.is_none();
  return t;
}

py::object JsonToPython(const nlohmann::json& j) { return py::module_::import("json").attr("loads")(j.dump()); }

// What register() returns: the typed result, turned into arrays on access.
struct Result {
  RegisterResult result;
  RegisterOptions options;
  IoOptions io;
  std::string input;

  nlohmann::json Stats() const {
    OutputOptions outputs;
    outputs.input = input;
    outputs.io = io;
    return RunJson(result, options, outputs);
  }
};

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
  for (const auto& [key, value] : kwargs) {
    const std::string name = key.cast<std::string>();
    std::string flag = name;
    for (char& c : flag) c = c == '_' ? '-' : c;
    if (value.is_none()) ThrowInputError("--" + flag, "must not be None");
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
  }
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

Result RegisterPath(const py::object& path, const py::object& progress, const py::kwargs& kwargs) {
  const fs::path input = PathArg(path, "path", true);
  RegisterCall call = ParseRegisterOptions(kwargs);
  RgbdSequence sequence = ReadSequence(input, call.io);
  return RegisterSequence(std::move(sequence), std::move(call), progress, fs::absolute(input).string());
}

// A dataset as read_sequence() returns it: frames decoded on access.
struct Sequence {
  RgbdSequence sequence;

  py::tuple Frame(py::ssize_t i) const {
    const auto n = static_cast<py::ssize_t>(sequence.frames.size());
    if (i < 0) i += n;
    if (i < 0 || i >= n) throw py::index_error("frame " + std::to_string(i) + " of " + std::to_string(n));
    const RgbdFrame& frame = sequence.frames[i];
    cv::Mat depth, color;
    {
      py::gil_scoped_release release;
      depth = LoadDepthMeters(sequence, frame);
      color = LoadColor(sequence, frame, depth.size());
      cv::cvtColor(color, color, cv::COLOR_BGR2RGB);
    }
    py::array_t<uint8_t> c({color.rows, color.cols, 3});
    py::array_t<float> d({depth.rows, depth.cols});
    for (int y = 0; y < color.rows; ++y) {
      std::memcpy(c.mutable_data(y, 0, 0), color.ptr<uint8_t>(y), static_cast<size_t>(color.cols) * 3);
      std::memcpy(d.mutable_data(y, 0), depth.ptr<float>(y), static_cast<size_t>(depth.cols) * sizeof(float));
    }
    return py::make_tuple(c, d);
  }
};

py::dict IntrinsicsDict(const CameraIntrinsics& k) {
  py::dict d;
  d["fx"] = k.fx;
  d["fy"] = k.fy;
  d["cx"] = k.cx;
  d["cy"] = k.cy;
  d["width"] = k.width;
  d["height"] = k.height;
  d["distortion"] = std::vector<double>(k.distortion.begin(), k.distortion.end());
  return d;
}

Sequence ReadSequenceArg(const py::object& path, const py::kwargs& kwargs) {
  const fs::path input = PathArg(path, "path", true);
  IoOptions io;
  for (const auto& [key, value] : kwargs) {
    std::string flag = key.cast<std::string>();
    for (char& c : flag) c = c == '_' ? '-' : c;
    if (value.is_none()) ThrowInputError("--" + flag, "must not be None");
    if (!SetFieldByFlag(io, flag, ToFieldValue(flag, value))) {
      ThrowInputError(key.cast<std::string>(),
                      "unknown option (read_sequence takes intrinsics, first, last, every, "
                      "sequence)");
    }
  }
  io.Check();
  return Sequence{ReadSequence(input, io)};
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
    std::string shape;
    for (py::ssize_t i = 0; i < array.ndim(); ++i) shape += (i ? " x " : "") + std::to_string(array.shape(i));
    ThrowInputError(what, fmt::format("frame {}: shape {} (wanted {}{})", k, shape,
                                      height > 0 ? fmt::format("{} x {}", height, width) : std::string("H x W"),
                                      channels == 1 ? "" : " x 3"));
  }
  return py::array_t<T, py::array::c_style>::ensure(array);
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
      if (!std::isfinite(times[k]) || (k > 0 && times[k] <= times[k - 1])) {
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
    const std::string name = fmt::format("{:.6f}", times[k]);
    if (!cv::imwrite((dir / "rgb" / (name + ".png")).string(), bgr) ||
        !cv::imwrite((dir / "depth" / (name + ".png")).string(), units)) {
      ThrowInputError(dir, "cannot write the frames");
    }
    rgb_txt += fmt::format("{} rgb/{}.png\n", name, name);
    depth_txt += fmt::format("{} depth/{}.png\n", name, name);
  }
  WriteFileAtomic(dir / "depth.txt", depth_txt);
  WriteFileAtomic(dir / "rgb.txt", rgb_txt);
  RgbdSequence sequence = ReadSequence(dir, call.io);
  Result r = RegisterSequence(std::move(sequence), std::move(call), progress, "(frames in memory)");
  return r;
}

py::dict MeshDict(const PlyPoints& m) {
  const auto n = static_cast<py::ssize_t>(m.positions.size());
  py::array_t<double> vertices({n, py::ssize_t{3}}), normals({m.normals.empty() ? 0 : n, py::ssize_t{3}});
  py::array_t<int32_t> triangles({static_cast<py::ssize_t>(m.faces.size()), py::ssize_t{3}});
  py::array_t<uint8_t> colors({m.colors.empty() ? 0 : n, py::ssize_t{3}});
  auto v = vertices.mutable_unchecked<2>();
  auto nn = normals.mutable_unchecked<2>();
  auto t = triangles.mutable_unchecked<2>();
  auto c = colors.mutable_unchecked<2>();
  for (py::ssize_t i = 0; i < n; ++i) {
    for (int k = 0; k < 3; ++k) {
      v(i, k) = m.positions[i][k];
      if (!m.normals.empty()) nn(i, k) = m.normals[i][k];
      if (!m.colors.empty()) c(i, k) = m.colors[i][k];
    }
  }
  for (size_t i = 0; i < m.faces.size(); ++i) {
    for (int k = 0; k < 3; ++k) t(i, k) = m.faces[i][k];
  }
  py::dict d;
  d["vertices"] = vertices;
  d["triangles"] = triangles;
  d["colors"] = colors;
  d["normals"] = normals;
  return d;
}

py::dict Evaluate(const py::object& estimate, const py::object& ground_truth, const py::object& timestamps,
                  const py::object& ground_truth_timestamps, double max_time_difference) {
  EvaluationOptions options;
  options.max_time_difference = max_time_difference;
  options.Check();
  Trajectory gt;
  std::optional<RgbdSequence> dataset;
  fs::path correspondence_file;
  if ((py::isinstance<py::str>(ground_truth) || py::hasattr(ground_truth, "__fspath__"))) {
    const fs::path path = PathArg(ground_truth, "ground_truth", true);
    gt = fs::is_directory(path) ? LoadGroundTruth(path, IoOptions(), &dataset) : ReadTrajectoryFile(path);
    if (dataset && fs::exists(path / "correspondences.txt")) correspondence_file = path / "correspondences.txt";
  } else {
    gt = TrajectoryArg(ground_truth, ground_truth_timestamps, "ground_truth");
  }
  const Trajectory est = TrajectoryArg(estimate, timestamps, "estimate");
  EvaluationResult r;
  std::optional<CorrespondenceResult> corr;
  {
    py::gil_scoped_release release;
    r = f2c::Evaluate(est, gt, options);
    if (!correspondence_file.empty()) {
      // The authors' metric on the folder's ground-truth correspondences, as evaluate gives it.
      std::vector<double> frame_timestamps;
      for (const RgbdFrame& f : dataset->frames) frame_timestamps.push_back(f.timestamp);
      corr = CorrespondenceError(PosesAtFrames(est, frame_timestamps, max_time_difference),
                                 ReadCorrespondences(correspondence_file), correspondence_file.string());
    }
  }
  nlohmann::json j = ToJson(r);
  if (corr) {
    j["correspondences"] = ToJson(*corr);
    j["correspondences"]["file"] = correspondence_file.string();
  }
  return JsonToPython(j);
}

// The frames of a dataset fused at the given poses (fuse's TSDF and marching cubes).
py::dict Fuse(const py::object& path, const py::object& poses, const py::object& timestamps, const py::object& out,
              const py::kwargs& kwargs) {
  const fs::path input = PathArg(path, "path", true);
  IoOptions io;
  FusionOptions fusion;
  for (const auto& [key, value] : kwargs) {
    std::string flag = key.cast<std::string>();
    for (char& c : flag) c = c == '_' ? '-' : c;
    if (value.is_none()) ThrowInputError("--" + flag, "must not be None");
    const FieldValue v = ToFieldValue(flag, value);
    if (!SetFieldByFlag(io, flag, v) && !SetFieldByFlag(fusion, flag, v)) {
      ThrowInputError(key.cast<std::string>(),
                      "unknown option (fuse's options, with '_' for '-': fine2coarse fuse --help)");
    }
  }
  io.Check();
  fusion.Check();
  const RgbdSequence sequence = ReadSequence(input, io);
  RequireIntrinsics(sequence);
  const Trajectory trajectory = TrajectoryArg(poses, timestamps, "poses");
  std::vector<std::optional<Rigid3d>> at;
  if (trajectory.has_timestamps) {
    at = PosesForFrames(sequence, trajectory, io.max_time_difference, "poses");
  } else {
    if (trajectory.size() != sequence.frames.size()) {
      ThrowInputError("poses", fmt::format("{} poses for {} frames (give timestamps= to place them by time)",
                                           trajectory.size(), sequence.frames.size()));
    }
    for (const Rigid3d& p : trajectory.world_from_camera) at.emplace_back(p);
  }
  FusionResult result;
  {
    py::gil_scoped_release release;
    result = FuseTsdf(sequence, at, fusion, true);
  }
  if (!out.is_none()) WritePly(PathArg(out, "out", false), result.mesh);
  return MeshDict(result.mesh);
}

py::array_t<double> Simulate(const std::string& scene, int frames, uint64_t seed, const py::object& out,
                             int correspondences) {
  const fs::path dir = PathArg(out, "out", false);
  sim::SimulateOptions options;
  options.scene = scene;
  options.seed = seed;
  options.walk.frames = frames;
  options.correspondences = correspondences;
  options.Check();
  Trajectory truth;
  {
    py::gil_scoped_release release;
    truth = sim::Simulate(dir, options, true);
  }
  return PoseArray(truth.world_from_camera);
}

}  // namespace
}  // namespace f2c::python

PYBIND11_MODULE(fine2coarse, m) {
  using namespace f2c::python;
  m.doc() =
      "fine2coarse: globally consistent camera poses and a mesh from an RGB-D video (fine-to-coarse global "
      "registration, Halber & Funkhouser, CVPR 2017). See docs/python.md.";
  py::register_exception<f2c::InputError>(m, "InputError", PyExc_ValueError);

  py::class_<Result>(m, "Result", "A registration's result: poses as arrays, the run's record, the mesh when asked.")
      .def_property_readonly(
          "poses", [](const Result& r) { return PoseArray(r.result.poses.world_from_camera); },
          "N x 4 x 4 float64: each frame's camera-to-world pose (refined, or T0 where the refinement did not run)")
      .def_property_readonly(
          "t0", [](const Result& r) { return PoseArray(r.result.odometry.t0.world_from_camera); },
          "N x 4 x 4 float64: the odometry's poses (T0)")
      .def_property_readonly(
          "timestamps", [](const Result& r) { return py::array_t<double>(py::cast(r.result.poses.timestamps)); },
          "N float64: each frame's time stamp (seconds)")
      .def_property_readonly(
          "frame_ids",
          [](const Result& r) {
            std::vector<std::string> ids;
            for (const f2c::RgbdFrame& f : r.result.sequence.frames) ids.push_back(f.name);
            return ids;
          },
          "each frame's name (its depth image's file name)")
      .def_property_readonly(
          "odometry",
          [](const Result& r) {
            py::list out;
            for (const f2c::PairAlignment& p : r.result.odometry.pairs) {
              py::dict d;
              d["frame"] = p.frame;
              d["reference"] = p.Reference();
              d["method"] = f2c::MethodName(p.method);
              d["inliers"] = p.inliers;
              d["fitness"] = p.fitness;
              out.append(d);
            }
            return out;
          },
          "per frame after the first: how the odometry aligned it (frame, reference, method, inliers, fitness)")
      .def_property_readonly(
          "stats", [](const Result& r) { return JsonToPython(r.Stats()); },
          "the run's record, as the command line's run.json holds it (a dict)")
      .def_property_readonly(
          "mesh",
          [](const Result& r) -> py::object {
            return r.result.fusion ? py::object(MeshDict(r.result.fusion->mesh)) : py::none();
          },
          "with mesh=True: a dict of vertices (V x 3 float64), triangles (T x 3 int32), colors (V x 3 uint8) and "
          "normals (V x 3 float64); else None")
      .def(
          "save",
          [](const Result& r, const py::object& outdir, bool report) {
            const fs::path dir = PathArg(outdir, "outdir", false);
            f2c::OutputOptions outputs;
            outputs.report = report;
            outputs.iterations = r.options.keep_iterations;
            outputs.input = r.input;
            outputs.io = r.io;
            py::gil_scoped_release release;
            return f2c::WriteOutputs(dir, r.result, r.options, outputs);
          },
          py::arg("outdir"), py::arg("report") = true,
          "Writes the command line's files into outdir (trajectory.txt, trajectory.log, trajectory.conf, "
          "trajectory_t0.txt, odometry.json, run.json, mesh.ply when fused, report.html unless report=False); "
          "returns their names")
      .def("__repr__", [](const Result& r) {
        return "<fine2coarse.Result: " + std::to_string(r.result.poses.size()) + " frames, " +
               (r.result.refine ? "refined" : "T0") + (r.result.fusion ? ", mesh" : "") + ">";
      });

  m.def("register", &RegisterPath, py::arg("path"), py::kw_only(), py::arg("progress") = py::none(),
        R"(Registers a dataset folder (TUM, 7-Scenes/3DMatch, Redwood/Open3D, SUN3D) or a .conf file.

Keyword options are the command line's (fine2coarse register --help-all) with '_' for '-':
intrinsics='tum-fr1', every=2, first=0, last=-1, preset='fast'|'default'|'paper',
stop_after='odometry'|'refine', structure=False, self_check=False, seed=0, voxel_size=0.01, ...
Beyond them: mesh=True fuses a mesh (off by default), features=False skips the features and the
refinement, quiet=False prints the command line's progress, threads=N, save_iterations=True,
initial_trajectory=PATH. progress=callable(stage, done, total) hears each stage's progress.
The GIL is released while it works. Returns a Result.)");

  py::class_<Sequence>(m, "Sequence", "A dataset as read_sequence() reads it; frames are decoded on access.")
      .def("__len__", [](const Sequence& s) { return s.sequence.frames.size(); })
      .def("__getitem__", &Sequence::Frame, py::arg("index"),
           "(color, depth): H x W x 3 uint8 RGB and H x W float32 metres (0: no depth), as the pipeline reads them "
           "(resampled to the pinhole model where the intrinsics carry distortion)")
      .def_property_readonly(
          "timestamps",
          [](const Sequence& s) {
            std::vector<double> t;
            for (const f2c::RgbdFrame& f : s.sequence.frames) t.push_back(f.timestamp);
            return py::array_t<double>(py::cast(t));
          },
          "N float64 seconds")
      .def_property_readonly(
          "frame_ids",
          [](const Sequence& s) {
            std::vector<std::string> ids;
            for (const f2c::RgbdFrame& f : s.sequence.frames) ids.push_back(f.name);
            return ids;
          },
          "each frame's name")
      .def_property_readonly(
          "intrinsics",
          [](const Sequence& s) -> py::object {
            return s.sequence.intrinsics ? py::object(IntrinsicsDict(*s.sequence.intrinsics)) : py::none();
          },
          "fx, fy, cx, cy, width, height, distortion; None where the folder carries none (TUM: pass intrinsics=)")
      .def_property_readonly(
          "ground_truth",
          [](const Sequence& s) -> py::object {
            if (!s.sequence.ground_truth) return py::none();
            const std::vector<std::optional<f2c::Rigid3d>> at =
                f2c::PosesForFrames(s.sequence, *s.sequence.ground_truth, f2c::IoOptions().max_time_difference,
                                    s.sequence.ground_truth_source);
            py::array_t<double> out({static_cast<py::ssize_t>(at.size()), py::ssize_t{4}, py::ssize_t{4}});
            auto a = out.mutable_unchecked<3>();
            for (size_t k = 0; k < at.size(); ++k) {
              const Eigen::Matrix4d m =
                  at[k] ? at[k]->matrix() : Eigen::Matrix4d::Constant(std::numeric_limits<double>::quiet_NaN());
              for (int r = 0; r < 4; ++r) {
                for (int c = 0; c < 4; ++c) a(k, r, c) = m(r, c);
              }
            }
            return out;
          },
          "N x 4 x 4 camera-to-world poses of the frames (NaN where a frame has none), or None")
      .def_property_readonly(
          "layout", [](const Sequence& s) { return f2c::LayoutName(s.sequence.layout); }, "the layout detected")
      .def("__repr__", [](const Sequence& s) {
        return "<fine2coarse.Sequence: " + s.sequence.root.string() + ", " + f2c::LayoutName(s.sequence.layout) + ", " +
               std::to_string(s.sequence.frames.size()) + " frames>";
      });

  m.def("read_sequence", &ReadSequenceArg, py::arg("path"),
        R"(Reads a dataset folder or .conf as register() would (intrinsics=, first=, last=, every=, sequence=).
Returns a Sequence: len(), seq[i] -> (color RGB uint8, depth float32 metres), timestamps,
frame_ids, intrinsics, ground_truth (N x 4 x 4 or None), layout.)");

  m.def("register_frames", &RegisterFrames, py::arg("colors"), py::arg("depths"), py::arg("intrinsics"), py::kw_only(),
        py::arg("timestamps") = py::none(), py::arg("depth_scale") = 0.001, py::arg("progress") = py::none(),
        R"(Registers frames already in memory (from a camera's SDK): colors, a list or array of H x W x 3
uint8 RGB images; depths, H x W uint16 (units of depth_scale metres, default millimetres) or
float32 metres; intrinsics (fx, fy, cx, cy) or a dict; timestamps in seconds (default 30 Hz).
Depth is kept at 0.2 mm (TUM's unit; beyond 13.1 m it is invalid). Options as register().)");

  m.def("evaluate", &Evaluate, py::arg("estimate"), py::arg("ground_truth"), py::kw_only(),
        py::arg("timestamps") = py::none(), py::arg("ground_truth_timestamps") = py::none(),
        py::arg("max_time_difference") = f2c::EvaluationOptions().max_time_difference,
        R"(ATE, RPE and rotation drift of a trajectory against the ground truth, as `evaluate --json` gives them.

estimate: a trajectory file (TUM, .log, .conf) or an N x 4 x 4 array of camera-to-world poses
(with timestamps=, else frame indices). ground_truth: a trajectory file, a dataset folder with
ground truth, or an array (with ground_truth_timestamps=). Poses are associated by time stamp
within max_time_difference seconds. Returns a dict (ate_m, rpe_per_frame, rpe_per_second,
rotation_drift_deg, ...).)");

  m.def("fuse", &Fuse, py::arg("path"), py::arg("poses"), py::kw_only(), py::arg("timestamps") = py::none(),
        py::arg("out") = py::none(),
        R"(Fuses a dataset's frames at the given poses into a mesh, as `fine2coarse fuse` does: poses an N x 4 x 4
array of camera-to-world poses (one per frame, or placed by timestamps=) or a trajectory file;
options voxel_size=, fuse_every=, intrinsics=, first=, last=, every=, ... Returns the mesh as
a dict of arrays (vertices, triangles, colors, normals); out=PATH also writes it as PLY.)");

  m.def("simulate", &Simulate, py::arg("scene"), py::arg("frames"), py::arg("seed"), py::arg("out"), py::kw_only(),
        py::arg("correspondences") = 400,
        R"(Simulates a scan into the folder out (a TUM layout with groundtruth.txt, correspondences.txt and
scene.ply), as `fine2coarse simulate` does: scene two-rooms, apartment, apartment-square,
corridor or object. Returns the true poses (frames x 4 x 4).)");
}
