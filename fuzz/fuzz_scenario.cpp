// libFuzzer target: parse_scenario (scenario YAML: world, robot, sensors, commands, navigation, ...),
// then checks what scenario.hpp promises about the spec; never build_world.
// What counts as a finding: fuzz/fuzz_drivers.hpp. Run it with scripts/fuzz.sh.
#include "fuzz_entry.hpp"

STARNAV_FUZZ_TARGET(fuzz_scenario)
