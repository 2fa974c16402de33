// libFuzzer target: read_ros1_bag (ROS 1 bag 2.0: records, chunks, messages).
// What counts as a finding: fuzz/fuzz_drivers.hpp. Run it with scripts/fuzz.sh.
#include "fuzz_entry.hpp"

STARNAV_FUZZ_TARGET(fuzz_ros_bag)
