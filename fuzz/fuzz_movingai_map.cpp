// libFuzzer target: parse_movingai_map (MovingAI .map text), plus the format/parse round trip.
// What counts as a finding: fuzz/fuzz_drivers.hpp. Run it with scripts/fuzz.sh.
#include "fuzz_entry.hpp"

STARNAV_FUZZ_TARGET(fuzz_movingai_map)
