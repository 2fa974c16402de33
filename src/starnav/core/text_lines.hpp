#pragma once
// Line-oriented text files (logs, relation files, trajectories): their lines, a line's
// whitespace-separated fields, and strict numbers.
#include <charconv>
#include <cmath>
#include <string_view>
#include <system_error>
#include <vector>

namespace starnav {

// `visit(line, line_number)` for each line, numbered from 1, without its '\n' and without a
// trailing '\r' (files written on Windows read the same).
template <class Visit>
void for_each_line(std::string_view text, Visit&& visit) {
  std::size_t begin = 0;
  int line_no = 0;
  while (begin < text.size()) {
    std::size_t end = text.find('\n', begin);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(begin, end - begin);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    visit(line, ++line_no);
    begin = end + 1;
  }
}

// The fields of `line` separated by spaces, tabs or carriage returns (views into `line`).
inline std::vector<std::string_view> split_fields(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
    const std::size_t begin = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') ++i;
    if (i > begin) out.push_back(line.substr(begin, i - begin));
  }
  return out;
}

// The whole of `text` as one finite decimal number (no sign '+', no spaces, no inf or nan).
inline bool parse_finite_number(std::string_view text, double& value) {
  const auto r = std::from_chars(text.data(), text.data() + text.size(), value);
  return r.ec == std::errc() && r.ptr == text.data() + text.size() && std::isfinite(value);
}

}  // namespace starnav
