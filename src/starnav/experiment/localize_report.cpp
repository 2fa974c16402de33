#include "starnav/experiment/localize_report.hpp"

#include <algorithm>
#include <chrono>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <unordered_map>
#include <variant>
#include <vector>

#include "starnav/core/angle.hpp"
#include "starnav/core/cpu_time.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/record_format.hpp"
#include "starnav/core/rng.hpp"
#include "starnav/core/statistics.hpp"
#include "starnav/estimate/amcl.hpp"
#include "starnav/harness/navigation_run.hpp"
#include "starnav/harness/run_record.hpp"
#include "starnav/io/file_bytes.hpp"
#include "starnav/io/map_file.hpp"
#include "starnav/logs/robot_log_source.hpp"
#include "starnav/sense/sensor_bus.hpp"
#include "starnav/registry/components.hpp"
#include "starnav/viz/map_picture.hpp"

namespace starnav {

const char* localize_start_name(LocalizeStart s) {
  switch (s) {
    case LocalizeStart::Pose: return "pose";
    case LocalizeStart::Global: return "global";
    case LocalizeStart::FirstMatched: return "first";
  }
  return "?";
}

LocalizeErrorStats localize_error_stats(std::vector<double> values) {
  LocalizeErrorStats s;
  s.n = values.size();
  if (values.empty()) return s;
  std::sort(values.begin(), values.end());
  s.median = quantile_sorted(values, 0.5);
  s.p90 = quantile_sorted(values, 0.9);
  s.max = values.back();
  return s;
}

namespace {

// A scan's readings at 1 cm as bytes: the key raw and corrected twins share.
std::string localize_range_key(const LogScan& s) {
  std::string key;
  key.reserve(s.ranges_m.size() * sizeof(std::int32_t));
  for (const float r : s.ranges_m) {
    const double cm = static_cast<double>(r) * 100.0;
    std::int32_t v = INT32_MIN;  // NaN and infinities
    if (std::isfinite(cm)) v = static_cast<std::int32_t>(std::clamp(std::lround(cm), -2147483647L, 2147483647L));
    key.append(reinterpret_cast<const char*>(&v), sizeof v);
  }
  return key;
}

std::vector<std::pair<std::string, std::string>> localize_amcl_values(std::span<const ParamSetting> settings) {
  std::vector<std::pair<std::string, std::string>> out;
  for (const ParamSpec& spec : find_localizer("amcl").info.params) {
    if (spec.key == "initial") continue;
    std::string value = spec.default_value;
    for (const ParamSetting& s : settings)
      if (s.key == spec.key) value = s.value;
    if (spec.key == "robot_model_type" && value == "auto") value = "differential";  // no robot in a log
    out.emplace_back(spec.key, value);
  }
  return out;
}

nlohmann::ordered_json localize_value_json(const std::string& text) {
  if (text == "true") return true;
  if (text == "false") return false;
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (!text.empty() && end == text.c_str() + text.size() && std::isfinite(v)) return v;
  return text;
}

nlohmann::ordered_json localize_stats_json(const LocalizeErrorStats& m, const LocalizeErrorStats& deg) {
  nlohmann::ordered_json j;
  j["count"] = m.n;
  j["m"] = {{"median", m.median}, {"p90", m.p90}, {"max", m.max}};
  j["deg"] = {{"median", deg.median}, {"p90", deg.p90}, {"max", deg.max}};
  return j;
}

// An Error from a reader, named by the flag that gave its file when it names no field itself.
[[noreturn]] void localize_rethrow(const Error& e, const std::string& path, const std::string& flag) {
  throw Error(e.message(), e.file().empty() ? path : e.file(), e.line(), e.field().empty() ? flag : e.field());
}

}  // namespace

std::vector<std::optional<std::size_t>> match_scans_by_ranges(const RobotLog& raw, const RobotLog& reference) {
  struct Seen {
    std::size_t count = 0;
    std::size_t index = 0;
  };
  std::unordered_map<std::string, Seen> ref;
  for (std::size_t i = 0; i < reference.scans.size(); ++i) {
    if (!reference.scans[i].laser_pose) continue;
    Seen& s = ref[localize_range_key(reference.scans[i])];
    ++s.count;
    s.index = i;
  }
  std::vector<std::string> keys(raw.scans.size());
  std::unordered_map<std::string, std::size_t> raw_count;
  for (std::size_t i = 0; i < raw.scans.size(); ++i) {
    keys[i] = localize_range_key(raw.scans[i]);
    if (ref.count(keys[i])) ++raw_count[keys[i]];
  }
  std::vector<std::optional<std::size_t>> out(raw.scans.size());
  for (std::size_t i = 0; i < raw.scans.size(); ++i) {
    const auto it = ref.find(keys[i]);
    if (it != ref.end() && it->second.count == 1 && raw_count[keys[i]] == 1) out[i] = it->second.index;
  }
  return out;
}

std::vector<ParamSetting> localize_log_defaults(LocalizeStart start) {
  const auto d = [](const char* key, const char* value) {
    return ParamSetting{key, value, "", 0, std::string("amcl.") + key + " (the default on a log)"};
  };
  std::vector<ParamSetting> out = {d("update_min_d_m", "0"), d("update_min_a_deg", "0"), d("max_beams", "180"),
                                   d("sigma_hit_m", "0.1")};
  if (start == LocalizeStart::Global)
    for (ParamSetting s : {d("max_particles", "10000"), d("recovery_alpha_slow", "0.001"), d("recovery_alpha_fast", "0.1"),
                           d("scan_proposal", "true")})
      out.push_back(std::move(s));
  return out;
}

namespace {

// The log's defaults, then the user's settings (the later value of a key wins).
std::vector<ParamSetting> localize_settings(const LocalizeRunRequest& q) {
  for (const ParamSetting& s : q.settings)
    if (s.key == "initial")
      throw Error("the start is chosen with --initial here (x,y,yaw_deg | global | first)", s.file, s.line,
                  s.field.empty() ? "amcl.initial" : s.field);
  std::vector<ParamSetting> settings = localize_log_defaults(q.initial.kind);
  settings.insert(settings.end(), q.settings.begin(), q.settings.end());
  return settings;
}

}  // namespace

LocalizeRunResult run_localize(const RobotLog& log, const OccupancyGrid& map, const OccupancyThresholds& thresholds,
                               const RobotLog* reference, const LocalizeRunRequest& q,
                               const std::function<void(std::size_t, std::size_t)>& progress) {
  std::vector<ParamSetting> settings = localize_settings(q);

  LocalizeRunResult r;
  r.log = q.log;
  r.map = q.map;
  r.reference = q.reference;
  r.initial = q.initial;
  r.seed = q.seed;
  r.scans = log.scans.size();
  r.laser_in_base = log.laser_in_base.value_or(Pose2());
  r.amcl = localize_amcl_values(settings);
  for (const ParamSetting& s : q.settings) r.overrides.emplace_back("amcl." + s.key, s.value);
  r.grid = map;
  if (!log.scans.empty()) {
    const RobotLogSummary summary = summarise_log(log);
    r.log_duration_s = static_cast<double>(summary.last_us - summary.first_us) * 1e-6;
  }

  std::vector<std::optional<std::size_t>> twins(log.scans.size());
  if (reference) {
    twins = match_scans_by_ranges(log, *reference);
    for (const LogScan& s : reference->scans) r.reference_scans += s.laser_pose ? 1 : 0;
    for (const auto& t : twins) r.matched += t ? 1 : 0;
  }
  const Pose2 base_in_laser = r.laser_in_base.inverse();

  switch (q.initial.kind) {
    case LocalizeStart::Pose: r.initial_pose = q.initial.pose; break;
    case LocalizeStart::Global: break;
    case LocalizeStart::FirstMatched: {
      if (!reference) throw Error("'first' starts at the corrected pose of a scan: give --reference", {}, 0, "--initial");
      // The source gives the odometry by the same rule when the log is played.
      const std::vector<std::optional<Pose2>> odometry = scan_odometry(log);
      std::size_t i = 0;
      while (i < log.scans.size() && !(twins[i] && odometry[i])) ++i;
      if (i == log.scans.size())
        throw Error("no scan of the log (with odometry) has a twin with the same ranges here", q.reference, 0, "--reference");
      r.start_scan = i;
      r.initial_pose = reference->scans[*twins[i]].laser_pose->compose(base_in_laser);
      break;
    }
  }

  // The localizer, built by name with its declared parameters, as a scenario builds it.
  LocalizerContext context(r.initial_pose, q.seed, q.log.empty() ? log.path : q.log);
  context.map = &map;
  context.thresholds = thresholds;
  context.laser_in_base = r.laser_in_base;
  if (q.initial.kind == LocalizeStart::Global) settings.push_back({"initial", "global", "", 0, "--initial"});
  const std::unique_ptr<Localizer> localizer = find_localizer("amcl").make(context, settings);

  const std::size_t total = log.scans.size() - r.start_scan;
  const auto wall0 = std::chrono::steady_clock::now();
  const double cpu0 = thread_cpu_s();
  int updates = 0;
  r.trajectory.reserve(total);
  // After a reading's delivery: the estimate, its error where the reference has the scan, a step.
  const auto record_reading = [&](std::size_t i, double cpu_s) {
    const LogScan& s = log.scans[i];
    const PoseEstimate a = localizer->estimate();
    const bool updated = a.updates > updates;
    updates = a.updates;
    if (updated) r.update_cpu_s += cpu_s;
    LocalizePose p;
    p.stamp_us = s.stamp_us;
    p.scan = i;
    p.pose = a.pose;
    p.converged = a.converged;
    p.updated = updated;
    p.particles = a.particles;
    if (a.converged && !r.converged_at_update) {
      r.converged_at_update = a.updates;
      r.converged_at_scan = i;
    }
    if (twins[i]) {
      LocalizeError e;
      e.stamp_us = s.stamp_us;
      e.scan = i;
      e.estimate = p.pose.compose(r.laser_in_base);
      e.reference = *reference->scans[*twins[i]].laser_pose;
      e.err_m = (e.estimate.translation() - e.reference.translation()).norm();
      e.err_deg = std::abs(rad_to_deg(angle_diff(e.estimate.yaw, e.reference.yaw)));
      e.converged = a.converged;
      e.after_convergence = r.converged_at_scan.has_value();
      r.errors.push_back(e);
    }
    if (q.record_steps && (updated || r.step_lines.empty())) {
      // A step per filter update: the estimate (the body is drawn there), the particles, the scan's
      // end points from the estimate, and the corrected pose where the reference has the scan.
      NavStepRecord step;
      step.t_s = static_cast<double>(s.stamp_us) * 1e-6;
      step.pose = Pose3::from_rpy(Vec3(p.pose.x, p.pose.y, 0.0), 0.0, 0.0, p.pose.yaw);
      step.estimate = p.pose;
      for (const Vec2& h : s.end_points(p.pose.compose(r.laser_in_base), kStepHits)) step.hits.push_back(Vec3(h.x(), h.y(), 0.0));
      step.returns = s.ranges_m.size();
      step.particles = localizer->belief_samples(kStepParticles);
      if (twins[i]) step.reference = reference->scans[*twins[i]].laser_pose->compose(r.laser_in_base.inverse());
      r.step_lines.push_back(step_record_json(step));
    }
    r.trajectory.push_back(p);
  };
  // The Localizer role, as the simulator drives it: the log's messages on a bus, in the order the
  // robot received them, the localizer subscribed to the odometry and the scans.
  const RobotLogStreams streams;
  SensorBus bus(SensorBus::Order::Receipt);
  bus.subscribe<OdometryMessage>(streams.odometry, [&](const OdometryMessage& o) { localizer->on_odometry(o); });
  bus.subscribe<ScanMessage>(streams.scan, [&](const ScanMessage& s) { localizer->on_scan(s); });
  // A reading goes onto the bus whole, when it counts: from the start scan on, with its odometry.
  std::vector<SensorMessage> reading;
  RobotLogSource source(log, streams);
  source.play([&](const SensorMessage& m) { reading.push_back(m); },
              [&](std::size_t read) {
                const std::size_t i = read - 1;
                const bool counted = i >= r.start_scan;
                if (progress && counted && (i - r.start_scan) % 100 == 0) progress(i - r.start_scan, total);
                const bool odometry_given = std::any_of(reading.begin(), reading.end(), [](const SensorMessage& m) {
                  return std::holds_alternative<OdometryMessage>(m);
                });
                if (counted && !odometry_given) ++r.scans_without_odometry;
                if (!counted || !odometry_given) {
                  reading.clear();
                  return;
                }
                const double t0 = thread_cpu_s();
                for (SensorMessage& m : reading) bus.publish(std::move(m));
                reading.clear();
                bus.deliver_all();
                record_reading(i, thread_cpu_s() - t0);
              });
  if (progress) progress(total, total);
  r.cpu_s = thread_cpu_s() - cpu0;
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  r.updates = updates;
  if (r.trajectory.empty()) throw Error("no scan has an odometry pose to localize with", q.log.empty() ? log.path : q.log, 0, "LOG");

  std::vector<double> am, adeg, m, deg;
  for (const LocalizeError& e : r.errors) {
    m.push_back(e.err_m);
    deg.push_back(e.err_deg);
    if (!e.after_convergence) continue;
    am.push_back(e.err_m);
    adeg.push_back(e.err_deg);
  }
  r.after_m = localize_error_stats(std::move(am));
  r.after_deg = localize_error_stats(std::move(adeg));
  r.all_m = localize_error_stats(std::move(m));
  r.all_deg = localize_error_stats(std::move(deg));
  return r;
}

LocalizeRunResult run_localize_on_file(const LocalizeRunRequest& q, const std::function<void(std::size_t, std::size_t)>& progress) {
  // The settings first: a bad one is its own error, before any file is read (or warned about).
  (void)amcl_config_from_settings(localize_settings(q), {});
  LoadedMap loaded;
  try {
    loaded = load_map(q.map);
  } catch (const Error& e) {
    localize_rethrow(e, q.map, "--map");
  }
  if (loaded.is_elevation()) throw Error("is an elevation map; localization needs an occupancy grid", q.map, 0, "--map");
  RobotLog log;
  try {
    log = read_robot_log(q.log, q.read);
  } catch (const Error& e) {
    localize_rethrow(e, q.log, "LOG");
  }
  std::optional<RobotLog> reference;
  if (!q.reference.empty()) {
    try {
      reference = read_robot_log(q.reference);
    } catch (const Error& e) {
      localize_rethrow(e, q.reference, "--reference");
    }
    if (std::none_of(reference->scans.begin(), reference->scans.end(), [](const LogScan& s) { return s.laser_pose.has_value(); }))
      throw Error("no scan carries a laser pose (a corrected CARMEN log has them in its FLASER lines)", q.reference, 0, "--reference");
  }
  return run_localize(log, loaded.occupancy(), loaded.thresholds(), reference ? &*reference : nullptr, q, progress);
}

nlohmann::ordered_json localize_summary_json(const LocalizeRunResult& r) {
  nlohmann::ordered_json j;
  j["log"] = r.log;
  j["map"] = r.map;
  j["reference"] = r.reference.empty() ? nlohmann::ordered_json() : nlohmann::ordered_json(r.reference);
  nlohmann::ordered_json init;
  init["mode"] = localize_start_name(r.initial.kind);
  if (r.initial.kind != LocalizeStart::Global)
    init["pose"] = {unsigned_zero(r.initial_pose.x), unsigned_zero(r.initial_pose.y), unsigned_zero(rad_to_deg(r.initial_pose.yaw))};
  init["start_scan"] = r.start_scan;
  j["initial"] = init;
  j["seed"] = r.seed;
  j["scans"] = r.scans;
  j["scans_run"] = r.trajectory.size();
  j["scans_without_odometry"] = r.scans_without_odometry;
  j["log_duration_s"] = r.log_duration_s;
  j["laser_in_base"] = {r.laser_in_base.x, r.laser_in_base.y, r.laser_in_base.yaw};
  j["updates"] = r.updates;
  j["converged"] = r.converged_at_update.has_value();
  j["updates_until_converged"] = r.converged_at_update ? nlohmann::ordered_json(*r.converged_at_update) : nlohmann::ordered_json();
  j["converged_at_scan"] = r.converged_at_scan ? nlohmann::ordered_json(*r.converged_at_scan) : nlohmann::ordered_json();
  j["final_converged"] = r.trajectory.back().converged;
  j["final_particles"] = r.trajectory.back().particles;
  j["reference_scans"] = r.reference_scans;
  j["matched"] = r.matched;
  j["matched_run"] = r.errors.size();
  j["error_frame"] = "laser";
  j["error_after_convergence"] = localize_stats_json(r.after_m, r.after_deg);
  j["error_all"] = localize_stats_json(r.all_m, r.all_deg);
  j["cpu_s"] = r.cpu_s;
  j["wall_s"] = r.wall_s;
  j["update_cpu_s"] = r.update_cpu_s;
  j["cpu_per_update_ms"] = r.cpu_per_update_ms();
  nlohmann::ordered_json amcl;
  for (const auto& [k, v] : r.amcl) amcl[k] = localize_value_json(v);
  j["amcl"] = amcl;
  nlohmann::ordered_json overrides = nlohmann::ordered_json::object();
  for (const auto& [k, v] : r.overrides) overrides[k] = localize_value_json(v);
  j["overrides"] = overrides;
  return j;
}

std::string localize_summary_text(const LocalizeRunResult& r) {
  std::ostringstream o;
  o << "localize (amcl, start " << localize_start_name(r.initial.kind);
  if (r.start_scan > 0) o << " at scan " << r.start_scan;
  o << "): " << r.trajectory.size() << " scans, " << r.updates << " updates, ";
  if (r.converged_at_update) o << "converged after " << *r.converged_at_update << " updates (scan " << *r.converged_at_scan << ")";
  else o << "never converged";
  o << "; " << format_fixed(r.cpu_per_update_ms(), 2) << " ms CPU per update, " << format_fixed(r.cpu_s, 2) << " s CPU for "
    << format_fixed(r.log_duration_s, 1) << " s of log\n";
  if (!r.reference.empty()) {
    o << "reference: " << r.matched << " of " << r.scans << " scans have a corrected twin, " << r.errors.size() << " in the run";
    if (r.after_m.n > 0)
      o << "; after convergence (" << r.after_m.n << "): median " << format_fixed(r.after_m.median, 3) << " m / "
        << format_fixed(r.after_deg.median, 2) << " deg, p90 " << format_fixed(r.after_m.p90, 3) << " m / "
        << format_fixed(r.after_deg.p90, 2) << " deg, max " << format_fixed(r.after_m.max, 3) << " m / "
        << format_fixed(r.after_deg.max, 2) << " deg";
    o << "\n";
  }
  return o.str();
}

std::string localize_trajectory_csv(const LocalizeRunResult& r) {
  std::string s = "t_s,x_m,y_m,yaw_rad,converged,particles\n";
  for (const LocalizePose& p : r.trajectory)
    s.append(format_stamp_us(p.stamp_us))
        .append(",")
        .append(format_number(unsigned_zero(p.pose.x)))
        .append(",")
        .append(format_number(unsigned_zero(p.pose.y)))
        .append(",")
        .append(format_number(unsigned_zero(p.pose.yaw)))
        .append(p.converged ? ",1," : ",0,")
        .append(std::to_string(p.particles))
        .append("\n");
  return s;
}

std::string localize_errors_csv(const LocalizeRunResult& r) {
  std::string s = "t_s,err_m,err_deg,converged\n";
  for (const LocalizeError& e : r.errors)
    s.append(format_stamp_us(e.stamp_us))
        .append(",")
        .append(format_number(e.err_m))
        .append(",")
        .append(format_number(e.err_deg))
        .append(e.converged ? ",1\n" : ",0\n");
  return s;
}

void write_localize_picture(const LocalizeRunResult& r, const std::string& path) {
  viz::PictureOptions options;
  options.title = std::filesystem::path(r.log).filename().string() + ": AMCL (start " + localize_start_name(r.initial.kind) + ")";
  viz::MapPicture pic(r.grid, options);
  const Pose2 base_in_laser = r.laser_in_base.inverse();
  std::vector<Vec2> reference;
  for (const LocalizeError& e : r.errors) reference.push_back(e.reference.compose(base_in_laser).translation());
  std::vector<Vec2> before, after;
  for (const LocalizePose& p : r.trajectory)
    (r.converged_at_scan && p.scan >= *r.converged_at_scan ? after : before).push_back(p.pose.translation());
  if (!after.empty() && !before.empty()) before.push_back(after.front());
  if (before.size() > 1)
    pic.add_polyline(std::move(before), {.colour = {120, 120, 120, 255}, .width_px = 0.8, .opacity = 0.6}, "AMCL before convergence");
  if (after.size() > 1) pic.add_polyline(std::move(after), {.colour = {0, 114, 178, 255}, .width_px = 1.2, .opacity = 0.9}, "AMCL");
  // The reference over the estimate: its poses are a sparse sample (the scans with a corrected twin).
  if (!reference.empty())
    pic.add_points(std::move(reference), {.fill = {213, 94, 0, 255}, .radius_px = 1.6, .outline_px = 0.0, .opacity = 0.9},
                   "reference (corrected)");
  if (r.converged_at_scan)
    for (const LocalizePose& p : r.trajectory)
      if (p.scan == *r.converged_at_scan) {
        pic.add_points({p.pose.translation()}, {.fill = {0, 158, 115, 255}, .radius_px = 4.0}, "converged");
        break;
      }
  if (path.size() > 4 && path.substr(path.size() - 4) == ".svg") pic.write_svg(path);
  else pic.write_png(path);
}

const std::vector<std::string>& localize_output_files() {
  static const std::vector<std::string> files = {"trajectory.csv", "errors.csv", "summary.json", "map.png",
                                                 "steps.jsonl",    "world.json", "run.json"};
  return files;
}

void write_localize_outputs(const LocalizeRunResult& r, const std::string& dir) {
  namespace fs = std::filesystem;
  fs::create_directories(dir);
  const fs::path d(dir);
  write_file_bytes((d / "trajectory.csv").string(), localize_trajectory_csv(r));
  write_file_bytes((d / "errors.csv").string(), localize_errors_csv(r));
  write_file_bytes((d / "summary.json").string(), localize_summary_json(r).dump(1) + "\n");
  write_localize_picture(r, (d / "map.png").string());
  if (!r.step_lines.empty()) {
    std::string steps;
    for (const std::string& l : r.step_lines) steps += l + '\n';
    // The map is known: the viewer shows it from the start.
    write_log_run_record(dir, "localization", r.log, "amcl", r.trajectory.front().stamp_us, r.trajectory.back().stamp_us, steps,
                         map_world_json(r.grid, true, r.trajectory.front().pose));
  }
}

}  // namespace starnav
