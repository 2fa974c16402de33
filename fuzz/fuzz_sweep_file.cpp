// libFuzzer target: parse_sweep_file (the sweep file of starnav sweep: command, axes, metrics,
// summary, plots), then the first tasks of its expansion; never resolves globs.
// What counts as a finding: fuzz/fuzz_drivers.hpp. Run it with scripts/fuzz.sh.
#include "fuzz_entry.hpp"

STARNAV_FUZZ_TARGET(fuzz_sweep_file)
