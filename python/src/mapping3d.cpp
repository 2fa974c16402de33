// 3D mapping from Python (docs/python.md, "3D SLAM and the octree"): `starnav slam3d` as one call
// (the library's driver, run with the GIL released) whose results are arrays, and the octree
// (cloud/octree_map.hpp) as an object: scans inserted from arrays, occupancy and probability
// queried at arrays of points, its .bt file and its 2D grid.
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "bindings.hpp"
#include "starnav/cloud/octree_map.hpp"
#include "starnav/core/angle.hpp"
#include "starnav/harness/slam3d_record.hpp"
#include "starnav/harness/slam3d_run.hpp"

namespace starnav::python {

namespace {

// ---- the octree -----------------------------------------------------------------------------------

struct OctreeHandle {
  std::shared_ptr<OctreeMap> map;
};

OctreeMapConfig octree_config(double resolution_m, double prob_hit, double prob_miss, double clamping_min, double clamping_max,
                              double occupancy_threshold, double max_range_m, bool discretize) {
  OctreeMapConfig c;
  c.resolution_m = resolution_m;
  c.prob_hit = prob_hit;
  c.prob_miss = prob_miss;
  c.clamping_min = clamping_min;
  c.clamping_max = clamping_max;
  c.occupancy_threshold = occupancy_threshold;
  c.max_range_m = max_range_m;
  c.discretize = discretize;
  c.validate();  // errors name the keyword (the config's fields are the keywords)
  return c;
}

py::dict octree_config_dict(const OctreeMapConfig& c) {
  py::dict d;
  d["resolution_m"] = c.resolution_m;
  d["prob_hit"] = c.prob_hit;
  d["prob_miss"] = c.prob_miss;
  d["clamping_min"] = c.clamping_min;
  d["clamping_max"] = c.clamping_max;
  d["occupancy_threshold"] = c.occupancy_threshold;
  d["max_range_m"] = c.max_range_m;
  d["discretize"] = c.discretize;
  return d;
}

py::dict insert_stats_dict(const OctreeInsertStats& s) {
  py::dict d;
  d["inserted"] = s.inserted;
  d["non_finite"] = s.non_finite;
  d["outside_extent"] = s.outside_extent;
  return d;
}

// An (N, 3) array of points that may hold NaN (a query, or an organised cloud's holes): read in
// place when float64 and C-ordered, else from a copy.
py::array_t<double, py::array::c_style | py::array::forcecast> query_points(const py::handle& data, const char* field) {
  const py::array any = py::module_::import("numpy").attr("asarray")(data);
  const bool one = any.ndim() == 1 && any.shape(0) == 3;
  if (!one && (any.ndim() != 2 || any.shape(1) != 3))
    throw Error("expected an (N, 3) array of points, got shape " + std::string(py::str(any.attr("shape"))), {}, 0, field);
  const char kind = any.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u')
    throw Error("expected real coordinates, got dtype " + std::string(py::str(any.dtype())), {}, 0, field);
  const py::object rows = one ? py::object(any.attr("reshape")(1, 3)) : py::object(any);
  return py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(rows);
}

Vec3 query_point(const double* p) { return Vec3(p[0], p[1], p[2]); }

OctreeInsertStats insert_scan(OctreeHandle& h, const py::handle& points, const py::handle& pose) {
  const auto a = query_points(points, "points");
  const Rigid3 sensor_pose = transform_of(pose, "pose");
  std::vector<Vec3> cloud(static_cast<std::size_t>(a.shape(0)));
  for (std::size_t i = 0; i < cloud.size(); ++i) cloud[i] = query_point(a.data() + 3 * i);
  py::gil_scoped_release release;
  return h.map->insert_scan(sensor_pose, cloud);
}

// The occupancy of each point: 100 occupied, 0 free, -1 unknown (the 2D grids' values).
py::array occupancy_of(const OctreeHandle& h, const py::handle& points) {
  const auto a = query_points(points, "points");
  const auto n = static_cast<std::size_t>(a.shape(0));
  std::vector<std::int8_t> out(n);
  {
    const double* p = a.data();
    py::gil_scoped_release release;
    for (std::size_t i = 0; i < n; ++i) {
      const CellState s = h.map->occupancy(query_point(p + 3 * i));
      out[i] = s == CellState::Occupied ? std::int8_t{100} : s == CellState::Free ? std::int8_t{0} : std::int8_t{-1};
    }
  }
  return owning_array(std::move(out), {static_cast<py::ssize_t>(n)});
}

py::array probability_of(const OctreeHandle& h, const py::handle& points) {
  const auto a = query_points(points, "points");
  const auto n = static_cast<std::size_t>(a.shape(0));
  std::vector<double> out(n);
  {
    const double* p = a.data();
    py::gil_scoped_release release;
    for (std::size_t i = 0; i < n; ++i) out[i] = h.map->probability(query_point(p + 3 * i)).value_or(std::numeric_limits<double>::quiet_NaN());
  }
  return owning_array(std::move(out), {static_cast<py::ssize_t>(n)});
}

py::object project(const OctreeHandle& h, double resolution_m, double floor_z_m, double min_height_m, double max_height_m,
                   double padding_m) {
  GridProjectionConfig c;
  c.resolution_m = resolution_m;
  c.floor_z_m = floor_z_m;
  c.min_height_m = min_height_m;
  c.max_height_m = max_height_m;
  c.padding_m = padding_m;
  LoadedMap loaded;
  loaded.format = MapFormat::RosMap;
  {
    py::gil_scoped_release release;
    loaded.map = h.map->project_to_grid(c);
  }
  return wrap_map(std::move(loaded), "octree", false);
}

// ---- slam3d ---------------------------------------------------------------------------------------

struct Slam3dRunHandle {
  std::shared_ptr<Slam3dRunResult> result;
  std::string input;
};

Slam3dRunHandle slam3d_run(const py::object& input, const std::string& matcher, int frames, const py::object& poses,
                           const py::object& mount, double rate_hz, const py::object& cloud_topic, const py::object& odom_topic,
                           const py::object& truth_topic, const py::dict& matcher_params, const py::dict& params) {
  Slam3dRunConfig c;
  c.matcher = matcher;
  c.matcher_field = "matcher";
  if (frames < 0) throw Error("must be >= 0", "", 0, "frames");
  c.max_frames = frames;
  c.settings = settings_of(params);
  c.matcher_settings = settings_of(matcher_params);
  if (!poses.is_none()) c.recording.poses = path_of(poses);
  if (!mount.is_none()) {
    const py::array a = py::module_::import("numpy").attr("asarray")(mount, py::arg("dtype") = "float64");
    if (a.ndim() == 1 && a.size() == 6) {
      // As the CLI's --mount X,Y,Z,ROLL,PITCH,YAW (m, degrees), to the same bits.
      const auto v = a.cast<std::vector<double>>();
      for (double x : v)
        if (!std::isfinite(x)) throw Error("expected finite numbers", {}, 0, "mount");
      c.recording.mount = Pose3::from_rpy(Vec3(v[0], v[1], v[2]), v[3] * kPi / 180, v[4] * kPi / 180, v[5] * kPi / 180);
    } else {
      const Rigid3 m = transform_of(mount, "mount");
      Pose3 p;
      p.position = m.translation();
      p.orientation = Eigen::Quaterniond(m.linear());
      c.recording.mount = p;
    }
  }
  if (!(std::isfinite(rate_hz) && rate_hz > 0 && rate_hz <= 10000)) throw Error("must be in (0, 10000] Hz", "", 0, "rate_hz");
  c.recording.rate_hz = rate_hz;
  const auto text = [](const py::object& o) { return o.is_none() ? std::string() : o.cast<std::string>(); };
  c.recording.bag = {text(cloud_topic), text(odom_topic), text(truth_topic)};
  Slam3dRunHandle h;
  h.input = path_of(input);
  h.result = std::make_shared<Slam3dRunResult>();
  {
    py::gil_scoped_release release;
    *h.result = with_missing_files({h.input, c.recording.poses}, [&] { return run_slam3d(h.input, c); });
  }
  return h;
}

// (N, 8) float64: t, x, y, z, qw, qx, qy, qz (trajectory.csv's columns but the frame number).
py::array pose_rows(const std::vector<double>& t, const std::vector<Rigid3>& poses) {
  std::vector<double> v;
  v.reserve(8 * poses.size());
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const Eigen::Quaterniond q(poses[i].linear());
    const Vec3 p = poses[i].translation();
    v.insert(v.end(), {t[i], p.x(), p.y(), p.z(), q.w(), q.x(), q.y(), q.z()});
  }
  return owning_array(std::move(v), {static_cast<py::ssize_t>(poses.size()), 8});
}

py::array matrices(const std::vector<Rigid3>& poses) {
  std::vector<double> v;
  v.reserve(16 * poses.size());
  for (const Rigid3& t : poses)
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) v.push_back(t(r, c));
  return owning_array(std::move(v), {static_cast<py::ssize_t>(poses.size()), 4, 4});
}

std::vector<double> frame_times(const Slam3dRunResult& r) {
  std::vector<double> t;
  for (std::size_t i = 0; i < r.trajectory.size(); ++i) t.push_back(r.input.frames[i].t_s);
  return t;
}

std::vector<Rigid3> truth_poses(const Slam3dRunResult& r) {
  std::vector<Rigid3> out;
  const Rigid3 mount = to_rigid(r.input.mount);
  for (std::size_t i = 0; i < r.trajectory.size(); ++i) out.push_back(to_rigid(*r.input.frames[i].truth) * mount);
  return out;
}

py::dict keyframes_dict(const Slam3dRunResult& r) {
  const auto& k = r.keyframes;
  const auto n = static_cast<py::ssize_t>(k.size());
  std::vector<std::int64_t> frame, points;
  std::vector<double> t, distance, floor;
  std::vector<Rigid3> poses;
  for (const Slam3dKeyframe& f : k) {
    frame.push_back(static_cast<std::int64_t>(f.frame));
    points.push_back(static_cast<std::int64_t>(f.cloud.size()));
    t.push_back(f.t_s);
    distance.push_back(f.accum_distance_m);
    poses.push_back(f.pose);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    if (f.floor) floor.insert(floor.end(), {f.floor->normal.x(), f.floor->normal.y(), f.floor->normal.z(), f.floor->d});
    else floor.insert(floor.end(), {nan, nan, nan, nan});
  }
  py::dict d;
  d["frame"] = owning_array(std::move(frame), {n});
  d["t"] = owning_array(std::move(t), {n});
  d["poses"] = matrices(poses);
  d["points"] = owning_array(std::move(points), {n});
  d["accum_distance_m"] = owning_array(std::move(distance), {n});
  d["floor"] = owning_array(std::move(floor), {n, 4});
  return d;
}

Slam3dMapConfig map_config(double resolution_m, double max_range_m) {
  Slam3dMapConfig c;
  c.octree.resolution_m = resolution_m;
  c.octree.max_range_m = max_range_m;
  c.octree.validate();
  return c;
}

}  // namespace

void bind_mapping3d(py::module_& m) {
  py::class_<OctreeHandle>(m, "Octree",
                           "The 3D occupancy octree (OctoMap's model; cloud/octree_map.hpp): scans inserted as rays from the "
                           "sensor, occupancy and probability per voxel.")
      .def(py::init([](double resolution_m, double prob_hit, double prob_miss, double clamping_min, double clamping_max,
                       double occupancy_threshold, double max_range_m, bool discretize) {
             return OctreeHandle{std::make_shared<OctreeMap>(octree_config(resolution_m, prob_hit, prob_miss, clamping_min, clamping_max,
                                                                           occupancy_threshold, max_range_m, discretize))};
           }),
           py::arg("resolution_m") = 0.05, py::kw_only(), py::arg("prob_hit") = 0.7, py::arg("prob_miss") = 0.4,
           py::arg("clamping_min") = 0.1192, py::arg("clamping_max") = 0.971, py::arg("occupancy_threshold") = 0.5,
           py::arg("max_range_m") = std::numeric_limits<double>::infinity(), py::arg("discretize") = true,
           "An empty octree: voxels of resolution_m, OctoMap's sensor model (prob_hit, prob_miss, clamping_min, clamping_max,\n"
           "occupancy_threshold), rays clearing free space up to max_range_m (m; inf: no limit), discretize: OctoMap's\n"
           "discretised insertion (one ray per end voxel, to its centre). Bad values raise starnav.InputError naming the keyword.")
      .def_property_readonly("resolution", [](const OctreeHandle& h) { return h.map->resolution(); }, "the voxel size (m)")
      .def_property_readonly("config", [](const OctreeHandle& h) { return octree_config_dict(h.map->config()); },
                             "the configuration, as the keywords that built it")
      .def("insert_scan", [](OctreeHandle& h, const py::handle& points, const py::handle& pose) {
             return insert_stats_dict(insert_scan(h, points, pose));
           }, py::arg("points"), py::arg("pose") = py::none(),
           "Inserts one scan: points (N, 3) in the sensor frame, pose the sensor in the map frame (None: identity; a 4 x 4\n"
           "transform or (x, y, z, roll, pitch, yaw) in m and degrees). Every voxel a ray crosses gets a miss, every end voxel\n"
           "a hit (OctoMap's insertPointCloud; the GIL released). Non-finite points are dropped and counted. Returns\n"
           "{inserted, non_finite, outside_extent}.")
      .def("occupancy", &occupancy_of, py::arg("points"),
           "(N,) int8 of (N, 3) points (map frame): 100 occupied, 0 free, -1 unknown (never observed, outside, or NaN)")
      .def("probability", &probability_of, py::arg("points"),
           "(N,) float64 of (N, 3) points (map frame): the voxel's occupancy probability, NaN where unknown")
      .def_property_readonly("occupied_leaf_count", [](const OctreeHandle& h) { return h.map->occupied_leaf_count(); },
                             "occupied leaves (a pruned leaf once, as the .bt file stores it)")
      .def_property_readonly("occupied_voxel_count", [](const OctreeHandle& h) { return h.map->occupied_voxel_count(); },
                             "occupied voxels at the map's resolution")
      .def("occupied_voxels", [](const OctreeHandle& h) {
             PointCloud c;
             {
               py::gil_scoped_release release;
               c = h.map->occupied_voxel_centres();
             }
             return cloud_array(std::move(c));
           }, "(N, 3) float64: the centre of every occupied voxel, ordered by (x, y, z) index")
      .def("known_bounds", [](const OctreeHandle& h) -> py::object {
             const auto b = h.map->known_bounds();
             if (!b) return py::none();
             return py::make_tuple(owning_array(std::vector<double>{b->min.x(), b->min.y(), b->min.z()}, {3}),
                                   owning_array(std::vector<double>{b->max.x(), b->max.y(), b->max.z()}, {3}));
           }, "(min (3,), max (3,)): the box of the known space, voxel faces included; None for an empty map")
      .def_property_readonly("memory_bytes", [](const OctreeHandle& h) { return h.map->memory_bytes(); }, "OctoMap's estimate")
      .def("binary", [](const OctreeHandle& h) { return py::bytes(h.map->binary()); },
           "the .bt file's bytes (OctoMap's compact binary format: the maximum-likelihood map)")
      .def("write", [](const OctreeHandle& h, const py::object& path) {
             const std::string p = path_of(path);
             py::gil_scoped_release release;
             h.map->write(p);
           }, py::arg("path"), "Writes the .bt file (as `starnav slam3d` writes map.bt).")
      .def("project_to_grid", &project, py::arg("resolution_m") = 0.0, py::arg("floor_z_m") = 0.0, py::arg("min_height_m") = 0.1,
           py::arg("max_height_m") = 0.6, py::arg("padding_m") = 0.0,
           "The planner's 2D grid (a starnav.OccupancyMap, row 0 at the bottom): a cell is occupied when an occupied voxel in\n"
           "the band [floor_z_m + min_height_m, floor_z_m + max_height_m] lies over it, else free when a free one does, else\n"
           "unknown; resolution_m 0: the octree's (as `starnav slam3d` writes map.yaml)");

  py::class_<Slam3dRunHandle>(m, "Slam3dRun", "A 3D SLAM run over a LiDAR recording (starnav.slam3d.run): `starnav slam3d`'s results.")
      .def_property_readonly("input", [](const Slam3dRunHandle& h) { return h.input; }, "the recording read")
      .def_property_readonly("input_kind", [](const Slam3dRunHandle& h) { return h.result->input_kind; },
                             "frames folder, cloud files, ROS 1 bag or ROS 2 bag")
      .def_property_readonly("matcher", [](const Slam3dRunHandle& h) { return h.result->matcher; }, "the scan matcher")
      .def_property_readonly("frames", [](const Slam3dRunHandle& h) { return h.result->frames; }, "frames run")
      .def_property_readonly("trajectory", [](const Slam3dRunHandle& h) { return pose_rows(frame_times(*h.result), h.result->trajectory); },
                             "(N, 8) float64: t (s), x, y, z (m), qw, qx, qy, qz: the sensor in the map frame at every frame")
      .def_property_readonly("poses", [](const Slam3dRunHandle& h) { return matrices(h.result->trajectory); },
                             "(N, 4, 4) float64: the same poses as transforms (sensor to map)")
      .def_property_readonly("truth", [](const Slam3dRunHandle& h) -> py::object {
             if (!h.result->has_truth) return py::none();
             return pose_rows(frame_times(*h.result), truth_poses(*h.result));
           }, "(N, 8) float64: the sensor's true pose in the truth's frame (None without truth)")
      .def_property_readonly("truth_alignment", [](const Slam3dRunHandle& h) { return matrix_array(h.result->truth_alignment); },
                             "4 x 4: the map frame into the truth's frame (position and heading of the first pose)")
      .def_property_readonly("keyframes", [](const Slam3dRunHandle& h) { return keyframes_dict(*h.result); },
                             "frame, t, poses (K, 4, 4), points, accum_distance_m, floor (K, 4: nx, ny, nz, d; NaN without)")
      .def("keyframe_cloud", [](const Slam3dRunHandle& h, std::int64_t i) {
             const auto n = static_cast<std::int64_t>(h.result->keyframes.size());
             if (i < -n || i >= n) throw Error("no key frame " + std::to_string(i) + " (" + std::to_string(n) + " key frames)", {}, 0, "index");
             PointCloud c = h.result->keyframes[static_cast<std::size_t>(i < 0 ? i + n : i)].cloud;
             return cloud_array(std::move(c));
           }, py::arg("index"), "(M, 3) float64: key frame `index`'s prefiltered cloud in the sensor frame")
      .def("map_cloud", [](const Slam3dRunHandle& h) {
             PointCloud c;
             {
               py::gil_scoped_release release;
               for (const Slam3dKeyframe& k : h.result->keyframes)
                 for (const Vec3& p : k.cloud) c.push_back(k.pose * p);
             }
             return cloud_array(std::move(c));
           }, "(M, 3) float64: every key frame's cloud at its optimised pose, in the map frame")
      .def_property_readonly("statistics", [](const Slam3dRunHandle& h) {
             // summary.json's numbers, read from its one writer so that the two never differ.
             const py::dict all = py::module_::import("json").attr("loads")(slam3d_summary_json(*h.result));
             py::dict d;
             for (const auto& [key, value] : all)
               if (py::isinstance<py::int_>(value) || py::isinstance<py::float_>(value)) d[key] = value;
             return d;
           }, "the run's figures (summary.json's; the errors with truth)")
      .def("summary_json", [](const Slam3dRunHandle& h) { return slam3d_summary_json(*h.result); }, "summary.json's text")
      .def("trajectory_csv", [](const Slam3dRunHandle& h) { return slam3d_trajectory_csv(*h.result); }, "trajectory.csv's text, byte for byte")
      .def("keyframes_csv", [](const Slam3dRunHandle& h) { return slam3d_keyframes_csv(*h.result); }, "keyframes.csv's text, byte for byte")
      .def("octree", [](const Slam3dRunHandle& h, double resolution_m, double max_range_m) {
             const Slam3dMapConfig c = map_config(resolution_m, max_range_m);
             std::shared_ptr<OctreeMap> map;
             {
               py::gil_scoped_release release;
               map = std::make_shared<OctreeMap>(slam3d_octree(h.result->keyframes, c));
             }
             return OctreeHandle{std::move(map)};
           }, py::arg("resolution_m") = 0.05, py::arg("max_range_m") = 10.0,
           "The run's map: every key frame's cloud inserted at its optimised pose (rays up to max_range_m clear free space),\n"
           "as `starnav slam3d` builds map.bt (--map-resolution-m)")
      .def("write", [](const Slam3dRunHandle& h, const py::object& folder, bool map, double resolution_m, double band_min_m,
                       double band_max_m, const py::object& plan_to, double inflation_m) {
             Slam3dOutputConfig c;
             c.field = "folder";
             c.map = map;
             c.map_config.octree.resolution_m = resolution_m;
             c.map_config.grid.min_height_m = band_min_m;
             c.map_config.grid.max_height_m = band_max_m;
             try {
               c.map_config.octree.validate();
               c.map_config.grid.validate();
             } catch (const Error& e) {
               throw Error(e.message(), "", 0,
                           e.field() == "resolution_m" ? "resolution_m" : e.field() == "min_height_m" ? "band_min_m" : "band_max_m");
             }
             if (!(inflation_m >= 0 && inflation_m <= 10)) throw Error("must be in [0, 10] m", "", 0, "inflation_m");
             if (!plan_to.is_none()) {
               const auto g = plan_to.cast<std::vector<double>>();
               if (g.size() != 2 || !std::isfinite(g[0]) || !std::isfinite(g[1]))
                 throw Error("expected (x, y), two finite numbers (m, map frame)", "", 0, "plan_to");
               c.plan_to = Vec2(g[0], g[1]);
             }
             c.inflation_m = inflation_m;
             const std::string dir = path_of(folder);
             Slam3dOutputs out;
             {
               py::gil_scoped_release release;
               out = write_slam3d_outputs(*h.result, h.input, dir, c);
             }
             std::vector<double> v;
             for (const Vec2& p : out.path) v.insert(v.end(), {p.x(), p.y()});
             const auto n = static_cast<py::ssize_t>(out.path.size());
             return owning_array(std::move(v), {n, 2});
           }, py::arg("folder"), py::kw_only(), py::arg("map") = true, py::arg("resolution_m") = 0.05, py::arg("band_min_m") = 0.1,
           py::arg("band_max_m") = 0.6, py::arg("plan_to") = py::none(), py::arg("inflation_m") = 0.35,
           "Writes the files of `starnav slam3d --out FOLDER` (trajectory.csv, keyframes.csv, summary.json; with map: map.bt,\n"
           "map.yaml + pgm, map.svg, map.png, and path.csv with plan_to (x, y); the run record), the keywords as its flags\n"
           "(--map-resolution-m, --band-m, --band-top-m, --plan-to, --inflation-m). Returns the planned path (N, 2).");
  m.def("slam3d_run", &slam3d_run, py::arg("input"), py::arg("matcher"), py::arg("frames"), py::arg("poses"), py::arg("mount"),
        py::arg("rate_hz"), py::arg("cloud_topic"), py::arg("odom_topic"), py::arg("truth_topic"), py::arg("matcher_params"),
        py::arg("params"), "3D graph SLAM on a LiDAR recording, as `starnav slam3d` (GIL released).");
}

}  // namespace starnav::python
