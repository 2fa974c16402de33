// libFuzzer target: parse_png (grey, grey+alpha, RGB, RGBA, palette; 8 and 16 bit).
// What counts as a finding: fuzz/fuzz_drivers.hpp. Run it with scripts/fuzz.sh.
#include "fuzz_entry.hpp"

STARNAV_FUZZ_TARGET(fuzz_png)
STARNAV_FUZZ_PNG_CRC_MUTATOR(false)
