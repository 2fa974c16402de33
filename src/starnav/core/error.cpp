#include "starnav/core/error.hpp"

#include <cmath>

namespace starnav {

std::string escape_control_characters(std::string_view text) {
  static constexpr char kHex[] = "0123456789abcdef";
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u == 0x7f) {
      out += "\\x";
      out += kHex[u >> 4];
      out += kHex[u & 0xf];
    } else {
      out += c;
    }
  }
  return out;
}

std::string format_error_location(const std::string& file_text, int line, const std::string& field_text,
                                  const std::string& message_text) {
  // Names and values from files and command lines reach the message: a newline in one must not
  // forge a second error line, nor a carriage return hide the text before it.
  const std::string file = escape_control_characters(file_text);
  const std::string field = escape_control_characters(field_text);
  const std::string message = escape_control_characters(message_text);
  std::string out;
  if (!file.empty()) {
    out.append(file);
    if (line > 0) out.append(":").append(std::to_string(line));
  } else if (line > 0) {
    out.append("line ").append(std::to_string(line));
  }
  if (!field.empty()) {
    if (!out.empty()) out.append(": ");
    out.append(field);
  }
  if (!out.empty()) out.append(": ");
  out.append(message);
  return out;
}

std::string one_line(std::string text, std::size_t max_chars) {
  for (char& c : text)
    if (c == '\n' || c == '\r' || c == '\t') c = ' ';
  while (!text.empty() && text.back() == ' ') text.pop_back();
  if (max_chars > 3 && text.size() > max_chars) text = text.substr(0, max_chars - 3) + "...";
  return text;
}

std::string printable(std::string_view text, std::size_t max_chars) {
  static constexpr char kHex[] = "0123456789abcdef";
  const bool cut = max_chars > 0 && text.size() > max_chars;
  std::string out;
  for (char c : cut ? text.substr(0, max_chars) : text) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u >= 0x7f) {
      out += "\\x";
      out += kHex[u >> 4];
      out += kHex[u & 0xf];
    } else {
      out += c;
    }
  }
  if (cut) out += "...";
  return out;
}

Error::Error(std::string message, std::string file, int line, std::string field)
    : std::runtime_error(format_error_location(file, line, field, message)),
      file_(std::move(file)),
      line_(line),
      field_(std::move(field)),
      message_(std::move(message)) {}

Error Error::with_file(const std::string& file) const { return Error(message_, file, line_, field_); }

void require(bool ok, const std::string& field, const std::string& what) {
  if (!ok) throw Error(what, {}, 0, field);
}
void require_positive(double v, const std::string& field) { require(std::isfinite(v) && v > 0.0, field, "must be finite and > 0"); }
void require_non_negative(double v, const std::string& field) {
  require(std::isfinite(v) && v >= 0.0, field, "must be finite and >= 0");
}

}  // namespace starnav
