#pragma once
// The one reading of a number written as text, for every command-line flag, YAML value and
// parameter: decimal only (no hex "0x10", no octal "010", no leading blanks), for reals a finite
// value. A real or a signed integer may have a leading '+'; a count or a seed takes no sign at all:
// "-1" is refused, not wrapped, and "+16" is refused too (one spelling per count).
#include <cstdint>
#include <optional>
#include <string_view>

namespace starnav {

// A finite real in decimal or exponent notation ("2", "-0.5", "1e-3"); nullopt otherwise.
std::optional<double> parse_real_text(std::string_view text);

// A signed decimal integer that fits in 64 bits; nullopt otherwise.
std::optional<std::int64_t> parse_integer_text(std::string_view text);

// A non-negative decimal integer without a sign that fits in 64 bits (counts, seeds); nullopt
// otherwise.
std::optional<std::uint64_t> parse_unsigned_text(std::string_view text);

// A whole number within [lo, hi]: without a sign when lo >= 0 (a count), else as
// parse_integer_text; nullopt otherwise (also out of the range).
std::optional<std::int64_t> parse_integer_in(std::string_view text, std::int64_t lo, std::int64_t hi);

}  // namespace starnav
