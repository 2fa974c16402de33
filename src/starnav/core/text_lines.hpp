#pragma once
// The lines of a text file, for the line-oriented readers (logs, relation files, trajectories,
// query lists): `visit(line, line_number)` for each line, numbered from 1, without its '\n' and
// without a trailing '\r' (files written on Windows read the same).
#include <string_view>

namespace starnav {

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

}  // namespace starnav
