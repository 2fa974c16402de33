#include "starnav/logs/robot_log.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include <nlohmann/json.hpp>
#include <sstream>

#include "starnav/core/angle.hpp"
#include "starnav/core/record_format.hpp"

namespace starnav {

LogRecordBudget::LogRecordBudget(std::string path, std::uint64_t source_bytes, std::optional<std::size_t> limit)
    : path_(std::move(path)), source_(source_bytes), limit_(limit) {}

void LogRecordBudget::add_source(std::uint64_t bytes) { source_ += bytes; }

std::uint64_t LogRecordBudget::limit() const {
  if (limit_) return *limit_;
  return std::min<std::uint64_t>(source_, kMaxLogFileBytes) + kLogRecordSlackBytes;
}

void LogRecordBudget::check(std::uint64_t bytes, const std::function<std::string()>& what, int line) const {
  if (bytes <= limit() && used_ <= limit() - bytes) return;
  const std::string rule = limit_ ? std::string("the limit given")
                                  : "the log's size" + std::string(source_ > kMaxLogFileBytes ? " (at most " + std::to_string(kMaxLogFileBytes) + ")" : "") +
                                        " plus " + std::to_string(kLogRecordSlackBytes >> 20) + " MiB, the most a log's records may take";
  throw Error("its " + what() + " would take more than " + std::to_string(limit()) + " bytes parsed (" + rule + ")", path_, line);
}

void LogRecordBudget::charge(std::uint64_t bytes, const std::function<std::string()>& what, int line) {
  check(bytes, what, line);
  used_ += bytes;
}

std::vector<Vec2> LogScan::end_points(const Pose2& sensor, std::size_t max) const {
  std::vector<Vec2> out;
  if (max == 0) return out;
  const std::size_t every = std::max<std::size_t>(1, (ranges_m.size() + max - 1) / max);
  for (std::size_t i = 0; i < ranges_m.size(); i += every) {
    const double d = ranges_m[i];
    if (!returned(i) || !(d > 0.0)) continue;
    const double a = sensor.yaw + angle(i);
    out.push_back(sensor.translation() + d * Vec2(std::cos(a), std::sin(a)));
  }
  return out;
}

bool parse_stamp_us(std::string_view text, std::int64_t& us) {
  // Decimal arithmetic, never through a double: mantissa digits (at most 18 kept, the first
  // dropped one rounds), a decimal exponent (CARMEN's %g writes "4.29497e+09", "1.08499e-42").
  std::size_t i = 0;
  bool negative = false;
  if (i < text.size() && (text[i] == '-' || text[i] == '+')) negative = text[i++] == '-';
  std::int64_t mantissa = 0;
  int kept = 0, scale = 0;  // value = mantissa * 10^(scale)
  bool any_digit = false, round_up = false, dropped = false;
  auto digit = [&](int d, bool fraction) {
    any_digit = true;
    if (kept < 18 && !(kept == 0 && d == 0)) {
      mantissa = mantissa * 10 + d;
      ++kept;
      if (fraction) --scale;
    } else if (kept >= 18) {
      if (!dropped) round_up = d >= 5, dropped = true;
      if (!fraction) ++scale;
    } else if (fraction) {
      --scale;  // a leading zero after the point
    }
  };
  while (i < text.size() && text[i] >= '0' && text[i] <= '9') digit(text[i++] - '0', false);
  if (i < text.size() && text[i] == '.') {
    ++i;
    while (i < text.size() && text[i] >= '0' && text[i] <= '9') digit(text[i++] - '0', true);
  }
  if (!any_digit) return false;
  if (i < text.size() && (text[i] == 'e' || text[i] == 'E')) {
    ++i;
    bool exp_negative = false;
    if (i < text.size() && (text[i] == '-' || text[i] == '+')) exp_negative = text[i++] == '-';
    int e = 0;
    bool exp_digit = false;
    while (i < text.size() && text[i] >= '0' && text[i] <= '9') {
      exp_digit = true;
      if (e < 100000) e = e * 10 + (text[i] - '0');
      ++i;
    }
    if (!exp_digit) return false;
    scale += exp_negative ? -e : e;
  }
  if (i != text.size()) return false;
  if (round_up) ++mantissa;
  // To microseconds: times 10^(scale + 6).
  int shift = scale + 6;
  std::int64_t v = mantissa;
  if (shift >= 0) {
    for (; shift > 0; --shift) {
      if (v > std::numeric_limits<std::int64_t>::max() / 10) return false;
      v *= 10;
    }
  } else {
    bool half = false;
    for (; shift < 0 && v > 0; ++shift) {
      half = v % 10 >= 5;
      v /= 10;
    }
    if (shift == 0 && half) ++v;  // half away from zero on the last digit dropped
  }
  us = negative ? -v : v;
  return true;
}

std::string format_stamp_us(std::int64_t us) {
  const bool negative = us < 0;
  const std::uint64_t a = negative ? 0 - static_cast<std::uint64_t>(us) : static_cast<std::uint64_t>(us);
  char buffer[40];
  std::snprintf(buffer, sizeof buffer, "%s%llu.%06llu", negative ? "-" : "", static_cast<unsigned long long>(a / 1'000'000),
                static_cast<unsigned long long>(a % 1'000'000));
  return buffer;
}

std::optional<ScanFault> scan_fault(const LogScan& s) {
  const std::size_t n = s.ranges_m.size();
  if (n > kMaxScanBeams)
    return ScanFault{"ranges", std::to_string(n) + " readings, more than the " + std::to_string(kMaxScanBeams) + " a scan may have"};
  if (!std::isfinite(s.angle_min_rad)) return ScanFault{"angle_min", "not a finite angle"};
  if (!std::isfinite(s.angle_increment_rad)) return ScanFault{"angle_increment", "not a finite angle"};
  if (n > 1 && s.angle_increment_rad == 0.0)
    return ScanFault{"angle_increment", "is 0 with " + std::to_string(n) + " beams: they would all point one way"};
  // One increment of slack: a full turn of n beams spans n - 1 increments, some drivers count n.
  const double span = std::abs(s.angle_increment_rad) * static_cast<double>(n > 0 ? n - 1 : 0);
  if (span > 2.0 * kPi + std::abs(s.angle_increment_rad) + 1e-6)
    return ScanFault{"angle_increment", std::to_string(n) + " beams " + format_number(s.angle_increment_rad) + " rad apart span " +
                                            format_number(span) + " rad, more than a turn"};
  if (!(std::isfinite(s.range_min_m) && s.range_min_m >= 0.0))
    return ScanFault{"range_min", format_number(s.range_min_m) + " m is not a distance"};
  if (!(s.range_max_m > s.range_min_m))
    return ScanFault{"range_max", format_number(s.range_max_m) + " m is not above range_min " + format_number(s.range_min_m) +
                                      " m: no reading could return"};
  for (std::size_t i = 0; i < n; ++i)
    if (std::isfinite(s.ranges_m[i]) && s.ranges_m[i] < 0.0f)
      return ScanFault{"ranges", "reading " + std::to_string(i) + " is " + format_number(s.ranges_m[i]) + " m: a range is never negative"};
  return std::nullopt;
}

Error error_at_scan(const RobotLog& log, const LogScan& scan, const Error& e) {
  if (!e.file().empty()) return e;
  const bool text = log.format == "carmen" || log.format == "odomscan_text";
  return Error(e.message() + (text ? "" : " (message " + std::to_string(scan.source_index) + ")"), log.path,
               text ? static_cast<int>(scan.source_index) : 0, e.field());
}

std::vector<LogOdometry> sort_by_time(std::vector<LogOdometry> odometry) {
  std::stable_sort(odometry.begin(), odometry.end(),
                   [](const LogOdometry& a, const LogOdometry& b) { return a.stamp_us < b.stamp_us; });
  return odometry;
}

std::optional<Pose2> odometry_at(const std::vector<LogOdometry>& sorted, std::int64_t stamp_us) {
  if (sorted.empty()) return std::nullopt;
  const auto after = std::lower_bound(sorted.begin(), sorted.end(), stamp_us,
                                      [](const LogOdometry& o, std::int64_t t) { return o.stamp_us < t; });
  if (after == sorted.begin()) return after->pose;
  if (after == sorted.end()) return sorted.back().pose;
  if (after->stamp_us == stamp_us) return after->pose;
  const LogOdometry& a = *(after - 1);
  const LogOdometry& b = *after;
  const double f = static_cast<double>(stamp_us - a.stamp_us) / static_cast<double>(b.stamp_us - a.stamp_us);
  return Pose2(a.pose.x + f * (b.pose.x - a.pose.x), a.pose.y + f * (b.pose.y - a.pose.y),
               wrap_angle(a.pose.yaw + f * wrap_angle(b.pose.yaw - a.pose.yaw)));
}

std::vector<std::optional<Pose2>> scan_odometry(const RobotLog& log) {
  std::vector<std::optional<Pose2>> out(log.scans.size());
  const auto in_order = [](const auto& items) {
    for (std::size_t i = 1; i < items.size(); ++i)
      if (items[i].stamp_us < items[i - 1].stamp_us) return false;
    return true;
  };
  bool indexed = true;
  for (const LogOdometry& o : log.odometry) indexed = indexed && o.source_index > 0;
  for (const LogScan& s : log.scans) indexed = indexed && s.source_index > 0;
  const bool by_time = (in_order(log.scans) && in_order(log.odometry)) || !indexed;
  const std::vector<LogOdometry> sorted = by_time ? sort_by_time(log.odometry) : std::vector<LogOdometry>{};
  // File order: readings by source index.
  std::vector<LogOdometry> filed = by_time ? std::vector<LogOdometry>{} : log.odometry;
  std::stable_sort(filed.begin(), filed.end(), [](const LogOdometry& a, const LogOdometry& b) { return a.source_index < b.source_index; });
  for (std::size_t k = 0; k < log.scans.size(); ++k) {
    const LogScan& scan = log.scans[k];
    if (scan.odometry) {
      out[k] = scan.odometry;
    } else if (by_time) {
      out[k] = odometry_at(sorted, scan.stamp_us);
    } else if (!filed.empty()) {
      const auto after = std::lower_bound(filed.begin(), filed.end(), scan.source_index,
                                          [](const LogOdometry& o, std::size_t i) { return o.source_index < i; });
      out[k] = (after == filed.begin() ? *after : *(after - 1)).pose;
    }
  }
  return out;
}

void for_each_scan_with_odometry(const RobotLog& log, const std::function<void(const LogScan&, const Pose2&)>& fn,
                                 const std::function<void(std::size_t, std::size_t)>& progress) {
  const std::vector<std::optional<Pose2>> odometry = scan_odometry(log);
  for (std::size_t k = 0; k < log.scans.size(); ++k) {
    if (progress && k % 100 == 0) progress(k, log.scans.size());
    if (odometry[k]) fn(log.scans[k], *odometry[k]);
  }
  if (progress) progress(log.scans.size(), log.scans.size());
}

RobotLogSummary summarise_log(const RobotLog& log) {
  RobotLogSummary s;
  s.scans = log.scans.size();
  s.odometry = log.odometry.size();
  s.truth = log.truth.size();
  s.imu = log.imu.size();
  bool any = false;
  auto span = [&](std::int64_t t) {
    s.first_us = any ? std::min(s.first_us, t) : t;
    s.last_us = any ? std::max(s.last_us, t) : t;
    any = true;
  };
  s.scan_odometry_in_line = !log.scans.empty();
  for (std::size_t i = 0; i < log.scans.size(); ++i) {
    const LogScan& scan = log.scans[i];
    span(scan.stamp_us);
    if (i > 0 && scan.stamp_us < log.scans[i - 1].stamp_us) ++s.scans_out_of_order;
    const std::size_t n = scan.ranges_m.size();
    s.beams_min = i == 0 ? n : std::min(s.beams_min, n);
    s.beams_max = std::max(s.beams_max, n);
    s.readings += n;
    for (std::size_t b = 0; b < n; ++b) s.no_return += scan.ranges_m[b] >= scan.range_max_m;
    s.scan_odometry_in_line = s.scan_odometry_in_line && scan.odometry.has_value();
  }
  if (!log.scans.empty()) s.range_max_m = log.scans.front().range_max_m;
  for (std::size_t i = 0; i < log.odometry.size(); ++i) {
    span(log.odometry[i].stamp_us);
    if (i > 0 && log.odometry[i].stamp_us < log.odometry[i - 1].stamp_us) ++s.odometry_out_of_order;
  }
  return s;
}

namespace {

std::string pose_text(const Pose2& p) {
  return "(" + format_fixed(p.x, 3) + ", " + format_fixed(p.y, 3) + ", " + format_fixed(rad_to_deg(p.yaw), 2) + " deg)";
}

}  // namespace

std::string log_info_text(const RobotLog& log) {
  const RobotLogSummary s = summarise_log(log);
  std::ostringstream out;
  out << "file:       " << log.path << "\n";
  out << "format:     " << log.format << "\n";
  out << "scans:      " << s.scans;
  if (s.scans > 0) {
    const LogScan& first = log.scans.front();
    out << " of " << s.beams_min;
    if (s.beams_max != s.beams_min) out << ".." << s.beams_max;
    out << " beams from " << format_fixed(rad_to_deg(first.angle_min_rad), 2) << " deg every "
        << format_fixed(rad_to_deg(first.angle_increment_rad), 4) << " deg; no return at or beyond "
        << format_fixed(s.range_max_m, 3) << " m (" << s.no_return << " of " << s.readings << " readings)";
  }
  out << "\n";
  if (s.scans_out_of_order > 0) out << "            " << s.scans_out_of_order << " scan stamps earlier than the one before\n";
  out << "odometry:   " << s.odometry << (s.scan_odometry_in_line ? " readings; every scan carries its odometry pose" : " readings")
      << "\n";
  if (s.odometry_out_of_order > 0)
    out << "            " << s.odometry_out_of_order << " odometry stamps earlier than the one before\n";
  if (s.truth > 0) out << "truth:      " << s.truth << " poses\n";
  if (s.imu > 0) out << "imu:        " << s.imu << " readings\n";
  if (s.scans + s.odometry > 0)
    out << "time:       " << format_stamp_us(s.first_us) << " .. " << format_stamp_us(s.last_us) << " s ("
        << format_fixed(static_cast<double>(s.last_us - s.first_us) * 1e-6, 3) << " s)\n";
  out << "laser pose: " << (log.laser_in_base ? pose_text(*log.laser_in_base) + " on the base" : std::string("not in the log"))
      << "\n";
  for (const auto& [k, v] : log.params)
    if (k == "scan_topic" || k == "odom_topic" || k == "imu_topic" || k == "truth_topic" || k == "range_max_m" || k == "laser_frame")
      out << k << ": " << v << "\n";
  for (const auto& [k, n] : log.skipped) out << "skipped:    " << n << " x " << k << "\n";
  if (!log.topics.empty()) {
    out << "topics:\n";
    for (const LogTopic& t : log.topics)
      out << "  " << t.name << "  " << t.type << "  " << t.messages << " message" << (t.messages == 1 ? "" : "s")
          << (t.use.empty() ? "" : " (read as " + t.use + ")") << "\n";
  }
  for (const std::string& w : log.warnings) out << "warning:    " << w << "\n";
  return out.str();
}

std::string log_info_json(const RobotLog& log) {
  const RobotLogSummary s = summarise_log(log);
  nlohmann::ordered_json j;
  j["file"] = log.path;
  j["format"] = log.format;
  j["scans"] = s.scans;
  j["beams_min"] = s.beams_min;
  j["beams_max"] = s.beams_max;
  j["angle_min_rad"] = log.scans.empty() ? 0.0 : log.scans.front().angle_min_rad;
  j["angle_increment_rad"] = log.scans.empty() ? 0.0 : log.scans.front().angle_increment_rad;
  j["range_max_m"] = s.range_max_m;
  j["readings"] = s.readings;
  j["no_return"] = s.no_return;
  j["scans_out_of_order"] = s.scans_out_of_order;
  j["odometry"] = s.odometry;
  j["odometry_out_of_order"] = s.odometry_out_of_order;
  j["scan_odometry_in_line"] = s.scan_odometry_in_line;
  j["truth"] = s.truth;
  j["imu"] = s.imu;
  j["first_stamp"] = format_stamp_us(s.first_us);
  j["last_stamp"] = format_stamp_us(s.last_us);
  j["duration_s"] = static_cast<double>(s.last_us - s.first_us) * 1e-6;
  if (log.laser_in_base)
    j["laser_in_base"] = {{"x_m", log.laser_in_base->x}, {"y_m", log.laser_in_base->y}, {"yaw_rad", log.laser_in_base->yaw}};
  else
    j["laser_in_base"] = nullptr;
  nlohmann::ordered_json params = nlohmann::ordered_json::object();
  for (const auto& [k, v] : log.params) params[k] = v;
  j["params"] = params;
  nlohmann::ordered_json skipped = nlohmann::ordered_json::object();
  for (const auto& [k, n] : log.skipped) skipped[k] = n;
  j["skipped"] = skipped;
  nlohmann::ordered_json topics = nlohmann::ordered_json::array();
  for (const LogTopic& t : log.topics) topics.push_back({{"name", t.name}, {"type", t.type}, {"messages", t.messages}, {"use", t.use}});
  j["topics"] = topics;
  j["warnings"] = log.warnings;
  // Names from a log may hold invalid UTF-8: replaced, not thrown on.
  return j.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n";
}

}  // namespace starnav
