// libFuzzer target: read_unity_raw through files in a scratch folder (sidecar YAML, separator line, RAW).
// What counts as a finding: fuzz/fuzz_drivers.hpp. Run it with scripts/fuzz.sh.
#include "fuzz_entry.hpp"

STARNAV_FUZZ_TARGET(fuzz_unity_raw)
