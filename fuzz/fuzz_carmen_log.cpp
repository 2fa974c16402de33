// libFuzzer target: read_carmen_log and read_odomscan_text (CARMEN logs, text extracts).
// What counts as a finding: fuzz/fuzz_drivers.hpp. Run it with scripts/fuzz.sh.
#include "fuzz_entry.hpp"

STARNAV_FUZZ_TARGET(fuzz_carmen_log)
