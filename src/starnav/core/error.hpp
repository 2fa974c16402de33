#pragma once
// The one error type of starnav: every bad input becomes an Error that names where it came from,
// so the CLI can print `starnav: error: FILE[:LINE][: FIELD]: what is wrong` and exit 2.
#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>

namespace starnav {

class Error : public std::runtime_error {
 public:
  explicit Error(std::string message, std::string file = {}, int line = 0, std::string field = {});

  const std::string& file() const noexcept { return file_; }
  int line() const noexcept { return line_; }
  const std::string& field() const noexcept { return field_; }
  const std::string& message() const noexcept { return message_; }

  // The same error attributed to a file (keeps line/field); used when a parser of text is
  // called on behalf of a named file.
  Error with_file(const std::string& file) const;

 private:
  std::string file_;
  int line_ = 0;
  std::string field_;
  std::string message_;
};

// `text` fit for one line of an error message: line breaks and tabs become spaces, trailing
// spaces go, and with max_chars > 0 a longer text is cut to max_chars ending in "...".
std::string one_line(std::string text, std::size_t max_chars = 0);

// Text taken from input (a token, a topic name) fit to quote in a message: every byte outside
// printable ASCII becomes \xNN, so that no input can break or forge an error line; with max_chars > 0 a longer
// text is cut to max_chars and "..." added.
std::string printable(std::string_view text, std::size_t max_chars = 0);

// Control characters (below 0x20, and 0x7f) as \xNN; every other byte (UTF-8 names too) kept.
std::string escape_control_characters(std::string_view text);

// FILE[:LINE][: FIELD]: message  (parts that are empty are left out; control characters in any
// part escaped, so an Error's what() is always one line).
std::string format_error_location(const std::string& file, int line, const std::string& field,
                                  const std::string& message);

// Checks for configurations' validate(): an Error naming `field` when the check fails.
void require(bool ok, const std::string& field, const std::string& what);
void require_positive(double v, const std::string& field);      // finite and > 0
void require_non_negative(double v, const std::string& field);  // finite and >= 0

}  // namespace starnav
