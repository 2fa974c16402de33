// libFuzzer target: parse_elevation_csv.
// What counts as a finding: fuzz/fuzz_drivers.hpp. Run it with scripts/fuzz.sh.
#include "fuzz_entry.hpp"

STARNAV_FUZZ_TARGET(fuzz_elevation_csv)
