// libFuzzer target: parse_pgm (P2/P5, 8 and 16 bit).
// What counts as a finding: fuzz/fuzz_drivers.hpp. Run it with scripts/fuzz.sh.
#include "fuzz_entry.hpp"

STARNAV_FUZZ_TARGET(fuzz_pgm)
