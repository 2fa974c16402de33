#include "starnav/core/error.hpp"

namespace starnav {

std::string format_error_location(const std::string& file, int line, const std::string& field,
                                  const std::string& message) {
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

Error::Error(std::string message, std::string file, int line, std::string field)
    : std::runtime_error(format_error_location(file, line, field, message)),
      file_(std::move(file)),
      line_(line),
      field_(std::move(field)),
      message_(std::move(message)) {}

Error Error::with_file(const std::string& file) const { return Error(message_, file, line_, field_); }

}  // namespace starnav
