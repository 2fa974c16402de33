#pragma once
// What the translation units of the Python module share (docs/python.md): the library's errors as
// Python exceptions, keyword arguments as the library's settings, declared parameters and
// components as dicts (from which starnav/_generate.py makes the planner and matcher functions,
// their docstrings and the type stubs), and numpy views of the library's own storage that keep
// their owner alive.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cerrno>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "starnav/cloud/point_cloud.hpp"
#include "starnav/core/component.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/file_error.hpp"
#include "starnav/core/params.hpp"
#include "starnav/io/map_file.hpp"
#include "starnav/sim/scenario.hpp"

namespace starnav::python {

namespace py = pybind11;

// ---- errors ---------------------------------------------------------------------------------------

// starnav.InputError (a ValueError), starnav.FileError (an OSError) and starnav.MissingFileError
// (a FileError and a FileNotFoundError), created once by bind_errors; every starnav::Error
// crossing into Python becomes one of them, its text the CLI's error line without "starnav:
// error: ", with the attributes file, line, field and message.
void bind_errors(py::module_& m);

// A deprecated alias's warning from the registry (empty: none) as a DeprecationWarning.
void warn_deprecated(const std::string& warning);

// A path argument (str or os.PathLike) as text.
inline std::string path_of(const py::handle& p) { return py::module_::import("os").attr("fspath")(p).cast<std::string>(); }

// The drivers' readers report a file that is not there as bad input (the CLI's exit 2); Python
// raises MissingFileError (an OSError) for it, with the same line.
template <class Call>
auto with_missing_files(const std::vector<std::string>& inputs, Call&& call) {
  try {
    return call();
  } catch (const FileError&) {
    throw;
  } catch (const Error& e) {
    for (const std::string& p : inputs) {
      std::error_code ec;
      if (!p.empty() && e.file() == p && !std::filesystem::exists(p, ec))
        throw FileError(e.field().empty() ? e.message() : e.field() + ": " + e.message(), e.file(), ENOENT);
    }
    throw;
  }
}

// ---- settings ---------------------------------------------------------------------------------------

// One keyword argument as the text a scenario or --set would give: True/False -> "true"/"false",
// an integer as itself, a float as its shortest exact text, a str as it is, a list, tuple or
// array -> "[a, b]" (a name list; nested, polygons "[[[x, y], ...], ...]"). Anything else is a
// TypeError naming `key`.
std::string setting_text(const py::handle& value, const std::string& key);
// The keyword arguments that are not None, in the order given, as settings whose field is empty
// (so errors name the key, as the keyword was written).
std::vector<ParamSetting> settings_of(const py::dict& kwargs);

// ---- declarations as dicts ------------------------------------------------------------------------

// {key, type, default, range, choices, unit, doc} of one declared parameter.
py::dict spec_dict(const ParamSpec& spec);
py::list specs_list(const std::vector<ParamSpec>& specs);
// {role, name, aliases, section, summary, capabilities, params, nav2} of one component.
py::dict component_dict(const ComponentInfo& info);

// ---- arrays -----------------------------------------------------------------------------------------

// A numpy array over memory owned by `owner` (the Python object holding the C++ storage): no copy,
// and the array keeps `owner` alive. Read-only unless `writable`.
template <class T>
py::array view_of(const T* data, std::vector<py::ssize_t> shape, py::handle owner, bool writable = false) {
  std::vector<py::ssize_t> strides(shape.size());
  py::ssize_t stride = static_cast<py::ssize_t>(sizeof(T));
  for (std::size_t i = shape.size(); i-- > 0;) {
    strides[i] = stride;
    stride *= shape[i];
  }
  py::array a(py::dtype::of<T>(), std::move(shape), std::move(strides), data, owner);
  if (!writable) a.attr("setflags")(py::arg("write") = false);
  return a;
}

// A numpy array that owns `values` (moved into a capsule): no copy of the elements.
template <class T>
py::array owning_array(std::vector<T>&& values, std::vector<py::ssize_t> shape) {
  auto* held = new std::vector<T>(std::move(values));
  py::capsule owner(held, [](void* p) { delete static_cast<std::vector<T>*>(p); });
  std::vector<py::ssize_t> strides(shape.size());
  py::ssize_t stride = static_cast<py::ssize_t>(sizeof(T));
  for (std::size_t i = shape.size(); i-- > 0;) {
    strides[i] = stride;
    stride *= shape[i];
  }
  return py::array(py::dtype::of<T>(), std::move(shape), std::move(strides), held->data(), owner);
}

// ---- point clouds ------------------------------------------------------------------------------

// Points read from an (N, 3) array: in place when it is float64 and C-ordered (Eigen's Vec3 is
// three packed doubles), else from a float64 copy; `array` keeps the memory alive. Errors name
// `field`.
struct Points {
  py::array_t<double, py::array::c_style | py::array::forcecast> array;
  std::span<const Vec3> span;
};
Points points_of(const py::handle& data, const char* field);
// An (N, 3) float64 array owning `cloud` (no copy of the points).
py::array cloud_array(PointCloud&& cloud);
// None (identity), a 4 x 4 rigid transform, or (x, y, z, roll, pitch, yaw) in metres and degrees
// as the CLI's --initial; errors name `field`.
Rigid3 transform_of(const py::handle& initial, const char* field = "initial");
// A 4 x 4 float64 array of `t`.
py::array matrix_array(const Rigid3& t);

// ---- scenarios -------------------------------------------------------------------------------------

// `set` ({dotted key: value} or None) as scenario overrides, checked as --set's.
std::vector<ScenarioOverride> overrides_of(const py::object& sets);
// A scenario from a file (`path`), or from YAML `text` that names itself `file` in errors.
ScenarioSpec scenario_of(const py::object& path, const py::object& text, const std::string& file, const py::object& sets);

// ---- maps -------------------------------------------------------------------------------------------

// A map as the Python classes OccupancyMap and ElevationMap hold it: the library's LoadedMap (the
// map, its file's format and metadata), shared so that arrays, results and planners can keep it
// alive, and where it came from ("array", "hills", "road" or the file's path).
struct MapHandle {
  std::shared_ptr<const LoadedMap> loaded;
  std::string source;  // the file read, or how it was made
  bool from_file = false;
  const GridGeometry& geometry() const { return loaded->geometry(); }
  // MovingAI maps and y-down grids: the CLI's units are cells there.
  bool index_grid() const { return loaded->format == MapFormat::MovingAi || geometry().y_down; }
};
struct OccupancyMapHandle : MapHandle {};
struct ElevationMapHandle : MapHandle {};

// The Python object of a loaded map (an OccupancyMap or an ElevationMap).
py::object wrap_map(LoadedMap&& loaded, std::string source, bool from_file);

// ---- the module's parts -----------------------------------------------------------------------------

void bind_registry(py::module_& m);
void bind_maps(py::module_& m);
void bind_terrain(py::module_& m);
void bind_planning(py::module_& m);
void bind_cloud(py::module_& m);
void bind_mapping3d(py::module_& m);
void bind_simulation(py::module_& m);
void bind_estimation(py::module_& m);
void bind_experiments(py::module_& m);

}  // namespace starnav::python
