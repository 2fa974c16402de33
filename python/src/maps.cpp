// Maps (every format the library reads and writes, built from numpy arrays, shared with numpy
// without a copy), MovingAI scenarios, terrain analysis and the terrain generators.
#include <cmath>
#include <string>
#include <utility>

#include "bindings.hpp"
#include "starnav/core/error.hpp"
#include "starnav/experiment/map_report.hpp"
#include "starnav/io/movingai.hpp"
#include "starnav/terrain/terrain_analysis.hpp"
#include "starnav/terrain/terrain_generator.hpp"

namespace starnav::python {

namespace {

using namespace pybind11::literals;

// (x, y, yaw) from a Python sequence of three numbers; Error naming "origin" otherwise.
Pose2 origin_of(const py::handle& origin) {
  const auto values = py::cast<std::vector<double>>(origin);
  if (values.size() != 3) throw Error("expected (x, y, yaw): three numbers, got " + std::to_string(values.size()), {}, 0, "origin");
  for (double v : values)
    if (!std::isfinite(v)) throw Error("expected finite numbers", {}, 0, "origin");
  return {values[0], values[1], values[2]};
}

GridGeometry geometry_of(py::ssize_t rows, py::ssize_t columns, double resolution, const py::handle& origin, bool y_down) {
  if (rows < 1 || columns < 1) throw Error("the array must have at least one row and one column", {}, 0, "data");
  if (static_cast<double>(rows) * static_cast<double>(columns) > static_cast<double>(kMaxGridCells))
    throw Error("too many cells for a map (at most 2^31 - 1)", {}, 0, "data");
  if (!std::isfinite(resolution) || !(resolution > 0.0)) throw Error("must be a finite number > 0", {}, 0, "resolution");
  GridGeometry g;
  g.width = static_cast<int>(columns);
  g.height = static_cast<int>(rows);
  g.resolution = resolution;
  g.origin = origin_of(origin);
  g.y_down = y_down;
  return g;
}

// A 2D numpy array of the given kinds ("biu": booleans and integers; "biuf": and reals).
py::array two_dimensional(const py::object& data, const char* kinds, const char* field, const char* what) {
  py::array a = py::module_::import("numpy").attr("asarray")(data);
  if (a.ndim() != 2)
    throw Error("expected a 2D array (rows, columns), got " + std::to_string(a.ndim()) + " dimensions", {}, 0, field);
  const char kind = a.dtype().kind();
  if (std::string(kinds).find(kind) == std::string::npos)
    throw Error(std::string("expected ") + what + ", got dtype " + std::string(py::str(a.dtype())), {}, 0, field);
  return a;
}

std::string cell_text(py::ssize_t row, py::ssize_t column) {
  return "row " + std::to_string(row) + ", column " + std::to_string(column);
}

// OccupancyMap(data, resolution, origin, index_grid): the values -1 (unknown) .. 100 (occupied),
// booleans as 0 / 100; row r of the array is row iy = r of the grid.
OccupancyMapHandle occupancy_from_array(const py::object& data, double resolution, const py::object& origin, bool index_grid) {
  const py::array a = two_dimensional(data, "biu", "data", "an integer array of occupancy -1..100 (or booleans)");
  const bool boolean = a.dtype().kind() == 'b';
  const auto values = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(a);
  const GridGeometry g = geometry_of(a.shape(0), a.shape(1), resolution, origin, index_grid);
  OccupancyGrid grid(g);
  const auto v = values.unchecked<2>();
  for (py::ssize_t r = 0; r < v.shape(0); ++r)
    for (py::ssize_t c = 0; c < v.shape(1); ++c) {
      const std::int64_t x = v(r, c);
      if (x < -1 || x > 100)
        throw Error("occupancy must be -1 (unknown) .. 100, found " + std::to_string(x) + " at " + cell_text(r, c), {}, 0, "data");
      grid(static_cast<int>(c), static_cast<int>(r)) = static_cast<std::int8_t>(boolean && x ? kOccupiedOccupancy : x);
    }
  LoadedMap loaded;
  loaded.format = index_grid ? MapFormat::MovingAi : MapFormat::RosMap;
  loaded.map = std::move(grid);
  OccupancyMapHandle h;
  h.loaded = std::make_shared<const LoadedMap>(std::move(loaded));
  h.source = "array";
  return h;
}

// ElevationMap(heights, resolution, origin, observed): NaN (or observed False) is an unobserved
// cell; every other height must be finite.
ElevationMapHandle elevation_from_array(const py::object& heights, double resolution, const py::object& origin,
                                        const py::object& observed) {
  const py::array a = two_dimensional(heights, "biuf", "heights", "a real array of heights (m)");
  const auto z = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a);
  const GridGeometry g = geometry_of(a.shape(0), a.shape(1), resolution, origin, false);
  std::optional<py::array_t<bool, py::array::c_style | py::array::forcecast>> mask;
  if (!observed.is_none()) {
    const py::array o = two_dimensional(observed, "b", "observed", "a boolean array");
    if (o.shape(0) != a.shape(0) || o.shape(1) != a.shape(1))
      throw Error("must have the shape of heights", {}, 0, "observed");
    mask = py::array_t<bool, py::array::c_style | py::array::forcecast>::ensure(o);
  }
  ElevationMap map(g);
  const auto zz = z.unchecked<2>();
  for (py::ssize_t r = 0; r < zz.shape(0); ++r)
    for (py::ssize_t c = 0; c < zz.shape(1); ++c) {
      if (mask && !mask->at(r, c)) continue;
      const double h = zz(r, c);
      if (std::isnan(h)) {
        if (mask) throw Error("NaN at an observed cell (" + cell_text(r, c) + ")", {}, 0, "heights");
        continue;
      }
      if (!std::isfinite(h)) throw Error("infinite height at " + cell_text(r, c), {}, 0, "heights");
      map.set_height(static_cast<int>(c), static_cast<int>(r), h);
    }
  LoadedMap loaded;
  loaded.format = MapFormat::Asc;
  loaded.map = std::move(map);
  ElevationMapHandle h;
  h.loaded = std::make_shared<const LoadedMap>(std::move(loaded));
  h.source = "array";
  return h;
}

ElevationMapHandle elevation_handle(ElevationMap&& map, std::string source) {
  LoadedMap loaded;
  loaded.format = MapFormat::Asc;
  loaded.map = std::move(map);
  ElevationMapHandle h;
  h.loaded = std::make_shared<const LoadedMap>(std::move(loaded));
  h.source = std::move(source);
  return h;
}

// The map info of `starnav map info --json`, as a dict.
py::dict map_info(const MapHandle& h) {
  const std::string text = map_info_json(*h.loaded, h.from_file ? h.source : "", h.from_file ? "" : h.source, -1);
  py::dict d = py::module_::import("json").attr("loads")(text);
  d["origin"] = py::tuple(d["origin"]);
  return d;
}

void save_map_file(const MapHandle& h, const std::string& path) {
  const MapFormat format = output_map_format(path, h.loaded->is_elevation());
  check_map_writable(*h.loaded, path, format);
  const py::object warn = py::module_::import("warnings").attr("warn");
  for (const std::string& loss : map_conversion_losses(*h.loaded, format)) warn(path + ": " + loss, py::arg("stacklevel") = 2);
  save_map(*h.loaded, path, format);
}

// The geometry methods both map classes have.
template <class Class>
void bind_geometry(Class& c) {
  using H = typename Class::type;
  c.def_property_readonly("width", [](const H& h) { return h.geometry().width; }, "columns (cells along x)")
      .def_property_readonly("height", [](const H& h) { return h.geometry().height; }, "rows (cells along y)")
      .def_property_readonly("shape", [](const H& h) { return py::make_tuple(h.geometry().height, h.geometry().width); },
                             "(rows, columns), the shape of the arrays")
      .def_property_readonly("resolution", [](const H& h) { return h.geometry().resolution; }, "metres per cell")
      .def_property_readonly(
          "origin", [](const H& h) { return py::make_tuple(h.geometry().origin.x, h.geometry().origin.y, h.geometry().origin.yaw); },
          "(x, y, yaw) of the lower-left corner of cell (0, 0) in the world (m, rad)")
      .def_property_readonly("index_grid", [](const H& h) { return h.index_grid(); },
                             "True for MovingAI maps and other y-down grids: row 0 is the top row and the units are cells")
      .def_property_readonly("source", [](const H& h) { return h.source; }, "the file read, or how the map was made")
      .def_property_readonly(
          "format", [](const H& h) { return h.from_file ? std::string(map_format_name(h.loaded->format)) : h.source; },
          "the file format read (movingai, ros_map, elevation_png, asc, csv, unity_raw, geotiff), or how the map was made")
      .def("info", [](const H& h) { return map_info(h); }, "The numbers of `starnav map info --json` as a dict.")
      .def("save", [](const H& h, const std::string& path) { save_map_file(h, path); }, py::arg("path"),
           "Writes the map in the format its extension names (.map, .yaml, .asc, .csv, .raw); what the format cannot "
           "keep is a warning, as the CLI prints it.")
      .def(
          "cell_center",
          [](const H& h, int ix, int iy) {
            const Vec2 p = h.geometry().cell_center(ix, iy);
            return py::make_tuple(p.x(), p.y());
          },
          py::arg("ix"), py::arg("iy"), "The world point (m) of the centre of cell (ix, iy).")
      .def(
          "cell_of",
          [](const H& h, double x, double y) -> py::object {
            const std::optional<Cell> c = h.geometry().world_to_cell(Vec2(x, y));
            if (!c) return py::none();
            return py::make_tuple(c->x, c->y);
          },
          py::arg("x"), py::arg("y"), "The cell (ix, iy) holding the world point (x, y), or None outside the map.");
}

// The terrain analysis with the map it was computed on.
struct TerrainAnalysisHandle {
  std::shared_ptr<const TerrainAnalysis> analysis;
  py::dict options;
};

template <class Handle, class Getter>
py::array mask_view(py::object self, Getter get) {
  const Handle& h = self.cast<const Handle&>();
  const auto& v = get(*h.analysis);
  const GridGeometry& g = h.analysis->geometry();
  py::array a(py::dtype("?"), std::vector<py::ssize_t>{g.height, g.width}, std::vector<py::ssize_t>{g.width, 1}, v.data(), self);
  a.attr("setflags")(py::arg("write") = false);
  return a;
}

// The options of a declared table with the settings applied, as a dict of texts in the user's units.
template <class Config>
py::dict options_dict(const ParamTable<Config>& table, const Config& config) {
  py::dict d;
  for (const ParamSpec& s : table.specs(config)) d[py::str(s.key)] = s.default_value;
  return d;
}

template <class Config>
Config configured_by(const ParamTable<Config>& table, const py::dict& kwargs, Config defaults = Config{}) {
  const std::vector<ParamSetting> settings = settings_of(kwargs);
  Config c = configured(table, settings, {}, std::move(defaults));
  try {
    c.validate();
  } catch (const Error& e) {
    rethrow_at_setting(e, settings);
  }
  return c;
}

}  // namespace

py::object wrap_map(LoadedMap&& loaded, std::string source, bool from_file) {
  const bool elevation = loaded.is_elevation();
  auto shared = std::make_shared<const LoadedMap>(std::move(loaded));
  if (elevation) {
    ElevationMapHandle h;
    h.loaded = shared;
    h.source = std::move(source);
    h.from_file = from_file;
    return py::cast(std::move(h));
  }
  OccupancyMapHandle h;
  h.loaded = shared;
  h.source = std::move(source);
  h.from_file = from_file;
  return py::cast(std::move(h));
}

void bind_maps(py::module_& m) {
  auto occ = py::class_<OccupancyMapHandle>(m, "OccupancyMap", R"doc(
An occupancy grid as ROS's nav_msgs/OccupancyGrid: int8 cells, 0..100 percent occupied, -1 unknown.

OccupancyMap(data, resolution=1.0, origin=(0, 0, 0), index_grid=False) copies a 2D integer (or
boolean) array, shape (rows, columns): data[iy, ix] is cell (ix, iy). On a metric map row 0 is the
bottom row (ROS's order: plot with origin="lower"); with index_grid=True (MovingAI's order) row 0
is the top row and coordinates are cells. `data` is the map's own storage shared with numpy (no
copy, read-only), and keeps the map alive.)doc");
  occ.def(py::init(&occupancy_from_array), py::arg("data"), py::kw_only(), py::arg("resolution") = 1.0,
          py::arg("origin") = py::make_tuple(0.0, 0.0, 0.0), py::arg("index_grid") = false);
  bind_geometry(occ);
  occ.def_property_readonly(
         "data",
         [](py::object self) {
           const OccupancyMapHandle& h = self.cast<const OccupancyMapHandle&>();
           const OccupancyGrid& g = h.loaded->occupancy();
           return view_of<std::int8_t>(g.data().data(), {g.height(), g.width()}, self);
         },
         "the cells, int8 (rows, columns), shared with the map (no copy; read-only)")
      .def_property_readonly(
          "thresholds",
          [](const OccupancyMapHandle& h) {
            const OccupancyThresholds t = h.loaded->thresholds();
            return py::make_tuple(t.occupied_percent, t.free_percent);
          },
          "(occupied, free) percent: how values become occupied, free or unknown (the map_server file's thresholds)")
      .def("__repr__", [](const OccupancyMapHandle& h) {
        return "<starnav.OccupancyMap " + std::to_string(h.geometry().width) + " x " + std::to_string(h.geometry().height) +
               " from " + h.source + ">";
      });

  auto elev = py::class_<ElevationMapHandle>(m, "ElevationMap", R"doc(
An elevation map: one height per cell (m), with the cell's min and max height and whether it was observed.

ElevationMap(heights, resolution=1.0, origin=(0, 0, 0), observed=None) copies a 2D real array,
shape (rows, columns): heights[iy, ix] is cell (ix, iy), row 0 the bottom row (plot with
origin="lower"). NaN (or observed False) is an unobserved cell. `heights`, `min_heights`,
`max_heights` (float64) and `observed` (bool) are the map's own storage shared with numpy (no copy,
read-only; an unobserved cell holds 0), and keep the map alive; to_array() is a copy with NaN where
unobserved.)doc");
  elev.def(py::init(&elevation_from_array), py::arg("heights"), py::kw_only(), py::arg("resolution") = 1.0,
           py::arg("origin") = py::make_tuple(0.0, 0.0, 0.0), py::arg("observed") = py::none());
  bind_geometry(elev);
  const auto height_view = [](const std::vector<double>& (ElevationMap::*get)() const) {
    return [get](py::object self) {
      const ElevationMapHandle& h = self.cast<const ElevationMapHandle&>();
      const ElevationMap& e = h.loaded->elevation();
      return view_of<double>((e.*get)().data(), {e.height(), e.width()}, self);
    };
  };
  elev.def_property_readonly("heights", height_view(&ElevationMap::heights),
                             "height per cell (m), float64 (rows, columns), shared with the map (0 where unobserved)")
      .def_property_readonly("min_heights", height_view(&ElevationMap::min_heights), "lowest height seen in each cell (m)")
      .def_property_readonly("max_heights", height_view(&ElevationMap::max_heights), "highest height seen in each cell (m)")
      .def_property_readonly(
          "observed",
          [](py::object self) {
            const ElevationMapHandle& h = self.cast<const ElevationMapHandle&>();
            const ElevationMap& e = h.loaded->elevation();
            py::array a(py::dtype("?"), std::vector<py::ssize_t>{e.height(), e.width()},
                        std::vector<py::ssize_t>{e.width(), 1}, e.observed().data(), self);
            a.attr("setflags")(py::arg("write") = false);
            return a;
          },
          "True where the cell was observed, bool (rows, columns), shared with the map")
      .def(
          "to_array",
          [](const ElevationMapHandle& h) {
            const ElevationMap& e = h.loaded->elevation();
            std::vector<double> z(e.heights());
            for (std::size_t i = 0; i < z.size(); ++i)
              if (!e.observed_at_index(i)) z[i] = std::nan("");
            return owning_array(std::move(z), {e.height(), e.width()});
          },
          "A copy of the heights with NaN where unobserved.")
      .def("__repr__", [](const ElevationMapHandle& h) {
        return "<starnav.ElevationMap " + std::to_string(h.geometry().width) + " x " + std::to_string(h.geometry().height) +
               " from " + h.source + ">";
      });

  m.def(
      "load_map",
      [](const std::string& path) { return wrap_map(load_map(path), path, true); }, py::arg("path"),
      "Reads any map file the CLI reads (MovingAI .map, map_server .yaml, elevation .yaml/.asc/.csv/.raw, GeoTIFF "
      "through the GDAL plugin): an OccupancyMap or an ElevationMap.");

  m.def(
      "load_scenarios",
      [](const std::string& path) {
        const MovingAiScenario s = read_movingai_scenario(path);
        const std::size_t n = s.entries.size();
        std::vector<std::int32_t> bucket(n), start(2 * n), goal(2 * n), size(2 * n);
        std::vector<double> optimal(n);
        py::list maps;
        for (std::size_t i = 0; i < n; ++i) {
          const ScenarioEntry& e = s.entries[i];
          bucket[i] = e.bucket;
          start[2 * i] = e.start_x;
          start[2 * i + 1] = e.start_y;
          goal[2 * i] = e.goal_x;
          goal[2 * i + 1] = e.goal_y;
          size[2 * i] = e.map_width;
          size[2 * i + 1] = e.map_height;
          optimal[i] = e.optimal_length;
          maps.append(e.map);
        }
        const auto rows = static_cast<py::ssize_t>(n);
        py::dict d;
        d["bucket"] = owning_array(std::move(bucket), {rows});
        d["map"] = maps;
        d["map_size"] = owning_array(std::move(size), {rows, 2});
        d["start"] = owning_array(std::move(start), {rows, 2});
        d["goal"] = owning_array(std::move(goal), {rows, 2});
        d["optimal_length"] = owning_array(std::move(optimal), {rows});
        return d;
      },
      py::arg("path"),
      "Reads a MovingAI .scen file: a dict of arrays (bucket, map, map_size, start, goal: (column, row from the top), "
      "optimal_length), one row per query.");
}

void bind_terrain(py::module_& m) {
  py::class_<TerrainAnalysisHandle>(m, "TerrainAnalysis", R"doc(
Terrain analysis of an elevation map (docs/terrain.md): per-cell ruggedness, slope, gradient and
normals, the Liu 2024 obstacle mask and Li 2019's node criteria, each expanded by the robot radius.
Arrays are (rows, columns) in the map's order (row 0 the bottom row); the masks, ruggedness,
heights and observed flags are the analysis's own storage (no copy, read-only) and keep it alive;
slope, gradient and normals are computed on access.)doc")
      .def_property_readonly("options", [](const TerrainAnalysisHandle& h) { return h.options; },
                             "the options used, as declared (text in the user's units)")
      .def_property_readonly("heights",
                             [](py::object self) {
                               const auto& h = self.cast<const TerrainAnalysisHandle&>();
                               const TerrainAnalysis& a = *h.analysis;
                               return view_of<double>(a.heights().data(), {a.height(), a.width()}, self);
                             },
                             "the heights analysed (m; 0 where unobserved)")
      .def_property_readonly(
          "observed", [](py::object self) { return mask_view<TerrainAnalysisHandle>(self, [](const TerrainAnalysis& a) -> const auto& { return a.observed(); }); },
          "observed cells")
      .def_property_readonly("ruggedness",
                             [](py::object self) {
                               const auto& h = self.cast<const TerrainAnalysisHandle&>();
                               const TerrainAnalysis& a = *h.analysis;
                               return view_of<double>(a.ruggedness().data(), {a.height(), a.width()}, self);
                             },
                             "S, the 3x3 height variance (m^2)")
      .def_property_readonly(
          "slope",
          [](const TerrainAnalysisHandle& h) {
            const TerrainAnalysis& a = *h.analysis;
            std::vector<double> s(a.heights().size());
            for (int y = 0; y < a.height(); ++y)
              for (int x = 0; x < a.width(); ++x) s[a.index(x, y)] = a.cell_slope(x, y);
            return owning_array(std::move(s), {a.height(), a.width()});
          },
          "slope of the plane fitted to each 3x3 block (rad)")
      .def_property_readonly(
          "gradient",
          [](const TerrainAnalysisHandle& h) {
            const TerrainAnalysis& a = *h.analysis;
            std::vector<double> g(2 * a.heights().size());
            for (int y = 0; y < a.height(); ++y)
              for (int x = 0; x < a.width(); ++x) {
                const Vec2 v = a.gradient(x, y);
                g[2 * a.index(x, y)] = v.x();
                g[2 * a.index(x, y) + 1] = v.y();
              }
            return owning_array(std::move(g), {a.height(), a.width(), 2});
          },
          "(dz/dx, dz/dy) of the fitted plane in the grid frame (m/m), (rows, columns, 2)")
      .def_property_readonly(
          "normals",
          [](const TerrainAnalysisHandle& h) {
            const TerrainAnalysis& a = *h.analysis;
            std::vector<double> n(3 * a.heights().size());
            for (int y = 0; y < a.height(); ++y)
              for (int x = 0; x < a.width(); ++x) {
                const Vec3 v = a.normal(x, y);
                for (int k = 0; k < 3; ++k) n[3 * a.index(x, y) + static_cast<std::size_t>(k)] = v[k];
              }
            return owning_array(std::move(n), {a.height(), a.width(), 3});
          },
          "unit upward surface normals in the world frame, (rows, columns, 3)")
      .def_property_readonly(
          "obstacle_mask",
          [](py::object self) { return mask_view<TerrainAnalysisHandle>(self, [](const TerrainAnalysis& a) -> const auto& { return a.obstacle_mask(); }); },
          "Liu 2024 obstacles: a step, slope or ruggedness at its threshold (unobserved cells when they are blocked)")
      .def_property_readonly(
          "li_blocked_mask",
          [](py::object self) { return mask_view<TerrainAnalysisHandle>(self, [](const TerrainAnalysis& a) -> const auto& { return a.li_blocked_mask(); }); },
          "Li 2019: cells failing the step or slope node criteria")
      .def_property_readonly(
          "expanded_obstacle_mask",
          [](py::object self) {
            return mask_view<TerrainAnalysisHandle>(self, [](const TerrainAnalysis& a) -> const auto& { return a.expanded_obstacle_mask(); });
          },
          "obstacle_mask expanded by robot_radius_m (AOEA*'s)")
      .def_property_readonly(
          "expanded_li_blocked_mask",
          [](py::object self) {
            return mask_view<TerrainAnalysisHandle>(self, [](const TerrainAnalysis& a) -> const auto& { return a.expanded_li_blocked_mask(); });
          },
          "li_blocked_mask expanded by robot_radius_m");

  m.def(
      "analyse_terrain",
      [](const ElevationMapHandle& map, const py::kwargs& kwargs) {
        const TerrainAnalysisOptions o = configured_by(terrain_analysis_params(), kwargs);
        TerrainAnalysisHandle h;
        {
          py::gil_scoped_release release;
          h.analysis = std::make_shared<const TerrainAnalysis>(map.loaded->elevation(), o);
        }
        h.options = options_dict(terrain_analysis_params(), o);
        return h;
      },
      py::arg("map"));
  m.def(
      "generate_hills",
      [](const py::kwargs& kwargs) {
        const HillsOptions o = configured_by(hills_params(), kwargs);
        py::gil_scoped_release release;
        return elevation_handle(generate_hills(o), "hills");
      });
  m.def(
      "generate_road",
      [](const py::kwargs& kwargs) {
        const RoadOptions o = configured_by(road_params(), kwargs);
        py::gil_scoped_release release;
        return elevation_handle(generate_road(o).map, "road");
      });
  m.def(
      "with_feature",
      [](const ElevationMapHandle& map, const std::string& kind, const std::vector<double>& centre, double radius_m,
         double depth_m) {
        if (kind != "pit" && kind != "mound") throw Error("expected pit or mound, got '" + kind + "'", {}, 0, "kind");
        if (centre.size() != 2) throw Error("expected (x, y)", {}, 0, "centre");
        ElevationMap copy = map.loaded->elevation();
        add_terrain_feature(copy, {kind == "pit" ? TerrainFeature::Kind::Pit : TerrainFeature::Kind::Mound,
                                   Vec2(centre[0], centre[1]), radius_m, depth_m});
        return elevation_handle(std::move(copy), map.source);
      },
      py::arg("map"), py::arg("kind"), py::arg("centre"), py::arg("radius_m"), py::arg("depth_m"),
      "A copy of the map with a pit (lowered) or mound (raised) raised-cosine bump of the given radius and depth (m).");
}

}  // namespace starnav::python
