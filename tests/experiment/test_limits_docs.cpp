// docs/limits.md is what the constants say.
#include <gtest/gtest.h>

#include <filesystem>

#include "starnav/experiment/limits_docs.hpp"
#include "support/test_support.hpp"

namespace starnav {
namespace {

TEST(LimitsDocs, TheLimitsPageIsCurrent) {
  const std::string path = (std::filesystem::path(STARNAV_SOURCE_DIR) / "docs" / "limits.md").string();
  ASSERT_TRUE(std::filesystem::exists(path)) << path;
  EXPECT_TRUE(test::read_text(path) == limits_markdown())
      << "docs/limits.md is stale: run `build/bin/starnav limits --markdown > docs/limits.md`";
}

}  // namespace
}  // namespace starnav
