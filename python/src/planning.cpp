// Planning: one query as `starnav plan` runs it (the same library calls, so the same JSON), and
// many queries in C++ with the GIL released. The planners and their keyword arguments come from
// the registry and the declared query parameters (experiment/plan_query.hpp); the Python package
// makes one function per planner from them (starnav/_generate.py).
#include <cmath>
#include <string>
#include <utility>

#include "bindings.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/record_format.hpp"
#include "starnav/experiment/plan_query.hpp"
#include "starnav/experiment/plan_report.hpp"
#include "starnav/experiment/terrain_report.hpp"
#include "starnav/registry/components.hpp"

namespace starnav::python {

namespace {

// One query's outcome and what its reports need (the map it was planned on is kept alive: the
// report context points into it).
// A planner between poses (Hybrid-A*) keeps its result and name in `poses` (the report of
// `starnav plan --start-yaw-deg ...`).
struct PosePlanOutcome {
  std::string planner;
  PlanResult result;
};

struct PlanResultHandle {
  std::shared_ptr<const LoadedMap> map;
  std::shared_ptr<PlanOutcome> occupancy;
  std::shared_ptr<TerrainPlanOutcome> terrain;
  std::shared_ptr<PosePlanOutcome> poses;
  PlanReportContext report;

  const PlanResult& result() const { return poses ? poses->result : occupancy ? occupancy->result : terrain->result; }
  bool index_grid() const { return occupancy && report.index_grid; }
  std::string json() const {
    if (poses) return pose_plan_json(poses->planner, poses->result);
    return occupancy ? plan_json(*occupancy, report) : terrain_plan_json(*terrain);
  }
  std::string planner() const {
    return poses ? poses->planner : occupancy ? std::string(occupancy->planner->name()) : terrain->planner;
  }
  // A planner between poses searches a lattice of motions: no optimality claim.
  bool admissible() const { return !poses && (occupancy ? occupancy->planner->admissible() : terrain->admissible); }
};

// Many queries' results.
struct PlanBatchHandle {
  std::shared_ptr<const LoadedMap> map;
  std::string planner;
  bool index_grid = false;
  std::vector<PlanResult> results;
};

// An endpoint (x, y) as the CLI's --start/--goal: cells on index grids (and with cells=True),
// metres in the map frame otherwise.
Cell endpoint(const py::handle& point, bool in_cells, const GridGeometry& g, const char* field) {
  std::vector<double> xy;
  try {
    xy = py::cast<std::vector<double>>(point);
  } catch (const py::cast_error&) {
    throw Error("expected (x, y), two numbers", {}, 0, field);
  }
  if (xy.size() != 2) throw Error("expected (x, y), two numbers", {}, 0, field);
  if (!std::isfinite(xy[0]) || !std::isfinite(xy[1])) throw Error("expected two finite numbers", {}, 0, field);
  return plan_endpoint_cell(Vec2(xy[0], xy[1]), in_cells, g, field, format_param_real(xy[0]) + "," + format_param_real(xy[1]));
}

// An (N, 2) array of endpoints as cells.
std::vector<Cell> endpoints(const py::object& points, bool in_cells, const GridGeometry& g, const char* field) {
  const py::array a = py::module_::import("numpy").attr("asarray")(points, py::arg("dtype") = "float64");
  if (a.ndim() != 2 || a.shape(1) != 2) throw Error("expected an (N, 2) array of points", {}, 0, field);
  const auto v = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a).unchecked<2>();
  std::vector<Cell> out(static_cast<std::size_t>(v.shape(0)));
  for (py::ssize_t i = 0; i < v.shape(0); ++i) {
    if (!std::isfinite(v(i, 0)) || !std::isfinite(v(i, 1)))
      throw Error("expected finite numbers (row " + std::to_string(i) + ")", {}, 0, field);
    const std::string text = format_param_real(v(i, 0)) + "," + format_param_real(v(i, 1));
    out[static_cast<std::size_t>(i)] =
        plan_endpoint_cell(Vec2(v(i, 0), v(i, 1)), in_cells, g, std::string(field) + " row " + std::to_string(i), text);
  }
  return out;
}

// The points of a path in the CLI's units, as `starnav plan --json` prints them: cells on index
// grids, metres (to 1e-9) on metric maps.
py::array path_array(const PlanResult& r, bool index_grid) {
  std::vector<double> xy(2 * r.path_cells.size());
  for (std::size_t i = 0; i < r.path_cells.size(); ++i) {
    xy[2 * i] = index_grid ? r.path_cells[i].x : json_coordinate(r.path_world[i].x());
    xy[2 * i + 1] = index_grid ? r.path_cells[i].y : json_coordinate(r.path_world[i].y());
  }
  return owning_array(std::move(xy), {static_cast<py::ssize_t>(r.path_cells.size()), 2});
}

py::array cells_array(const std::vector<Cell>& cells) {
  std::vector<std::int32_t> xy(2 * cells.size());
  for (std::size_t i = 0; i < cells.size(); ++i) {
    xy[2 * i] = cells[i].x;
    xy[2 * i + 1] = cells[i].y;
  }
  return owning_array(std::move(xy), {static_cast<py::ssize_t>(cells.size()), 2});
}

// The map as error messages name it: its file, or "the map".
std::string map_name(const MapHandle& h) { return h.from_file ? h.source : "the map"; }

py::object optional_number(bool present, double v) { return present ? py::object(py::float_(v)) : py::object(py::none()); }

// A pose (x, y, yaw): metres and radians in the map frame.
Pose2 pose_endpoint(const py::handle& point, const char* field) {
  std::vector<double> v;
  try {
    v = py::cast<std::vector<double>>(point);
  } catch (const py::cast_error&) {
    throw Error("expected (x, y, yaw), three numbers (m, m, rad): the planner plans between poses", {}, 0, field);
  }
  if (v.size() != 3) throw Error("expected (x, y, yaw), three numbers (m, m, rad): the planner plans between poses", {}, 0, field);
  if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2])) throw Error("expected three finite numbers", {}, 0, field);
  return Pose2(v[0], v[1], v[2]);
}

// A planner between poses (capability needs_headings) through its role, as `starnav plan` runs it
// with --start-yaw-deg and --goal-yaw-deg: its declared parameters, and `unknown` (free or
// blocked) as --unknown.
PlanResultHandle plan_between_poses(const OccupancyMapHandle& h, const GlobalPlannerDef& def, const py::object& start,
                                    const py::object& goal, bool cells, std::vector<ParamSetting> settings) {
  const OccupancyGrid& grid = h.loaded->occupancy();
  const GridGeometry& geometry = grid.geometry();
  if (h.index_grid())
    throw Error("'" + def.info.name + "' plans on metric maps (map_server .yaml), in metres", h.from_file ? h.source : "", 0, "map");
  GlobalPlannerContext pctx;
  pctx.grid.thresholds = h.loaded->thresholds();
  for (auto it = settings.begin(); it != settings.end();) {
    if (it->key != "unknown") {
      ++it;
      continue;
    }
    if (it->value != "free" && it->value != "blocked") throw Error("must be free or blocked, got '" + printable(it->value, 40) + "'", {}, 0, "unknown");
    pctx.grid.unknown_is_free = it->value == "free";
    it = settings.erase(it);
  }
  const std::unique_ptr<GlobalPlanner> planner = def.make(pctx, settings);
  Pose2 s = pose_endpoint(start, "start"), g = pose_endpoint(goal, "goal");
  if (cells) {  // cell indices: their centres
    const auto centre = [&](Pose2 p, const char* field) {
      const Cell c = plan_endpoint_cell(Vec2(p.x, p.y), true, geometry, field, format_param_real(p.x) + "," + format_param_real(p.y));
      const Vec2 w = geometry.cell_center(c);
      return Pose2(w.x(), w.y(), p.yaw);
    };
    s = centre(s, "start");
    g = centre(g, "goal");
  }
  PlanQuery q;
  q.start_pose = s;
  q.goal_pose = g;
  q.start = geometry.world_to_cell_unchecked(Vec2(s.x, s.y));
  q.goal = geometry.world_to_cell_unchecked(Vec2(g.x, g.y));
  auto outcome = std::make_shared<PosePlanOutcome>();
  outcome->planner = def.info.name;
  {
    py::gil_scoped_release release;
    outcome->result = planner->plan_poses(PlanningLayers{&grid, nullptr}, q, {});
  }
  PlanResultHandle out;
  out.map = h.loaded;
  out.poses = std::move(outcome);
  out.report = {&grid, q.start, q.goal, false, false};
  return out;
}


PlanResultHandle plan_query(const py::object& map_object, const py::object& start, const py::object& goal,
                            const py::object& planner_name, bool cells, const py::dict& kwargs) {
  const std::vector<ParamSetting> settings = settings_of(kwargs);
  PlanResultHandle out;
  if (py::isinstance<OccupancyMapHandle>(map_object)) {
    const auto& h = map_object.cast<const OccupancyMapHandle&>();
    const std::string planner = planner_name.is_none() ? "astar" : planner_name.cast<std::string>();
    const OccupancyGrid& grid = h.loaded->occupancy();
    const bool index_grid = h.index_grid();
    std::string warning;
    if (const GlobalPlannerDef& def = find_global_planner(planner, "planner", &warning); def.info.has(Capability::NeedsHeadings)) {
      warn_deprecated(warning);
      return plan_between_poses(h, def, start, goal, cells, settings);
    }
    warning.clear();
    PlanRequest rq = occupancy_plan_request(planner, settings, grid.geometry(), index_grid, h.loaded->thresholds(),
                                            map_name(h), "planner", &warning);
    warn_deprecated(warning);
    const Cell s = endpoint(start, index_grid || cells, grid.geometry(), "start");
    const Cell g = endpoint(goal, index_grid || cells, grid.geometry(), "goal");
    auto outcome = std::make_shared<PlanOutcome>();
    {
      py::gil_scoped_release release;
      *outcome = plan_query_on_grid(grid, s, g, rq, settings);
    }
    out.map = h.loaded;
    out.occupancy = std::move(outcome);
    out.report = {&grid, s, g, index_grid, rq.options.record_trace};
    return out;
  }
  if (!py::isinstance<ElevationMapHandle>(map_object))
    throw py::type_error("map: expected a starnav.OccupancyMap or starnav.ElevationMap");
  const auto& h = map_object.cast<const ElevationMapHandle&>();
  const std::string planner = planner_name.is_none() ? "ia" : planner_name.cast<std::string>();
  const RoughTerrainPlannerKind kind = terrain_plan_planner(planner, "planner");
  TerrainPlanQuery q = terrain_plan_query(settings, std::vector<RoughTerrainPlannerKind>{kind});
  const ElevationMap& e = h.loaded->elevation();
  const Cell s = endpoint(start, cells, e.geometry(), "start");
  const Cell g = endpoint(goal, cells, e.geometry(), "goal");
  auto outcome = std::make_shared<TerrainPlanOutcome>();
  {
    py::gil_scoped_release release;
    *outcome = plan_on_terrain(e, s, g, kind, q.options, q.limits);
  }
  out.map = h.loaded;
  out.terrain = std::move(outcome);
  out.report.start = s;
  out.report.goal = g;
  return out;
}

PlanBatchHandle plan_batch(const py::object& map_object, const py::object& starts, const py::object& goals,
                           const py::object& planner_name, bool cells, unsigned threads, const py::dict& kwargs) {
  const std::vector<ParamSetting> settings = settings_of(kwargs);
  PlanBatchHandle out;
  std::vector<PlanEndpoints> queries;
  const auto pair_up = [&](const GridGeometry& g, bool in_cells) {
    const std::vector<Cell> s = endpoints(starts, in_cells, g, "starts"), e = endpoints(goals, in_cells, g, "goals");
    if (s.size() != e.size())
      throw Error("starts has " + std::to_string(s.size()) + " rows, goals " + std::to_string(e.size()), {}, 0, "goals");
    queries.resize(s.size());
    for (std::size_t i = 0; i < s.size(); ++i) queries[i] = {s[i], e[i]};
  };
  if (py::isinstance<OccupancyMapHandle>(map_object)) {
    const auto& h = map_object.cast<const OccupancyMapHandle&>();
    out.planner = planner_name.is_none() ? "astar" : planner_name.cast<std::string>();
    const OccupancyGrid& grid = h.loaded->occupancy();
    out.index_grid = h.index_grid();
    std::string warning;
    const PlanRequest rq = occupancy_plan_request(out.planner, settings, grid.geometry(), out.index_grid,
                                                  h.loaded->thresholds(), map_name(h), "planner", &warning);
    warn_deprecated(warning);
    pair_up(grid.geometry(), out.index_grid || cells);
    {
      py::gil_scoped_release release;
      out.results = plan_many_on_grid(grid, queries, rq, settings, threads);
    }
    out.map = h.loaded;
    return out;
  }
  if (!py::isinstance<ElevationMapHandle>(map_object))
    throw py::type_error("map: expected a starnav.OccupancyMap or starnav.ElevationMap");
  const auto& h = map_object.cast<const ElevationMapHandle&>();
  out.planner = planner_name.is_none() ? "ia" : planner_name.cast<std::string>();
  const RoughTerrainPlannerKind kind = terrain_plan_planner(out.planner, "planner");
  TerrainPlanQuery q = terrain_plan_query(settings, std::vector<RoughTerrainPlannerKind>{kind});
  q.kind = kind;
  const ElevationMap& e = h.loaded->elevation();
  pair_up(e.geometry(), cells);
  {
    py::gil_scoped_release release;
    out.results = plan_many_on_terrain(e, queries, q, threads);
  }
  out.map = h.loaded;
  return out;
}

}  // namespace

void bind_planning(py::module_& m) {
  py::class_<PlanResultHandle>(m, "PlanResult", R"doc(
The result of one planning query, as `starnav plan --json` reports it: json() is the CLI's line,
byte for byte (time_ms aside, a wall-clock time). `path` holds the path's points in the CLI's units
(cells on MovingAI maps, metres in the map frame otherwise), (N, 2) float64; `path_cells` the cells
(ix, iy), (N, 2) int32.)doc")
      .def_property_readonly("planner", &PlanResultHandle::planner)
      .def_property_readonly("admissible", &PlanResultHandle::admissible)
      .def_property_readonly(
          "poses",
          [](const PlanResultHandle& h) -> py::object {
            if (!h.poses) return py::none();
            const PlanResult& r = h.poses->result;
            std::vector<double> v;
            v.reserve(3 * r.path_poses.size());
            for (const Pose2& p : r.path_poses) v.insert(v.end(), {p.x, p.y, p.yaw});
            return owning_array(std::move(v), {static_cast<py::ssize_t>(r.path_poses.size()), 3});
          },
          "planners between poses (hybrid_astar): the path's poses (N, 3) x, y (m), yaw (rad); else None")
      .def_property_readonly(
          "reversing",
          [](const PlanResultHandle& h) -> py::object {
            if (!h.poses) return py::none();
            std::vector<std::uint8_t> v(h.poses->result.path_reversing);
            const auto n = static_cast<py::ssize_t>(v.size());
            return owning_array(std::move(v), {n}).attr("astype")("bool");
          },
          "planners between poses: per pose, whether the motion leaving it drives in reverse; else None")
      .def_property_readonly("found", [](const PlanResultHandle& h) { return h.result().found(); })
      .def_property_readonly("reason", [](const PlanResultHandle& h) { return std::string(plan_status_reason(h.result().status)); },
                             "found, start_outside_map, goal_outside_map, start_blocked, goal_blocked, no_path, expansion_limit, "
                             "time_limit")
      .def_property_readonly("cost", [](const PlanResultHandle& h) { return optional_number(h.result().found(), h.result().cost); },
                             "the planner's objective (None without a path)")
      .def_property_readonly("length", [](const PlanResultHandle& h) { return optional_number(h.result().found(), h.result().length); },
                             "geometric length in the map's units (None without a path)")
      .def_property_readonly("units", [](const PlanResultHandle& h) { return std::string(h.index_grid() ? "cells" : "m"); })
      .def_property_readonly("expanded", [](const PlanResultHandle& h) { return h.result().expanded; }, "states expanded")
      .def_property_readonly("generated", [](const PlanResultHandle& h) { return h.result().generated; }, "states generated")
      .def_property_readonly("time_ms", [](const PlanResultHandle& h) { return h.result().time_ms; }, "the search's wall time")
      .def_property_readonly("path",
                             [](const PlanResultHandle& h) {
                               if (!h.poses) return path_array(h.result(), h.index_grid());
                               const std::vector<Pose2>& poses = h.poses->result.path_poses;  // x, y of each pose
                               std::vector<double> xy;
                               xy.reserve(2 * poses.size());
                               for (const Pose2& p : poses) xy.insert(xy.end(), {json_coordinate(p.x), json_coordinate(p.y)});
                               return owning_array(std::move(xy), {static_cast<py::ssize_t>(poses.size()), 2});
                             })
      .def_property_readonly("path_cells", [](const PlanResultHandle& h) { return cells_array(h.result().path_cells); })
      .def_property_readonly(
          "smoothed_path",
          [](const PlanResultHandle& h) -> py::object {
            if (!h.occupancy || !h.occupancy->smoothed) return py::none();
            const std::vector<Vec2>& pts = h.occupancy->smoothed->points;
            std::vector<double> xy(2 * pts.size());
            for (std::size_t i = 0; i < pts.size(); ++i) {
              const Vec2 p = h.index_grid() ? Vec2(pts[i] - Vec2(0.5, 0.5)) : pts[i];
              xy[2 * i] = json_coordinate(p.x());
              xy[2 * i + 1] = json_coordinate(p.y());
            }
            return owning_array(std::move(xy), {static_cast<py::ssize_t>(pts.size()), 2});
          },
          "with smooth='gradient': the smoothed points in the path's units, else None")
      .def_property_readonly(
          "expanded_cells",
          [](const PlanResultHandle& h) -> py::object {
            if (h.poses) return py::none();
            if (h.occupancy) return h.report.expanded ? py::object(cells_array(h.occupancy->planner->trace())) : py::none();
            return h.terrain->options.record_trace ? py::object(cells_array(h.terrain->trace)) : py::none();
          },
          "with expanded=True: the expanded cells in order, else None")
      .def("json", &PlanResultHandle::json, "The CLI's `starnav plan --json` line for this query.")
      .def(
          "to_dict", [](const PlanResultHandle& h) { return py::module_::import("json").attr("loads")(h.json()); },
          "json() as a dict (metrics, options and the rest of the report).")
      .def("__bool__", [](const PlanResultHandle& h) { return h.result().found(); })
      .def("__repr__", [](const PlanResultHandle& h) {
        const PlanResult& r = h.result();
        return "<starnav.PlanResult " + std::string(plan_status_reason(r.status)) +
               (r.found() ? ", cost " + format_param_real(r.cost) + ", " + std::to_string(r.path_cells.size()) + " points" : "") +
               ">";
      });

  py::class_<PlanBatchHandle>(m, "PlanBatch", R"doc(
The results of many queries (plan_many), in query order: arrays of N, and the paths.)doc")
      .def("__len__", [](const PlanBatchHandle& b) { return b.results.size(); })
      .def_property_readonly("planner", [](const PlanBatchHandle& b) { return b.planner; })
      .def_property_readonly("units", [](const PlanBatchHandle& b) { return std::string(b.index_grid ? "cells" : "m"); })
      .def_property_readonly("found",
                             [](const PlanBatchHandle& b) {
                               std::vector<std::uint8_t> v;
                               for (const PlanResult& r : b.results) v.push_back(r.found() ? 1 : 0);
                               return py::array(owning_array(std::move(v), {static_cast<py::ssize_t>(b.results.size())})).attr("astype")("bool");
                             })
      .def_property_readonly("reasons",
                             [](const PlanBatchHandle& b) {
                               py::list l;
                               for (const PlanResult& r : b.results) l.append(plan_status_reason(r.status));
                               return l;
                             })
      .def_property_readonly("cost",
                             [](const PlanBatchHandle& b) {
                               std::vector<double> v;
                               for (const PlanResult& r : b.results) v.push_back(r.found() ? r.cost : std::nan(""));
                               return owning_array(std::move(v), {static_cast<py::ssize_t>(b.results.size())});
                             },
                             "per query (NaN without a path)")
      .def_property_readonly("length",
                             [](const PlanBatchHandle& b) {
                               std::vector<double> v;
                               for (const PlanResult& r : b.results) v.push_back(r.found() ? r.length : std::nan(""));
                               return owning_array(std::move(v), {static_cast<py::ssize_t>(b.results.size())});
                             })
      .def_property_readonly("expanded",
                             [](const PlanBatchHandle& b) {
                               std::vector<std::uint64_t> v;
                               for (const PlanResult& r : b.results) v.push_back(r.expanded);
                               return owning_array(std::move(v), {static_cast<py::ssize_t>(b.results.size())});
                             })
      .def_property_readonly("generated",
                             [](const PlanBatchHandle& b) {
                               std::vector<std::uint64_t> v;
                               for (const PlanResult& r : b.results) v.push_back(r.generated);
                               return owning_array(std::move(v), {static_cast<py::ssize_t>(b.results.size())});
                             })
      .def_property_readonly("time_ms",
                             [](const PlanBatchHandle& b) {
                               std::vector<double> v;
                               for (const PlanResult& r : b.results) v.push_back(r.time_ms);
                               return owning_array(std::move(v), {static_cast<py::ssize_t>(b.results.size())});
                             })
      .def(
          "path", [](const PlanBatchHandle& b, std::size_t i) {
            if (i >= b.results.size()) throw py::index_error("query " + std::to_string(i) + " of " + std::to_string(b.results.size()));
            return path_array(b.results[i], b.index_grid);
          },
          py::arg("i"), "The path of query i in the CLI's units, (N, 2).")
      .def(
          "path_cells", [](const PlanBatchHandle& b, std::size_t i) {
            if (i >= b.results.size()) throw py::index_error("query " + std::to_string(i) + " of " + std::to_string(b.results.size()));
            return cells_array(b.results[i].path_cells);
          },
          py::arg("i"));

  m.def("plan", &plan_query, py::arg("map"), py::arg("start"), py::arg("goal"), py::arg("planner") = py::none(),
        py::arg("cells") = false, py::arg("params") = py::dict(),
        "One query as `starnav plan` runs it; `params` are the declared query parameters (see starnav.planners).");
  m.def("plan_many", &plan_batch, py::arg("map"), py::arg("starts"), py::arg("goals"), py::arg("planner") = py::none(),
        py::arg("cells") = false, py::arg("threads") = 1u, py::arg("params") = py::dict(),
        "Many queries in C++ with the GIL released: one planner per thread, built once.");
}

}  // namespace starnav::python
