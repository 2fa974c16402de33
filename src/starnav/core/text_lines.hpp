#pragma once
// Line-oriented text files (logs, relation files, trajectories): their lines, a line's
// whitespace-separated fields, and strict numbers.
#include <charconv>
#include <cmath>
#include <optional>
#include <string_view>
#include <system_error>
#include <vector>

#include "starnav/core/number_text.hpp"

namespace starnav {

// `text` without a leading UTF-8 byte-order mark: every text format reads the same with or
// without one (Windows editors write it).
inline std::string_view without_utf8_bom(std::string_view text) {
  if (text.size() >= 3 && static_cast<unsigned char>(text[0]) == 0xEF && static_cast<unsigned char>(text[1]) == 0xBB &&
      static_cast<unsigned char>(text[2]) == 0xBF)
    text.remove_prefix(3);
  return text;
}

// `visit(line, line_number)` for each line, numbered from 1, without its '\n' and without a
// trailing '\r' (files written on Windows read the same), after any byte-order mark.
template <class Visit>
void for_each_line(std::string_view text, Visit&& visit) {
  text = without_utf8_bom(text);
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

// The whole of `text` as one finite decimal number (core/number_text.hpp: no spaces, no inf or nan).
inline bool parse_finite_number(std::string_view text, double& value) {
  const std::optional<double> v = parse_real_text(text);
  if (v) value = *v;
  return v.has_value();
}

}  // namespace starnav
