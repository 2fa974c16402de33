// libFuzzer target: read_ros2_bag_bytes on rosbag2 SQLite3 databases.
// What counts as a finding: fuzz/fuzz_drivers.hpp. Run it with scripts/fuzz.sh.
#include "fuzz_entry.hpp"

STARNAV_FUZZ_TARGET(fuzz_rosbag2_sqlite)
