#pragma once
// Number and field formats of the deterministic records (CSV, JSON) the simulator and the
// navigation stack write: fixed decimals, so the same run gives the same bytes.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <sstream>
#include <string>

namespace starnav {

// Six decimals; "-0.000000" prints as "0.000000" (the same bytes whichever side of zero rounding fell).
inline std::string format_fixed6(double v) {
  char buf[64];
  const int n = std::snprintf(buf, sizeof buf, "%.6f", v);
  std::string s(buf, static_cast<std::size_t>(n));
  if (s == "-0.000000") s = "0.000000";
  return s;
}

// A number with a fixed count of decimals for tables; "-" for NaN, "inf" / "-inf" for infinities.
inline std::string format_fixed(double v, int precision) {
  if (!std::isfinite(v)) return std::isnan(v) ? "-" : (v > 0 ? "inf" : "-inf");
  char buf[512];
  const int n = std::snprintf(buf, sizeof buf, "%.*f", precision, v);
  return n > 0 && static_cast<std::size_t>(n) < sizeof buf ? std::string(buf, static_cast<std::size_t>(n)) : std::string("-");
}

// A coordinate in metres for JSON: rounded to the nanometre, so a cell centre computed as
// (x + 0.5) * resolution prints as 0.85, not 0.8500000000000001 (exact below 9e6 m).
inline double json_coordinate(double v) { return std::isfinite(v) ? std::round(v * 1e9) / 1e9 : v; }

// A number for people to read (titles, one-line summaries): four significant digits, no exponent,
// trailing zeros dropped ("13.57", "0.004805", "31186", "0.5"); "-" for NaN, "inf" / "-inf".
inline std::string format_readable(double v, int significant = 4) {
  if (!std::isfinite(v)) return std::isnan(v) ? "-" : (v > 0 ? "inf" : "-inf");
  if (v == 0.0) return "0";
  const int magnitude = static_cast<int>(std::floor(std::log10(std::fabs(v))));
  const int decimals = std::max(0, significant - 1 - magnitude);
  std::string s = format_fixed(v, std::min(decimals, 20));
  if (s.find('.') != std::string::npos) {
    s.erase(s.find_last_not_of('0') + 1);
    if (s.back() == '.') s.pop_back();
  }
  return s == "-0" ? "0" : s;
}

// Up to 10 significant digits, shortest form ("0.5", "12.25", "inf"): numbers in one-line summaries.
inline std::string format_number(double v) {
  std::ostringstream s;
  s << std::setprecision(10) << v;
  return s.str();
}

// A CSV field, quoted when it holds a comma, a quote or a line break (line breaks become spaces).
inline std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string q = "\"";
  for (const char c : s) {
    if (c == '"') q += "\"\"";
    else if (c == '\n' || c == '\r') q += ' ';
    else q += c;
  }
  return q + "\"";
}

// -0.0 prints as "-0.0" in JSON; the same quantity should read the same whichever side it came from.
inline double unsigned_zero(double v) { return v == 0.0 ? 0.0 : v; }

// Rounded to the millimetre (poses, paths) or the centimetre (LiDAR hits, particles), the
// precision of the run records a viewer reads (docs/run-records.md).
inline double round_mm(double v) { return unsigned_zero(std::round(v * 1000.0) / 1000.0); }
inline double round_cm(double v) { return unsigned_zero(std::round(v * 100.0) / 100.0); }

}  // namespace starnav
