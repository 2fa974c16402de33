// libFuzzer target: parse_ros_map_yaml, and read_ros_map when the input carries an image after the separator line.
// What counts as a finding: fuzz/fuzz_drivers.hpp. Run it with scripts/fuzz.sh.
#include "fuzz_entry.hpp"

STARNAV_FUZZ_TARGET(fuzz_ros_yaml)
