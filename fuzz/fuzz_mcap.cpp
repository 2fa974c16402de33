// libFuzzer target: read_ros2_bag_bytes on MCAP (records, chunks, zstd/lz4, summary and indexes) and the record-by-record path.
// What counts as a finding: fuzz/fuzz_drivers.hpp. Run it with scripts/fuzz.sh.
#include "fuzz_entry.hpp"

STARNAV_FUZZ_TARGET(fuzz_mcap)
