#include "starnav/logs/carmen_log.hpp"

#include <algorithm>
#include <charconv>
#include <limits>
#include <cmath>
#include <functional>
#include <map>
#include <optional>
#include <tuple>
#include <vector>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/record_format.hpp"
#include "starnav/core/text_lines.hpp"

namespace starnav {

namespace {

// The fields of one line and where it is, for errors.
class Fields {
 public:
  Fields(std::string_view line, const std::string& path, int line_no)
      : tokens_(split_fields(line)), path_(path), line_(line_no) {}
  std::size_t size() const { return tokens_.size(); }
  std::string_view operator[](std::size_t i) const { return tokens_[i]; }
  const std::string& type() const {
    if (type_.empty() && !tokens_.empty()) type_ = printable(tokens_[0], 40);
    return type_;
  }

  [[noreturn]] void fail(const std::string& field, const std::string& what) const {
    throw Error(what, path_, line_, type() + " " + field);
  }
  void need(std::size_t n, const std::string& layout) const {
    if (tokens_.size() < n)
      fail("fields", "expected at least " + std::to_string(n) + " fields (" + layout + "), got " +
                         std::to_string(tokens_.size()));
  }
  double number(std::size_t i, const char* field) const {
    if (i >= tokens_.size()) fail(field, "missing");
    double v = 0.0;
    if (!parse_finite_number(tokens_[i], v)) fail(field, "expected a finite number, got '" + printable(tokens_[i], 40) + "'");
    return v;
  }
  // A position (metres): finite and within kMaxCoordinateM of the origin.
  double coordinate(std::size_t i, const char* field) const {
    const double v = number(i, field);
    if (!plausible_coordinate(v))
      fail(field, format_number(v) + " m lies farther than " + format_number(kMaxCoordinateM) + " m from the origin: not a position");
    return v;
  }
  std::size_t count(std::size_t i, const char* field, std::size_t max) const {
    if (i >= tokens_.size()) fail(field, "missing");
    std::size_t v = 0;
    const std::string_view t = tokens_[i];
    const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
    if (r.ec != std::errc() || r.ptr != t.data() + t.size() || v > max)
      fail(field, "expected a count 0.." + std::to_string(max) + ", got '" + printable(t, 40) + "'");
    return v;
  }
  std::int64_t stamp(std::size_t i, const char* field) const {
    std::int64_t us = 0;
    if (i >= tokens_.size()) fail(field, "missing");
    if (!parse_stamp_us(tokens_[i], us)) fail(field, "expected a timestamp in seconds, got '" + printable(tokens_[i], 40) + "'");
    return us;
  }
  int line() const { return line_; }

 private:
  std::vector<std::string_view> tokens_;
  const std::string& path_;
  int line_;
  mutable std::string type_;
};

constexpr std::size_t kMaxBeams = kMaxScanBeams;

// A scan_fault in the words of CARMEN's fields, at the scan's line.
void check_scan(const LogScan& s, const std::string& path, int line, const std::string& type) {
  const std::optional<ScanFault> fault = scan_fault(s);
  if (!fault) return;
  const std::string& f = fault->field;
  const std::string field = f == "angle_min"         ? "start_angle"
                            : f == "angle_increment" ? "angular_resolution"
                            : f == "range_max"       ? "maximum_range"
                            : f == "ranges"          ? "range"
                                                     : f;
  throw Error(fault->what, path, line, type + " " + field);
}

bool blank_or_comment(std::string_view line) {
  const std::size_t i = line.find_first_not_of(" \t\r");
  return i == std::string_view::npos || line[i] == '#';
}

void read_ranges(const Fields& f, std::size_t first, std::size_t n, LogScan& s) {
  s.ranges_m.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double v = f.number(first + i, "range");
    if (!(std::abs(v) <= std::numeric_limits<float>::max()))
      f.fail("range", format_number(v) + " m is beyond what a reading holds (a float, at most 3.4e38)");
    s.ranges_m[i] = static_cast<float>(v);
  }
}

// Finite readings from which a missing no-return value is worth a warning (above).
constexpr std::size_t kNoReturnEvidenceReadings = 50000;

// The no-return value of logs that do not store it (see the header).
void set_inferred_range_max(RobotLog& log, const std::vector<std::size_t>& scans, const LogReadOptions& o,
                            const std::string& path) {
  std::vector<float> values;
  for (std::size_t i : scans)
    for (float r : log.scans[i].ranges_m)
      if (std::isfinite(r)) values.push_back(r);
  std::sort(values.begin(), values.end(), std::greater<>());
  const std::size_t repeats = std::max<std::size_t>(10, (values.size() + 999) / 1000);
  // From the top, the first value that repeats that often; the readings above it are strays.
  std::optional<float> saturated;
  std::size_t saturated_count = 0, above_saturated = 0;
  for (std::size_t at = 0; at < values.size() && !saturated;) {
    std::size_t end = at;
    while (end < values.size() && values[end] == values[at]) ++end;
    if (end - at >= repeats) saturated = values[at], saturated_count = end - at, above_saturated = at;
    at = end;
  }
  double range_max = std::nextafter(values.empty() ? 0.0 : static_cast<double>(values.front()), kInfinity);
  if (saturated) range_max = *saturated;
  if (o.range_max_m) {
    range_max = *o.range_max_m;
  } else if (o.warn && !values.empty()) {
    // Without a repeated top value every reading counts as a return; worth a word only in a log
    // long enough that a sensor's no-return readings would have shown (a few hundred scans), not
    // in a short hand-made one.
    if (!saturated && values.size() >= kNoReturnEvidenceReadings)
      o.warn(path + ": no reading repeats at the top as a sensor's no-return value does: every reading counts as a return "
                    "(--range-max says which readings returned nothing)");
    else if (above_saturated > 0)
      o.warn(path + ": " + std::to_string(above_saturated) + " readings lie above the no-return value " + format_number(*saturated) +
             " m (repeated " + std::to_string(saturated_count) + " times; the largest is " + format_number(values.front()) +
             " m): they count as no return too (--range-max overrides)");
  }
  for (std::size_t i : scans) log.scans[i].range_max_m = range_max;
  log.params["range_max_m"] = std::to_string(range_max) + (o.range_max_m ? " (given)" : " (inferred)");
}

LogScan raw_laser(const Fields& f, bool robot_laser) {
  // type start_angle fov resolution max_range accuracy remission_mode n ...
  f.need(9, "type start_angle fov resolution max_range accuracy remission_mode n ranges...");
  LogScan s;
  s.angle_min_rad = f.number(2, "start_angle");
  s.angle_increment_rad = f.number(4, "angular_resolution");
  s.range_max_m = f.number(5, "maximum_range");
  if (!(s.range_max_m > 0)) f.fail("maximum_range", "must be > 0");
  const std::size_t n = f.count(8, "num_readings", kMaxBeams);
  read_ranges(f, 9, n, s);
  const std::size_t m = f.count(9 + n, "num_remissions", kMaxBeams);
  std::size_t at = 10 + n + m;
  if (robot_laser) {
    f.need(at + 11 + 1, "... remissions laser_x laser_y laser_theta x y theta tv rv forward side turn_axis ipc_timestamp");
    s.laser_pose = Pose2(f.coordinate(at, "laser_x"), f.coordinate(at + 1, "laser_y"), wrap_angle(f.number(at + 2, "laser_theta")));
    s.odometry = Pose2(f.coordinate(at + 3, "x"), f.coordinate(at + 4, "y"), wrap_angle(f.number(at + 5, "theta")));
    at += 11;
  }
  s.stamp_us = f.stamp(at, "ipc_timestamp");
  return s;
}

// The memory a text log's records take, bounded as every log's (LogRecordBudget): the records
// are counted from the lines' first words before any is stored (and a log that must hold scans
// but has none is refused there, before its odometry is stored); the readings are charged as each
// scan is read.
class RecordBudget {
 public:
  RecordBudget(std::string_view text, const std::string& path, bool odomscan, const LogReadOptions& o)
      : budget_(path, text.size(), o.record_limit_bytes) {
    for_each_line(text, [&](std::string_view line, int) {
      const std::size_t b = line.find_first_not_of(" \t");
      if (b == std::string_view::npos) return;
      line.remove_prefix(b);
      const std::string_view type = line.substr(0, line.find_first_of(" \t"));
      if (odomscan ? type == "LASERSCAN" : (type == "FLASER" || type == "ROBOTLASER1" ||
                                           (type.size() == 9 && type.substr(0, 8) == "RAWLASER" && type[8] >= '1' && type[8] <= '4')))
        ++scans;
      else if (type == (odomscan ? "ODOMETRY" : "ODOM"))
        ++odometry;
      else if (!odomscan && type == "TRUEPOS")
        ++truth;
    });
    // A text with no record line at all is not a log: read_robot_log says so.
    if (!o.allow_no_scans && scans == 0 && odometry + truth > 0)
      throw Error(odomscan ? "holds no LASERSCAN line: nothing to map or localize with"
                           : "holds no laser scan line (FLASER, ROBOTLASER1, RAWLASER1..4): nothing to map or localize with",
                  path);
    charge(scans * sizeof(LogScan) + odometry * sizeof(LogOdometry) + truth * sizeof(LogTruePose), 0);
  }
  // Adds `bytes`; refuses the log when the records pass the bound.
  void charge(std::size_t bytes, int line) {
    budget_.charge(bytes, [&] {
      return std::to_string(scans) + " scan, " + std::to_string(odometry) + " odometry and " + std::to_string(truth) + " ground-truth lines";
    }, line);
  }
  void reserve(RobotLog& log) const {
    log.scans.reserve(scans);
    log.odometry.reserve(odometry);
    log.truth.reserve(truth);
  }
  std::size_t scans = 0, odometry = 0, truth = 0;

 private:
  LogRecordBudget budget_;
};

}  // namespace

void set_flaser_beam_angles(LogScan& s, std::size_t n) {
  s.angle_min_rad = -kPi / 2;
  if (n == 180) s.angle_increment_rad = deg_to_rad(1.0);
  else if (n == 360) s.angle_increment_rad = deg_to_rad(0.5);
  else s.angle_increment_rad = n > 1 ? kPi / static_cast<double>(n - 1) : 0.0;
}

RobotLog read_carmen_log(std::string_view text, const std::string& path, const LogReadOptions& o) {
  RobotLog log;
  log.path = path;
  log.format = "carmen";
  RecordBudget budget(text, path, false, o);
  budget.reserve(log);
  std::vector<std::size_t> flaser;
  for_each_line(text, [&](std::string_view line, int line_no) {
    if (blank_or_comment(line)) return;
    const Fields f(line, path, line_no);
    const std::string& type = f.type();
    if (type == "FLASER") {
      f.need(2, "n ranges... x y theta odom_x odom_y odom_theta ipc_timestamp");
      const std::size_t n = f.count(1, "num_readings", kMaxBeams);
      budget.charge(n * sizeof(float), line_no);
      f.need(2 + n + 7, "n ranges... x y theta odom_x odom_y odom_theta ipc_timestamp");
      LogScan s;
      set_flaser_beam_angles(s, n);
      read_ranges(f, 2, n, s);
      s.laser_pose = Pose2(f.coordinate(2 + n, "x"), f.coordinate(2 + n + 1, "y"), wrap_angle(f.number(2 + n + 2, "theta")));
      s.odometry = Pose2(f.coordinate(2 + n + 3, "odom_x"), f.coordinate(2 + n + 4, "odom_y"),
                         wrap_angle(f.number(2 + n + 5, "odom_theta")));
      s.stamp_us = f.stamp(2 + n + 6, "ipc_timestamp");
      s.source_index = static_cast<std::size_t>(line_no);
      flaser.push_back(log.scans.size());
      log.scans.push_back(std::move(s));
    } else if (type == "ROBOTLASER1" || type.rfind("RAWLASER", 0) == 0) {
      if (type.rfind("RAWLASER", 0) == 0 && !(type.size() == 9 && type[8] >= '1' && type[8] <= '4')) {
        ++log.skipped[type];
        return;
      }
      if (f.size() > 8) budget.charge(f.count(8, "num_readings", kMaxBeams) * sizeof(float), line_no);
      LogScan s = raw_laser(f, type == "ROBOTLASER1");
      if (o.range_max_m) s.range_max_m = *o.range_max_m;
      s.source_index = static_cast<std::size_t>(line_no);
      check_scan(s, path, line_no, type);
      log.scans.push_back(std::move(s));
    } else if (type == "ODOM") {
      f.need(8, "x y theta tv rv accel ipc_timestamp");
      LogOdometry od;
      od.pose = Pose2(f.coordinate(1, "x"), f.coordinate(2, "y"), wrap_angle(f.number(3, "theta")));
      od.tv_mps = f.number(4, "tv");
      od.rv_radps = f.number(5, "rv");
      od.stamp_us = f.stamp(7, "ipc_timestamp");
      od.source_index = static_cast<std::size_t>(line_no);
      log.odometry.push_back(od);
    } else if (type == "TRUEPOS") {
      f.need(8, "x y theta odom_x odom_y odom_theta ipc_timestamp");
      LogTruePose tp;
      tp.pose = Pose2(f.coordinate(1, "true_x"), f.coordinate(2, "true_y"), wrap_angle(f.number(3, "true_theta")));
      tp.odometry = Pose2(f.coordinate(4, "odom_x"), f.coordinate(5, "odom_y"), wrap_angle(f.number(6, "odom_theta")));
      tp.stamp_us = f.stamp(7, "ipc_timestamp");
      log.truth.push_back(tp);
    } else if (type == "PARAM") {
      f.need(3, "name value");
      const std::string name = printable(f[1], std::size_t{200});
      log.params[name] = printable(f[2], std::size_t{200});
      if (name == "robot_frontlaser_offset") log.laser_in_base = Pose2(f.coordinate(2, "robot_frontlaser_offset"), 0.0, 0.0);
    } else {
      ++log.skipped[type];
    }
  });
  if (!flaser.empty()) set_inferred_range_max(log, flaser, o, path);
  for (std::size_t i : flaser) check_scan(log.scans[i], path, static_cast<int>(log.scans[i].source_index), "FLASER");
  return log;
}

RobotLog read_odomscan_text(std::string_view text, const std::string& path, const LogReadOptions& o) {
  RobotLog log;
  log.path = path;
  log.format = "odomscan_text";
  RecordBudget budget(text, path, true, o);
  budget.reserve(log);
  std::vector<std::size_t> scans;
  for_each_line(text, [&](std::string_view line, int line_no) {
    if (blank_or_comment(line)) return;
    const Fields f(line, path, line_no);
    if (f.type() == "LASERSCAN") {
      f.need(3, "ipc_timestamp n ranges...");
      const std::size_t n = f.count(2, "n", kMaxBeams);
      budget.charge(n * sizeof(float), line_no);
      if (f.size() != 3 + n) f.fail("ranges", "expected " + std::to_string(n) + " ranges, got " + std::to_string(f.size() - 3));
      LogScan s;
      set_flaser_beam_angles(s, n);
      s.stamp_us = f.stamp(1, "ipc_timestamp");
      read_ranges(f, 3, n, s);
      s.source_index = static_cast<std::size_t>(line_no);
      scans.push_back(log.scans.size());
      log.scans.push_back(std::move(s));
    } else if (f.type() == "ODOMETRY") {
      if (f.size() != 7) f.fail("fields", "expected ODOMETRY ipc_timestamp x y theta tv rv, got " + std::to_string(f.size()) + " fields");
      LogOdometry od;
      od.stamp_us = f.stamp(1, "ipc_timestamp");
      od.pose = Pose2(f.coordinate(2, "x"), f.coordinate(3, "y"), wrap_angle(f.number(4, "theta")));
      od.tv_mps = f.number(5, "tv");
      od.rv_radps = f.number(6, "rv");
      od.source_index = static_cast<std::size_t>(line_no);
      log.odometry.push_back(od);
    } else {
      ++log.skipped[f.type()];
    }
  });
  if (!scans.empty()) set_inferred_range_max(log, scans, o, path);
  for (std::size_t i : scans) check_scan(log.scans[i], path, static_cast<int>(log.scans[i].source_index), "LASERSCAN");
  return log;
}

bool looks_like_odomscan_text(std::string_view text) {
  bool result = false, decided = false;
  for_each_line(text.substr(0, 1 << 20), [&](std::string_view line, int) {
    if (decided || blank_or_comment(line)) return;
    decided = true;
    const std::size_t i = line.find_first_not_of(" \t");
    result = line.substr(i).rfind("ODOMETRY ", 0) == 0 || line.substr(i).rfind("LASERSCAN ", 0) == 0;
  });
  return result;
}

std::string carmen_log_text(const RobotLog& log, const std::string& host) {
  const Pose2 mount = log.laser_in_base.value_or(Pose2());
  const std::vector<std::optional<Pose2>> odometry = scan_odometry(log);
  // (stamp, kind, index): kind 0 odometry, 1 truth, 2 scan, so that at one stamp the odometry comes first.
  std::vector<std::tuple<std::int64_t, int, std::size_t>> order;
  for (std::size_t i = 0; i < log.odometry.size(); ++i) order.emplace_back(log.odometry[i].stamp_us, 0, i);
  for (std::size_t i = 0; i < log.truth.size(); ++i) order.emplace_back(log.truth[i].stamp_us, 1, i);
  for (std::size_t i = 0; i < log.scans.size(); ++i) order.emplace_back(log.scans[i].stamp_us, 2, i);
  std::stable_sort(order.begin(), order.end(), [](const auto& a, const auto& b) {
    return std::get<0>(a) != std::get<0>(b) ? std::get<0>(a) < std::get<0>(b) : std::get<1>(a) < std::get<1>(b);
  });
  // Appends, field by field (string concatenation chains trip GCC 12's -Wrestrict).
  std::string out = "# CARMEN log written by starnav\n# ODOM x y theta tv rv accel; TRUEPOS true_x true_y true_theta odom_x odom_y odom_theta\n";
  const auto field = [&out](const std::string& v) {
    out += ' ';
    out += v;
  };
  const auto pose = [&](const Pose2& p) {
    field(format_fixed(p.x, 6));
    field(format_fixed(p.y, 6));
    field(format_fixed(p.yaw, 6));
  };
  const auto end_line = [&](std::int64_t stamp) {
    field(format_stamp_us(stamp));
    field(host);
    field(format_stamp_us(stamp));
    out += '\n';
  };
  if (log.laser_in_base) {
    out += "PARAM robot_frontlaser_offset";
    field(format_fixed(mount.x, 6));
    field(host);
    field("0.000000");
    out += '\n';
  }
  for (const auto& [stamp, kind, i] : order) {
    if (kind == 0) {
      const LogOdometry& o = log.odometry[i];
      out += "ODOM";
      pose(o.pose);
      field(format_fixed(o.tv_mps, 6));
      field(format_fixed(o.rv_radps, 6));
      field("0.000000");
      end_line(stamp);
    } else if (kind == 1) {
      out += "TRUEPOS";
      pose(log.truth[i].pose);
      pose(log.truth[i].odometry);
      end_line(stamp);
    } else {
      const LogScan& s = log.scans[i];
      if (!odometry[i]) continue;  // no pose to write beside it
      const std::size_t n = s.ranges_m.size();
      LogScan layout;
      set_flaser_beam_angles(layout, n);
      const bool flaser = std::abs(layout.angle_min_rad - s.angle_min_rad) < 1e-9 && std::abs(layout.angle_increment_rad - s.angle_increment_rad) < 1e-9;
      if (flaser) {
        out += "FLASER";
        field(std::to_string(n));
      } else {
        out += "ROBOTLASER1 0";
        // The field of view from the increment as written, so that writing again keeps the bytes.
        const std::string increment = format_fixed(s.angle_increment_rad, 12);
        field(format_fixed(s.angle_min_rad, 12));
        field(format_fixed(std::stod(increment) * static_cast<double>(n > 0 ? n - 1 : 0), 12));
        field(increment);
        field(format_fixed(s.range_max_m, 3));
        field("0.010 0");
        field(std::to_string(n));
      }
      for (std::size_t b = 0; b < n; ++b) field(format_fixed(s.returned(b) ? static_cast<double>(s.ranges_m[b]) : s.range_max_m, 3));
      if (!flaser) field("0");  // no remissions
      pose(s.laser_pose ? *s.laser_pose : odometry[i]->compose(mount));
      pose(*odometry[i]);
      if (!flaser) field("0.000000 0.000000 0.000000 0.000000 0.000000");
      end_line(stamp);
    }
  }
  return out;
}

}  // namespace starnav
