// The records and pictures of the paper's experiments E1 and E4 stay byte for byte what they were:
// SHA-256 digests of every output file (timing.json aside, the only wall-clock file) kept in
// tests/data/digests/. A change that alters an output updates the digest file and says why in its
// commit message; this test prints the new lines to paste.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "support/sha256.hpp"
#include "support/test_support.hpp"

namespace starnav {
namespace {

namespace fs = std::filesystem;

// "digest  name" lines, as sha256sum writes them.
std::map<std::string, std::string> read_digests(const std::string& path) {
  std::map<std::string, std::string> out;
  std::istringstream in(test::read_text(path));
  std::string digest, name;
  while (in >> digest >> name) out[name] = digest;
  return out;
}

void expect_outputs_match(const std::string& scenario, const std::string& digests_file,
                          const std::vector<std::string>& extra_args = {}) {
  const test::ScratchDir dir;
  const std::string out = dir.file("run");
  std::vector<std::string> args = {"sim", test::scenario_path(scenario), "--out", out, "--quiet"};
  args.insert(args.end(), extra_args.begin(), extra_args.end());
  const auto r = test::run_cli(args);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto expected = read_digests(test::test_data("digests/" + digests_file));
  ASSERT_FALSE(expected.empty()) << digests_file;
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(out))
    if (e.path().filename() != "timing.json") names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  std::string now;
  for (const std::string& n : names) now += test::sha256_hex(test::read_text((fs::path(out) / n).string())) + "  " + n + "\n";
  for (const std::string& n : names) {
    const auto it = expected.find(n);
    ASSERT_NE(it, expected.end()) << "new output " << n << "; digests now:\n" << now;
    EXPECT_EQ(test::sha256_hex(test::read_text((fs::path(out) / n).string())), it->second)
        << n << " changed; digests now:\n" << now;
  }
  EXPECT_EQ(names.size(), expected.size()) << "an output went missing; digests now:\n" << now;
}

TEST(OutputDigests, Sha256MatchesTheStandardsTestVectors) {
  EXPECT_EQ(test::sha256_hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(test::sha256_hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(test::sha256_hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  EXPECT_EQ(test::sha256_hex(std::string(1000000, 'a')), "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

TEST(OutputDigests, E1RecordsAndPicturesAreUnchanged) {
  expect_outputs_match("e1_terrain_platform.yaml", "e1.sha256");
}

TEST(OutputDigests, E4RecordsAndPicturesAreUnchanged) {
  // Under the sanitizers E4's minute of navigation runs once, in NavigationRun's test;
  // its bytes are this test's in the Release tree.
  if (test::kUnderAddressSanitizer) GTEST_SKIP() << "E4 runs under the sanitizers in NavigationRun.E4LeavesTheDeadEndAndReachesTheGoal";
  expect_outputs_match("e4_dynamic_dead_end.yaml", "e4.sha256");
}

}  // namespace
}  // namespace starnav
