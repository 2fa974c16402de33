// Regression tests from fuzzing: every input saved under fuzz/crashers/<target>/ (inputs that once
// crashed a parser, leaked, timed out or broke an invariant) and every input of the kept corpora
// fuzz/corpus/<target>/ goes through the same driver as the libFuzzer target (fuzz/fuzz_drivers.hpp),
// here under g++ (and ASan + UBSan in `make asan`). Each must either parse or throw starnav::Error.
#include <gtest/gtest.h>

#include <algorithm>
#include <exception>
#include <filesystem>
#include <string>
#include <typeinfo>
#include <vector>

#include "../../fuzz/fuzz_drivers.hpp"
#include "support/test_support.hpp"

namespace fs = std::filesystem;

namespace {

struct Input {
  std::string target;
  fs::path path;
};

// Files under <root>/<target>/ for every target folder (sorted, so failures read the same each run).
std::vector<Input> inputs_under(const fs::path& root) {
  std::vector<Input> out;
  if (!fs::is_directory(root)) return out;
  for (const auto& dir : fs::directory_iterator(root)) {
    if (!dir.is_directory()) continue;
    for (const auto& f : fs::recursive_directory_iterator(dir.path())) {
      if (f.is_regular_file()) out.push_back({dir.path().filename().string(), f.path()});
    }
  }
  std::sort(out.begin(), out.end(), [](const Input& a, const Input& b) { return a.path < b.path; });
  return out;
}

// Runs one input through its target's driver; returns "" or what went wrong.
std::string replay(const Input& in) {
  const starnav::fuzz::Target* target = starnav::fuzz::find_target(in.target);
  if (target == nullptr) return "folder name '" + in.target + "' is not a fuzz target";
  const std::string bytes = starnav::test::read_text(in.path.string());
  try {
    target->run(bytes);  // swallows starnav::Error, the expected outcome for bad input
  } catch (const std::exception& e) {
    return std::string("threw ") + typeid(e).name() + ": " + e.what();
  } catch (...) {
    return "threw a non-std exception";
  }
  return {};
}

const fs::path kFuzzDir = fs::path(STARNAV_SOURCE_DIR) / "fuzz";

}  // namespace

TEST(FuzzRegressions, CrashersParseOrThrowError) {
  const auto inputs = inputs_under(kFuzzDir / "crashers");
  if (inputs.empty()) GTEST_SKIP() << "no saved crashers under fuzz/crashers/";
  for (const auto& in : inputs) {
    SCOPED_TRACE(in.path.string());
    EXPECT_EQ(replay(in), "");
  }
}

TEST(FuzzRegressions, CorpusParsesOrThrowsError) {
  const auto inputs = inputs_under(kFuzzDir / "corpus");
  if (inputs.empty()) GTEST_SKIP() << "no fuzz corpus under fuzz/corpus/";
  std::size_t failures = 0;
  for (const auto& in : inputs) {
    const std::string problem = replay(in);
    if (!problem.empty() && ++failures <= 20) ADD_FAILURE() << in.path.string() << ": " << problem;
  }
  EXPECT_EQ(failures, 0u) << "of " << inputs.size() << " corpus inputs";
}

TEST(FuzzRegressions, EveryTargetHasSeeds) {
  for (const auto& t : starnav::fuzz::kTargets) {
    const fs::path dir = kFuzzDir / "corpus" / t.name;
    EXPECT_TRUE(fs::is_directory(dir) && !fs::is_empty(dir)) << "fuzz/corpus/" << t.name << " is missing or empty";
  }
}
