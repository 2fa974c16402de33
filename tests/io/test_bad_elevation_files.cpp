// The malformed elevation files under tests/data/bad/ (prefixes elev_, asc_, csv_, raw_): each
// must give a starnav::Error whose what() is one line starting with the file's path and saying
// what is wrong. Auxiliary files (the images and RAW sidecars the cases point at) are listed too.
#include <gtest/gtest.h>

#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "starnav/core/error.hpp"
#include "starnav/io/elevation_io.hpp"
#include "support/test_support.hpp"

namespace starnav {
namespace {

namespace fs = std::filesystem;

enum class ElevationReader { Asc, ElevationYaml, Csv, UnityRaw };

struct BadElevationFile {
  const char* file;      // under tests/data/bad/
  ElevationReader reader;
  const char* contains;  // a part of what() after the path
  const char* blamed = nullptr;  // the file what() starts with, when not `file` itself
};

const BadElevationFile kBadElevationFiles[] = {
    // ESRI ASCII grid
    {"asc_missing_ncols.asc", ElevationReader::Asc, ":5: ncols: missing from the header"},
    {"asc_negative_cellsize.asc", ElevationReader::Asc, ":5: cellsize: must be positive"},
    {"asc_zero_cellsize.asc", ElevationReader::Asc, ":5: cellsize: must be positive"},
    {"asc_missing_cellsize.asc", ElevationReader::Asc, ":5: cellsize: missing from the header"},
    {"asc_too_few_values.asc", ElevationReader::Asc, ":7: ncols: row 2 has 2 values, ncols is 3"},
    {"asc_too_many_values.asc", ElevationReader::Asc, ":6: ncols: row 1 has 4 values, ncols is 3"},
    {"asc_too_few_rows.asc", ElevationReader::Asc, ":7: nrows: only 2 rows of values, nrows is 3"},
    {"asc_too_many_rows.asc", ElevationReader::Asc, ":8: nrows: more rows of values than nrows = 2"},
    {"asc_nan_value.asc", ElevationReader::Asc, ":7: value 'nan' in column 2 is not finite"},
    {"asc_inf_value.asc", ElevationReader::Asc, ":6: value '-inf' in column 2 is not finite"},
    {"asc_non_numeric_value.asc", ElevationReader::Asc, ":7: value 'x6' in column 3 is not a number"},
    {"asc_huge_ncols.asc", ElevationReader::Asc, ":1: ncols: header promises 1000000 x 1000 = 1000000000 values but only"},
    {"asc_ncols_overflow.asc", ElevationReader::Asc, ":1: ncols: too large: 4000000000"},
    {"asc_ncols_not_integer.asc", ElevationReader::Asc, ":1: ncols: must be a whole number, got '3.5'"},
    {"asc_duplicate_key.asc", ElevationReader::Asc, ":3: nrows: given twice (first on line 2)"},
    {"asc_unknown_key.asc", ElevationReader::Asc, ":5: unknown header key 'celsize'"},
    {"asc_xllcorner_and_xllcenter.asc", ElevationReader::Asc, ":4: xllcorner: both xllcorner and xllcenter given"},
    {"asc_nodata_nan.asc", ElevationReader::Asc, ":6: NODATA_value: must be a finite number, got 'nan'"},
    {"asc_empty.asc", ElevationReader::Asc, ": ncols: missing from the header"},
    {"asc_non_square_dx_dy.asc", ElevationReader::Asc, ":6: dy: non-square cells (dx 1, dy 2) are not supported"},
    // PNG16 + YAML
    {"elev_missing_z_min.yaml", ElevationReader::ElevationYaml, ": z_min: missing key"},
    {"elev_alias_bomb.yaml", ElevationReader::ElevationYaml, ":12: holds more than 200000 YAML nodes once its aliases are expanded"},
    {"elev_zmax_below_zmin.yaml", ElevationReader::ElevationYaml, ":5: z_max: z_max (5) must be >= z_min (10)"},
    {"elev_z_min_nan.yaml", ElevationReader::ElevationYaml, ":4: z_min: must be a finite number, got '.nan'"},
    {"elev_z_min_not_number.yaml", ElevationReader::ElevationYaml, ":4: z_min: must be a number, got 'low'"},
    {"elev_image_not_found.yaml", ElevationReader::ElevationYaml, ":1: image: 'elev_no_such_image.png' not found"},
    {"elev_image_8bit.yaml", ElevationReader::ElevationYaml, ":1: image: 'elev_img8_3x2.png' is 8-bit; an elevation image must be 16-bit"},
    {"elev_image_rgb.yaml", ElevationReader::ElevationYaml, ":1: image: 'elev_img16_rgb.png' is 3-channel"},
    {"elev_image_truncated.yaml", ElevationReader::ElevationYaml, ": ", "elev_img16_truncated.png"},
    {"elev_size_mismatch.yaml", ElevationReader::ElevationYaml, ":7: height: says 4 but image 'elev_img16_3x2.png' is 3 x 2"},
    {"elev_nodata_out_of_range.yaml", ElevationReader::ElevationYaml, ":6: nodata: must be in 0..65535, got 70000"},
    {"elev_resolution_zero.yaml", ElevationReader::ElevationYaml, ":2: resolution: must be positive"},
    {"elev_origin_two_values.yaml", ElevationReader::ElevationYaml, ":3: origin: must be a list of three numbers"},
    {"elev_duplicate_key.yaml", ElevationReader::ElevationYaml, ":6: z_min: duplicate key"},
    {"elev_not_yaml.yaml", ElevationReader::ElevationYaml, ": YAML syntax error"},
    {"elev_not_a_mapping.yaml", ElevationReader::ElevationYaml, ": expected a YAML mapping of keys"},
    // CSV
    {"csv_ragged_rows.csv", ElevationReader::Csv, ":2: row has 2 fields, the first row has 3"},
    {"csv_too_many_fields.csv", ElevationReader::Csv, ":2: row has more fields than the first row (3)"},
    {"csv_nan.csv", ElevationReader::Csv, ":2: column 2: value 'nan' is not finite"},
    {"csv_inf.csv", ElevationReader::Csv, ":1: column 3: value 'inf' is not finite"},
    {"csv_header_row.csv", ElevationReader::Csv, ":1: column 1: value 'x' is not a number"},
    {"csv_empty.csv", ElevationReader::Csv, ": empty CSV"},
    // Unity RAW
    {"raw_sidecar_missing.raw", ElevationReader::UnityRaw, ": sidecar "},
    {"raw_wrong_size.raw", ElevationReader::UnityRaw, ": file has 17 bytes, a 3 x 3 16-bit RAW has 18 (wrong file size)"},
    {"raw_size_not_2n1.raw", ElevationReader::UnityRaw, ".yaml:3: size: must be 2^n + 1, got 4"},
    {"raw_missing_z_max.raw", ElevationReader::UnityRaw, ".yaml: z_max: missing key"},
    {"raw_width_too_large.raw", ElevationReader::UnityRaw, ".yaml:4: width: must be in 1..3, got 5"},
    {"raw_big_endian.raw", ElevationReader::UnityRaw, ".yaml:2: byte_order: only little-endian RAW is supported"},
    {"raw_zmax_below_zmin.raw", ElevationReader::UnityRaw, ".yaml:9: z_max: z_max (-1) must be >= z_min (0)"},
    {"raw_alias_bomb.raw", ElevationReader::UnityRaw, ".yaml:15: holds more than 200000 YAML nodes once its aliases are expanded"},
};

// Files in the corpus that are not cases themselves but what the cases point at.
const std::set<std::string> kAuxiliary = {
    "elev_img16_3x2.png",     "elev_img8_3x2.png",          "elev_img16_rgb.png",
    "elev_img16_truncated.png", "raw_wrong_size.raw.yaml",    "raw_size_not_2n1.raw.yaml",
    "raw_missing_z_max.raw.yaml", "raw_width_too_large.raw.yaml", "raw_big_endian.raw.yaml",
    "raw_zmax_below_zmin.raw.yaml", "raw_alias_bomb.raw.yaml",
};

void read_elevation_with(ElevationReader reader, const std::string& path) {
  switch (reader) {
    case ElevationReader::Asc: read_asc(path); return;
    case ElevationReader::ElevationYaml: read_elevation_yaml(path); return;
    case ElevationReader::Csv: read_elevation_csv(path); return;
    case ElevationReader::UnityRaw: read_unity_raw(path); return;
  }
}

TEST(BadElevationFilesTest, EachFileGivesAOneLineErrorNamingIt) {
  for (const BadElevationFile& bad : kBadElevationFiles) {
    const std::string path = test::test_data(std::string("bad/") + bad.file);
    SCOPED_TRACE(bad.file);
    ASSERT_TRUE(fs::exists(path));
    const std::string blamed = bad.blamed ? test::test_data(std::string("bad/") + bad.blamed) : path;
    try {
      read_elevation_with(bad.reader, path);
      ADD_FAILURE() << "no error for " << bad.file;
    } catch (const Error& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.rfind(blamed, 0), 0u) << what;
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
      EXPECT_NE(what.find(bad.contains, blamed.size()), std::string::npos) << what;
    } catch (const std::exception& e) {
      ADD_FAILURE() << "not a starnav::Error: " << e.what();
    }
  }
}

// The corpus and the table agree: every elevation-format file in the folder is a case or an
// auxiliary, and there are enough distinct faults.
TEST(BadElevationFilesTest, TableCoversTheCorpus) {
  std::set<std::string> cases;
  for (const BadElevationFile& bad : kBadElevationFiles) EXPECT_TRUE(cases.insert(bad.file).second) << "twice: " << bad.file;
  int found = 0;
  for (const auto& entry : fs::directory_iterator(test::test_data("bad"))) {
    const std::string name = entry.path().filename().string();
    const bool mine = name.rfind("elev_", 0) == 0 || name.rfind("asc_", 0) == 0 || name.rfind("csv_", 0) == 0 ||
                      name.rfind("raw_", 0) == 0;
    if (!mine) continue;
    ++found;
    EXPECT_TRUE(cases.count(name) || kAuxiliary.count(name)) << name << " is in tests/data/bad but not in the table";
  }
  EXPECT_EQ(static_cast<std::size_t>(found), cases.size() + kAuxiliary.size());
  EXPECT_GE(cases.size(), 14u);
}

}  // namespace
}  // namespace starnav
