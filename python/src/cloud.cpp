// Point clouds: N x 3 arrays in and out (float64 C-ordered arrays are read in place, as the
// library's own points), the filters, the cloud files, and 3D registration with the registry's
// matchers (the same calls as `starnav cloud register`).
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>

#include "bindings.hpp"
#include "starnav/cloud/cloud_filters.hpp"
#include "starnav/cloud/cloud_io.hpp"
#include "starnav/cloud/scan_matcher_3d.hpp"
#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/experiment/cloud_registration.hpp"
#include "starnav/registry/components.hpp"

namespace starnav::python {

Points points_of(const py::handle& data, const char* field) {
  const py::array any = py::module_::import("numpy").attr("asarray")(data);
  if (any.ndim() != 2 || any.shape(1) != 3)
    throw Error("expected an (N, 3) array of points, got shape " + std::string(py::str(any.attr("shape"))), {}, 0, field);
  const char kind = any.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u')
    throw Error("expected real coordinates, got dtype " + std::string(py::str(any.dtype())), {}, 0, field);
  Points p;
  p.array = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(any);
  if (reinterpret_cast<std::uintptr_t>(p.array.data()) % alignof(Vec3) != 0)  // a view into unaligned bytes
    p.array = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(
        py::module_::import("numpy").attr("array")(p.array, py::arg("copy") = true));
  static_assert(sizeof(Vec3) == 3 * sizeof(double), "Vec3 must be three packed doubles");
  p.span = {reinterpret_cast<const Vec3*>(p.array.data()), static_cast<std::size_t>(p.array.shape(0))};
  for (std::size_t i = 0; i < p.span.size(); ++i)
    if (!p.span[i].allFinite()) throw Error("point " + std::to_string(i) + " is not finite", {}, 0, field);
  return p;
}

py::array cloud_array(PointCloud&& cloud) {
  auto* held = new PointCloud(std::move(cloud));
  py::capsule owner(held, [](void* p) { delete static_cast<PointCloud*>(p); });
  const auto n = static_cast<py::ssize_t>(held->size());
  return py::array(py::dtype::of<double>(), std::vector<py::ssize_t>{n, 3},
                   std::vector<py::ssize_t>{static_cast<py::ssize_t>(sizeof(Vec3)), static_cast<py::ssize_t>(sizeof(double))},
                   reinterpret_cast<const double*>(held->data()), owner);
}

Rigid3 transform_of(const py::handle& initial, const char* field) {
  if (initial.is_none()) return Rigid3::Identity();
  const py::array a = py::module_::import("numpy").attr("asarray")(initial, py::arg("dtype") = "float64");
  const auto v = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a);
  if (v.ndim() == 1 && v.shape(0) == 6) {
    const double* p = v.data();
    for (int i = 0; i < 6; ++i)
      if (!std::isfinite(p[i])) throw Error("expected finite numbers", {}, 0, field);
    return to_rigid(Pose3::from_rpy(Vec3(p[0], p[1], p[2]), deg_to_rad(p[3]), deg_to_rad(p[4]), deg_to_rad(p[5])));
  }
  if (v.ndim() != 2 || v.shape(0) != 4 || v.shape(1) != 4)
    throw Error("expected a 4 x 4 transform or (x, y, z, roll, pitch, yaw) in m and degrees", {}, 0, field);
  Eigen::Matrix4d t;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) t(r, c) = v.at(r, c);
  if (!t.allFinite()) throw Error("expected finite numbers", {}, 0, field);
  const Eigen::Matrix3d rot = t.topLeftCorner<3, 3>();
  if ((rot.transpose() * rot - Eigen::Matrix3d::Identity()).norm() > 1e-6 || rot.determinant() < 0.0 ||
      t.row(3) != Eigen::RowVector4d(0, 0, 0, 1))
    throw Error("not a rigid transform (a rotation, a translation and the row 0 0 0 1)", {}, 0, field);
  Rigid3 out = Rigid3::Identity();
  out.matrix() = t;
  return out;
}

py::array matrix_array(const Rigid3& t) {
  std::vector<double> m(16);
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m[static_cast<std::size_t>(4 * r + c)] = t(r, c);
  return owning_array(std::move(m), {4, 4});
}

namespace {

// A matcher of the registry with its settings, and the reference it was last given.
struct MatcherHandle {
  std::string name;
  std::unique_ptr<ScanMatcher3d> matcher;
  py::object reference;  // the array the matcher was prepared on
  std::size_t reference_points = 0;
};

MatcherHandle make_matcher(const std::string& method, const py::dict& kwargs) {
  MatcherHandle h;
  std::string warning;
  const ScanMatcher3dDef& def = find_scan_matcher_3d(method, "method", &warning);
  warn_deprecated(warning);
  h.matcher = def.make({}, settings_of(kwargs));
  h.name = h.matcher->name();
  return h;
}

py::dict registration_dict(const CloudRegistration& r) {
  py::dict d;
  d["matcher"] = r.matcher;
  d["transform"] = matrix_array(r.match.transform);
  d["fitness"] = r.match.fitness;
  d["converged"] = r.match.converged;
  d["iterations"] = r.match.iterations;
  d["source_points"] = r.source_points;
  d["target_points"] = r.target_points;
  d["time_s"] = r.match.time_s;
  d["json"] = cloud_registration_json(r);
  return d;
}


}  // namespace

void bind_cloud(py::module_& m) {
  m.def(
      "read_cloud", [](const std::string& path) { return cloud_array(read_point_cloud(path).points); }, py::arg("path"),
      "Reads a PCD, PLY or KITTI .bin file (x, y, z; non-finite points dropped): an (N, 3) float64 array.");
  m.def(
      "write_cloud",
      [](const std::string& path, const py::object& points, bool binary) {
        const Points p = points_of(points, "points");
        const std::string ext = path.size() >= 4 ? path.substr(path.size() - 4) : "";
        PointCloudFormat f = PointCloudFormat::Pcd;
        if (ext == ".ply") f = PointCloudFormat::Ply;
        else if (ext != ".pcd") throw Error("expected a .pcd or .ply file name", path);
        write_point_cloud(path, p.span, f, binary ? PointCloudEncoding::Binary : PointCloudEncoding::Ascii);
      },
      py::arg("path"), py::arg("points"), py::kw_only(), py::arg("binary") = false,
      "Writes points as PCD or PLY (by the extension), ASCII or binary.");
  m.def(
      "voxel_downsample",
      [](const py::object& points, double leaf_m) {
        const Points p = points_of(points, "points");
        PointCloud out;
        {
          py::gil_scoped_release release;
          out = voxel_downsample(p.span, leaf_m);
        }
        return cloud_array(std::move(out));
      },
      py::arg("points"), py::arg("leaf_m"),
      "One point per voxel of side leaf_m (the centroid of its points), in voxel order (z, then y, then x index).");
  m.def(
      "crop",
      [](const py::object& points, double min_range_m, double max_range_m, double min_z_m, double max_z_m) {
        const Points p = points_of(points, "points");
        const RangeWindow w{min_range_m, max_range_m, min_z_m, max_z_m};
        PointCloud out;
        {
          py::gil_scoped_release release;
          out = crop_range_height(p.span, w);
        }
        return cloud_array(std::move(out));
      },
      py::arg("points"), py::kw_only(), py::arg("min_range_m") = RangeWindow{}.min_range_m,
      py::arg("max_range_m") = RangeWindow{}.max_range_m, py::arg("min_z_m") = -kInfinity, py::arg("max_z_m") = kInfinity,
      "The points with min_range_m <= |p| <= max_range_m and min_z_m <= z <= max_z_m, in input order.");
  m.def(
      "remove_radius_outliers",
      [](const py::object& points, double radius_m, std::size_t min_neighbours) {
        const Points p = points_of(points, "points");
        PointCloud out;
        {
          py::gil_scoped_release release;
          out = remove_radius_outliers(p.span, radius_m, min_neighbours);
        }
        return cloud_array(std::move(out));
      },
      py::arg("points"), py::arg("radius_m"), py::arg("min_neighbours"),
      "The points with at least min_neighbours others within radius_m, in input order.");
  m.def(
      "prefilter",
      [](const py::object& points, const py::kwargs& kwargs) {
        const Points p = points_of(points, "points");
        const std::vector<ParamSetting> settings = settings_of(kwargs);
        PrefilterConfig c = configured(prefilter_params(), settings, {});
        try {
          c.validate();
        } catch (const Error& e) {
          rethrow_at_setting(e, settings);
        }
        PrefilterCounts counts;
        PointCloud out;
        {
          py::gil_scoped_release release;
          out = prefilter_cloud(p.span, c, &counts);
        }
        py::dict n;
        n["raw"] = counts.raw;
        n["windowed"] = counts.windowed;
        n["voxelised"] = counts.voxelised;
        n["kept"] = counts.kept;
        return py::make_tuple(cloud_array(std::move(out)), n);
      },
      py::arg("points"));

  py::class_<MatcherHandle>(m, "Matcher", R"doc(
A 3D scan matcher of the registry (icp, gicp, ndt, ndt_mt, and pcl_* with the PCL plugin) with its
declared parameters: set_reference(target) prepares the reference once (a k-d tree, NDT's voxels),
match(source, initial) registers any number of scans onto it.)doc")
      .def(py::init(&make_matcher), py::arg("method") = "gicp", py::arg("params") = py::dict())
      .def_property_readonly("name", [](const MatcherHandle& h) { return h.name; })
      .def_property_readonly("threads", [](const MatcherHandle& h) { return h.matcher->threads(); })
      .def(
          "set_reference",
          [](MatcherHandle& h, const py::object& target) {
            const Points p = points_of(target, "target");
            {
              py::gil_scoped_release release;
              h.matcher->set_reference(p.span);
            }
            h.reference = p.array;
            h.reference_points = p.span.size();
          },
          py::arg("target"))
      .def(
          "match",
          [](MatcherHandle& h, const py::object& source, const py::object& initial) {
            if (!h.reference) throw Error("set_reference(target) first", {}, 0, "target");
            const Points p = points_of(source, "source");
            const Rigid3 guess = transform_of(initial);
            CloudRegistration r;
            {
              py::gil_scoped_release release;
              r.match = h.matcher->match(p.span, guess);
            }
            r.matcher = h.name;
            r.source_points = p.span.size();
            r.target_points = h.reference_points;
            return registration_dict(r);
          },
          py::arg("source"), py::arg("initial") = py::none());

  m.def(
      "register_clouds",
      [](const py::object& source, const py::object& target, const std::string& method, const py::object& initial,
         const py::dict& params) {
        CloudRegistrationRequest rq;
        rq.matcher = method;
        rq.matcher_field = "method";
        rq.settings = settings_of(params);
        rq.initial = transform_of(initial);
        const Points s = points_of(source, "source"), t = points_of(target, "target");
        std::string warning;
        CloudRegistration r;
        {
          py::gil_scoped_release release;
          r = register_cloud_points(s.span, t.span, rq, &warning);
        }
        warn_deprecated(warning);
        return registration_dict(r);
      },
      py::arg("source"), py::arg("target"), py::arg("method") = "gicp", py::arg("initial") = py::none(),
      py::arg("params") = py::dict(),
      "The rigid transform T with target ~= T * source: the run of `starnav cloud register` (the same JSON).");
  m.def(
      "pose_matrix",
      [](double x, double y, double z, double roll_deg, double pitch_deg, double yaw_deg) {
        return matrix_array(to_rigid(Pose3::from_rpy(Vec3(x, y, z), deg_to_rad(roll_deg), deg_to_rad(pitch_deg), deg_to_rad(yaw_deg))));
      },
      py::arg("x"), py::arg("y"), py::arg("z"), py::arg("roll_deg"), py::arg("pitch_deg"), py::arg("yaw_deg"),
      "The 4 x 4 transform of a pose (m, degrees; roll, pitch, yaw as the CLI's --initial and --mount).");
}

}  // namespace starnav::python
