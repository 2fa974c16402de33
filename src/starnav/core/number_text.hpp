#pragma once
// The one reading of a number written as text, for every command-line flag, YAML value and
// parameter: decimal only (no hex "0x10", no octal "010", no leading blanks), an optional leading
// '+', and for reals a finite value. A count or a seed takes no sign: "-1" is refused, not wrapped.
#include <cstdint>
#include <optional>
#include <string_view>

namespace starnav {

// A finite real in decimal or exponent notation ("2", "-0.5", "1e-3"); nullopt otherwise.
std::optional<double> parse_real_text(std::string_view text);

// A signed decimal integer that fits in 64 bits; nullopt otherwise.
std::optional<std::int64_t> parse_integer_text(std::string_view text);

// A non-negative decimal integer that fits in 64 bits (counts, seeds); nullopt otherwise.
std::optional<std::uint64_t> parse_unsigned_text(std::string_view text);

}  // namespace starnav
