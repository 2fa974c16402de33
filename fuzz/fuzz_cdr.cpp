// libFuzzer target: the CDR decoders of the ROS 2 messages starnav reads (the first byte picks the type).
// What counts as a finding: fuzz/fuzz_drivers.hpp. Run it with scripts/fuzz.sh.
#include "fuzz_entry.hpp"

STARNAV_FUZZ_TARGET(fuzz_cdr)
