#include "python/arguments.h"

#include <cerrno>
#include <cmath>
#include <limits>

#include "f2c/util/error.h"

namespace f2c::python {
namespace fs = std::filesystem;

bool IsPath(const py::handle& value) { return py::isinstance<py::str>(value) || py::hasattr(value, "__fspath__"); }

fs::path PathArg(const py::object& value, const char* what, bool must_exist) {
  if (!IsPath(value)) {
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

void ForEachOption(
    const py::kwargs& kwargs,
    const std::function<void(const std::string& name, const std::string& flag, const py::handle& value)>& f) {
  for (const auto& [key, value] : kwargs) {
    const std::string name = key.cast<std::string>();
    std::string flag = name;
    for (char& c : flag) c = c == '_' ? '-' : c;
    if (value.is_none()) ThrowInputError("--" + flag, "must not be None");
    f(name, flag, value);
  }
}

std::string ShapeText(const py::array& array) {
  std::string shape;
  for (py::ssize_t i = 0; i < array.ndim(); ++i) shape += (i ? " x " : "") + std::to_string(array.shape(i));
  return shape.empty() ? std::string("a scalar") : shape;
}

py::array_t<double> PoseArray(const std::vector<std::optional<Rigid3d>>& poses) {
  py::array_t<double> out({static_cast<py::ssize_t>(poses.size()), py::ssize_t{4}, py::ssize_t{4}});
  auto a = out.mutable_unchecked<3>();
  for (size_t k = 0; k < poses.size(); ++k) {
    const Eigen::Matrix4d m =
        poses[k] ? poses[k]->matrix() : Eigen::Matrix4d::Constant(std::numeric_limits<double>::quiet_NaN());
    for (int r = 0; r < 4; ++r) {
      for (int c = 0; c < 4; ++c) a(k, r, c) = m(r, c);
    }
  }
  return out;
}

py::array_t<double> PoseArray(const PoseList& poses) {
  return PoseArray(std::vector<std::optional<Rigid3d>>(poses.begin(), poses.end()));
}

PoseList PosesFromArray(const py::handle& value, const std::string& what) {
  py::array_t<double, py::array::forcecast> array;
  try {
    array = py::array_t<double, py::array::forcecast>::ensure(value);
  } catch (const py::error_already_set&) {
  }
  if (!array) ThrowInputError(what, "must be an array of N x 4 x 4 numbers");
  if (array.ndim() != 3 || array.shape(1) != 4 || array.shape(2) != 4) {
    ThrowInputError(what, "must have shape N x 4 x 4, got " + ShapeText(array));
  }
  PoseList poses;
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

Trajectory TrajectoryArg(const py::object& value, const py::object& timestamps, const std::string& what) {
  if (IsPath(value)) {
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

}  // namespace f2c::python
