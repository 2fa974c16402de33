#pragma once
// Limits on how many times a benchmark repeats its work: counts a person types, bounded so that
// a slip of the finger (an extra zero, a negative number read as 2^64 - 1) is refused at once
// rather than running for days. The same numbers bound the CLI flags and the library calls.
#include <cstdint>

namespace starnav {

inline constexpr int kMaxRepeats = 1000;                    // timings of one problem (median)
inline constexpr std::uint64_t kMaxRandomQueries = 100000;  // random queries drawn by a benchmark
inline constexpr std::uint64_t kMaxSeeds = 1000000;         // seeds of one sweep

}  // namespace starnav
