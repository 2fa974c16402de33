#include "starnav/core/number_text.hpp"

#include <charconv>
#include <cmath>

namespace starnav {

namespace {

// from_chars reads decimal only and no blanks; it refuses a leading '+', which people type. "+-1"
// and "++1" stay refused: after the '+' no second sign.
std::optional<std::string_view> without_plus(std::string_view text) {
  if (text.empty() || text.front() != '+') return text;
  text.remove_prefix(1);
  if (!text.empty() && (text.front() == '+' || text.front() == '-')) return std::nullopt;
  return text;
}

template <typename T>
std::optional<T> parse_whole(std::string_view text) {
  const std::optional<std::string_view> digits = without_plus(text);
  if (!digits || digits->empty()) return std::nullopt;
  text = *digits;
  T v{};
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || ptr != text.data() + text.size()) return std::nullopt;
  return v;
}

}  // namespace

std::optional<double> parse_real_text(std::string_view text) {
  const std::optional<double> v = parse_whole<double>(text);
  if (!v || !std::isfinite(*v)) return std::nullopt;
  return v;
}

std::optional<std::int64_t> parse_integer_text(std::string_view text) { return parse_whole<std::int64_t>(text); }

std::optional<std::uint64_t> parse_unsigned_text(std::string_view text) {
  // from_chars for an unsigned type refuses '-', so "-1" does not wrap; "-0" is refused too.
  if (!text.empty() && text.front() == '+') return std::nullopt;
  return parse_whole<std::uint64_t>(text);
}

std::optional<std::int64_t> parse_integer_in(std::string_view text, std::int64_t lo, std::int64_t hi) {
  std::optional<std::int64_t> v;
  if (lo >= 0) {
    const std::optional<std::uint64_t> u = parse_unsigned_text(text);
    if (u && *u <= static_cast<std::uint64_t>(hi)) v = static_cast<std::int64_t>(*u);
  } else {
    v = parse_integer_text(text);
  }
  if (!v || *v < lo || *v > hi) return std::nullopt;
  return v;
}

}  // namespace starnav
