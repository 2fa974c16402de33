// libFuzzer target: the point-cloud readers (PCD ascii/binary/binary_compressed, PLY, KITTI .bin)
// and the LZF decompressor. What counts as a finding: fuzz/fuzz_drivers.hpp. Run it with scripts/fuzz.sh.
#include "fuzz_entry.hpp"

STARNAV_FUZZ_TARGET(fuzz_point_cloud)
