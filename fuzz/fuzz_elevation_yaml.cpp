// libFuzzer target: read_elevation_yaml through files in a scratch folder (YAML, separator line, PNG).
// What counts as a finding: fuzz/fuzz_drivers.hpp. Run it with scripts/fuzz.sh.
#include "fuzz_entry.hpp"

STARNAV_FUZZ_TARGET(fuzz_elevation_yaml)
STARNAV_FUZZ_PNG_CRC_MUTATOR(true)
