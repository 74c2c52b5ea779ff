#pragma once
// Python values in and out of the library's types for the module `fine2coarse`: paths,
// keyword options (by the command line's long names, util/fields_set.h), pose arrays,
// trajectories, meshes. Bad input is an InputError naming the argument, as on the command line.

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>  // in every file of the module: one set of type casters

#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "f2c/geometry/intrinsics.h"
#include "f2c/io/ply.h"
#include "f2c/io/trajectory.h"
#include "f2c/util/fields_set.h"

namespace f2c::python {

namespace py = pybind11;
using PoseList = std::vector<Rigid3d, Eigen::aligned_allocator<Rigid3d>>;

// str or os.PathLike.
bool IsPath(const py::handle& value);
// A path argument; TypeError when it is not one, FileNotFoundError when it must exist and does not.
std::filesystem::path PathArg(const py::object& value, const char* what, bool must_exist);

// A Python keyword value as a field value: bool before int (a bool is an int in Python).
FieldValue ToFieldValue(const std::string& name, const py::handle& value);
// Each keyword option with its flag's long name ("voxel_size" -> "voxel-size"); None is refused.
void ForEachOption(
    const py::kwargs& kwargs,
    const std::function<void(const std::string& name, const std::string& flag, const py::handle& value)>& f);

// "480 x 640 x 3": an array's shape as error messages give it.
std::string ShapeText(const py::array& array);

// Poses as N x 4 x 4 float64; NaN where a pose is absent.
py::array_t<double> PoseArray(const PoseList& poses);
py::array_t<double> PoseArray(const std::vector<std::optional<Rigid3d>>& poses);
// An N x 4 x 4 array (any real dtype, any strides) as rigid transforms; InputError naming
// `what` for a wrong shape, a non-finite entry or a matrix that is not a rigid transform.
PoseList PosesFromArray(const py::handle& value, const std::string& what);
// A trajectory from a path (TUM, .log, .conf) or from poses and time stamps (None: frame indices).
Trajectory TrajectoryArg(const py::object& value, const py::object& timestamps, const std::string& what);

py::object JsonToPython(const nlohmann::json& j);
// vertices, triangles, colors, normals as arrays.
py::dict MeshDict(const PlyPoints& mesh);
py::dict IntrinsicsDict(const CameraIntrinsics& intrinsics);

}  // namespace f2c::python
