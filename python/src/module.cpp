// The Python module starnav._starnav (docs/python.md): the library's errors, settings and
// declarations; the maps, terrain, planning, cloud, simulator, estimation and experiment parts are
// bound in their own translation units (maps.cpp, planning.cpp, cloud.cpp, simulation.cpp,
// estimation.cpp, experiments.cpp) to keep each compile small.
#include <Python.h>

#include <cerrno>
#include <new>
#include <system_error>

#include "bindings.hpp"
#include "starnav/cloud/cloud_filters.hpp"
#include "starnav/config.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/file_error.hpp"
#include "starnav/experiment/plan_query.hpp"
#include "starnav/registry/components.hpp"
#include "starnav/terrain/terrain_analysis.hpp"
#include "starnav/terrain/terrain_generator.hpp"

namespace starnav::python {

namespace {

PyObject* input_error = nullptr;
PyObject* file_error = nullptr;
PyObject* missing_file_error = nullptr;

// UTF-8 text from the library (file names may hold any bytes: those that are not UTF-8 are shown
// escaped, never a UnicodeDecodeError).
py::str text_of(const std::string& s) {
  return py::reinterpret_steal<py::str>(PyUnicode_DecodeUTF8(s.data(), static_cast<Py_ssize_t>(s.size()), "backslashreplace"));
}

void raise(PyObject* type, const Error& e, int system_errno) {
  py::object exc = py::reinterpret_borrow<py::object>(type)(text_of(e.what()));
  exc.attr("file") = e.file().empty() ? py::object(py::none()) : py::object(text_of(e.file()));
  exc.attr("line") = e.line() > 0 ? py::object(py::int_(e.line())) : py::object(py::none());
  exc.attr("field") = e.field().empty() ? py::object(py::none()) : py::object(text_of(e.field()));
  exc.attr("message") = text_of(e.message());
  // Only errno: with strerror or filename set, OSError's str() would no longer be the line.
  if (system_errno != 0) exc.attr("errno") = system_errno;
  PyErr_SetObject(type, exc.ptr());
}

PyObject* new_exception(const char* name, PyObject* bases, const char* doc) {
  PyObject* type = PyErr_NewExceptionWithDoc(name, doc, bases, nullptr);
  if (!type) throw py::error_already_set();
  return type;
}

}  // namespace

void bind_errors(py::module_& m) {
  input_error = new_exception("starnav.InputError", PyExc_ValueError,
                              "Bad input: the library's one-line message (FILE:LINE: FIELD: what is wrong), with the "
                              "attributes file, line, field and message.");
  file_error = new_exception("starnav.FileError", PyExc_OSError,
                             "A file that does not exist or cannot be read or written: the library's one-line message, "
                             "errno, and the attributes file, line, field and message.");
  py::tuple missing_bases = py::make_tuple(py::handle(file_error), py::handle(PyExc_FileNotFoundError));
  missing_file_error = new_exception("starnav.MissingFileError", missing_bases.ptr(),
                                     "A file that does not exist (a FileError and a FileNotFoundError).");
  m.attr("InputError") = py::handle(input_error);
  m.attr("FileError") = py::handle(file_error);
  m.attr("MissingFileError") = py::handle(missing_file_error);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const FileError& e) {
      raise(e.system_errno() == ENOENT ? missing_file_error : file_error, e, e.system_errno());
    } catch (const Error& e) {
      raise(input_error, e, 0);
    } catch (const std::system_error& e) {
      PyErr_SetString(PyExc_OSError, e.what());
    }
  });
}

void warn_deprecated(const std::string& warning) {
  if (warning.empty()) return;
  py::module_::import("warnings").attr("warn")(warning, py::module_::import("builtins").attr("DeprecationWarning"),
                                               py::arg("stacklevel") = 3);
}

// ---- settings ---------------------------------------------------------------------------------------

std::string setting_text(const py::handle& value, const std::string& key) {
  PyObject* v = value.ptr();
  if (PyBool_Check(v)) return v == Py_True ? "true" : "false";
  if (PyLong_Check(v)) return py::str(value);
  if (PyFloat_Check(v)) return format_param_real(PyFloat_AsDouble(v));
  if (PyUnicode_Check(v)) return value.cast<std::string>();
  if (py::hasattr(value, "dtype") && py::hasattr(value, "item") && py::getattr(value, "ndim", py::int_(1)).cast<int>() == 0)
    return setting_text(value.attr("item")(), key);  // a numpy scalar
  if (PyList_Check(v) || PyTuple_Check(v) || py::isinstance(value, py::module_::import("numpy").attr("ndarray"))) {
    std::string text;
    for (const py::handle item : value) text += (text.empty() ? "" : ", ") + setting_text(item, key);
    return "[" + text + "]";  // a name list ([a, b]) or nested lists (polygons: [[[x, y], ...], ...])
  }
  throw py::type_error(key + ": expected a number, a boolean, a name or a list, got " + std::string(Py_TYPE(v)->tp_name));
}

std::vector<ParamSetting> settings_of(const py::dict& kwargs) {
  std::vector<ParamSetting> out;
  for (const auto& [k, v] : kwargs) {
    if (v.is_none()) continue;
    const std::string key = py::str(k);
    out.push_back({key, setting_text(v, key), {}, 0, {}});
  }
  return out;
}

// ---- declarations -----------------------------------------------------------------------------------

py::dict spec_dict(const ParamSpec& s) {
  py::dict d;
  d["key"] = s.key;
  d["type"] = param_type_name(s.type);
  d["default"] = s.default_value;
  d["range"] = s.range_text();
  d["choices"] = s.choices;
  d["unit"] = s.unit;
  d["doc"] = s.doc;
  return d;
}

py::list specs_list(const std::vector<ParamSpec>& specs) {
  py::list l;
  for (const ParamSpec& s : specs) l.append(spec_dict(s));
  return l;
}

py::dict component_dict(const ComponentInfo& i) {
  py::dict d;
  d["role"] = role_name(i.role);
  d["name"] = i.name;
  d["aliases"] = i.deprecated_aliases;
  d["section"] = i.section;
  d["summary"] = i.summary;
  d["capabilities"] = i.capabilities.names();
  d["params"] = specs_list(i.params);
  d["nav2"] = i.nav2_counterpart;
  return d;
}

void bind_registry(py::module_& m) {
  m.def(
      "components",
      [](const std::string& role) {
        py::list out;
        for (const ComponentInfo& i : all_components())
          if (role.empty() || role == role_name(i.role)) out.append(component_dict(i));
        return out;
      },
      py::arg("role") = "",
      "Every registered component (of one role: global_planner, scan_matcher_3d, ...) with its declared parameters.");
  m.def(
      "declared_parameters",
      [](const std::string& table) -> py::list {
        if (table == "plan_occupancy") return specs_list(occupancy_plan_params().specs());
        if (table == "plan_terrain") {
          TerrainPlanQuery defaults;
          defaults.options.heuristic = LiuHeuristic::Paper;  // as terrain_plan_query's
          return specs_list(terrain_plan_params().specs(defaults));
        }
        if (table == "terrain_analysis") return specs_list(terrain_analysis_params().specs());
        if (table == "hills") return specs_list(hills_params().specs());
        if (table == "road") return specs_list(road_params().specs());
        if (table == "prefilter") return specs_list(prefilter_params().specs());
        throw Error("unknown table '" + table + "' (plan_occupancy, plan_terrain, terrain_analysis, hills, road, prefilter)",
                    {}, 0, "table");
      },
      py::arg("table"), "The declared parameters of one of the library's option tables.");
  py::dict build;
  build["version"] = STARNAV_VERSION;
  build["gdal"] = static_cast<bool>(STARNAV_HAVE_GDAL);
  build["pcl"] = static_cast<bool>(STARNAV_HAVE_PCL);
  m.attr("build_info") = build;
  m.attr("__version__") = STARNAV_VERSION;
}

}  // namespace starnav::python

PYBIND11_MODULE(_starnav, m) {
  m.doc() = "starnav's C++ library (docs/python.md); use the package starnav, which builds its API on this module.";
  starnav::python::bind_errors(m);
  starnav::python::bind_registry(m);
  starnav::python::bind_maps(m);
  starnav::python::bind_terrain(m);
  starnav::python::bind_planning(m);
  starnav::python::bind_cloud(m);
  starnav::python::bind_mapping3d(m);
  starnav::python::bind_simulation(m);
  starnav::python::bind_estimation(m);
  starnav::python::bind_experiments(m);
}
