// The one YAML reader: each node of the text visited once, aliases counted as what they expand to
// (a closed-form count here), duplicate keys and alias cycles refused, sizes bounded.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "starnav/io/yaml_document.hpp"
#include "support/test_support.hpp"

namespace starnav {
namespace {

// `key: &a [x, ..., x]` (k scalars), then `use: [*a, ..., *a]` (m aliases).
std::string anchored_list_used(int k, int m) {
  std::string y = "key: &a [";
  for (int i = 0; i < k; ++i) y += i ? ", x" : "x";
  y += "]\nuse: [";
  for (int i = 0; i < m; ++i) y += i ? ", *a" : "*a";
  return y + "]\n";
}
// Its nodes once expanded: the root mapping, two keys, the list (1 + k) and the list of m copies.
std::uint64_t expanded_nodes(int k, int m) {
  return 1 + 2 + (1 + static_cast<std::uint64_t>(k)) + 1 + static_cast<std::uint64_t>(m) * (1 + static_cast<std::uint64_t>(k));
}

TEST(YamlDocument, AliasesCountAsTheNodesTheyExpandTo) {
  // k + 1 = 100 nodes per copy; m copies chosen to land exactly on the limit, then one node over.
  const int k = 99;
  const int m = static_cast<int>((kMaxYamlNodes - expanded_nodes(k, 0)) / 100);
  const std::uint64_t at = expanded_nodes(k, m);
  ASSERT_LE(at, kMaxYamlNodes);
  ASSERT_GT(expanded_nodes(k, m + 1), kMaxYamlNodes);
  EXPECT_NO_THROW(load_yaml_document(anchored_list_used(k, m), "ok.yaml"));
  const std::string what = test::error_of([&] { load_yaml_document(anchored_list_used(k, m + 1), "over.yaml"); });
  EXPECT_EQ(what, "over.yaml:2: holds more than 200000 YAML nodes once its aliases are expanded");
  // An alias is the node it names: the reader sees the same values.
  const YAML::Node doc = load_yaml_document(anchored_list_used(3, 2), "small.yaml");
  ASSERT_EQ(doc["use"].size(), 2u);
  EXPECT_EQ(doc["use"][1][2].Scalar(), "x");
}

TEST(YamlDocument, PlainDocumentsAreBoundedByTheirNodesToo) {
  // A flat list of n scalars is n + 1 nodes: the limit holds without any alias.
  const auto list = [](std::uint64_t n) {
    std::string y = "[";
    for (std::uint64_t i = 0; i < n; ++i) y += i ? ",1" : "1";
    return y + "]";
  };
  EXPECT_NO_THROW(load_yaml_document(list(1000), "flat.yaml"));
  EXPECT_NE(test::error_of([&] { load_yaml_document(list(kMaxYamlNodes), "flat.yaml"); }).find("more than 200000 YAML nodes"),
            std::string::npos);
}

TEST(YamlDocument, NestedAliasesAreRefusedWithoutExpandingThem) {
  // Nine levels of ten: 10^9 nodes in 400 bytes (walking them took minutes).
  std::string y = "l0: &l0 [x, x, x, x, x, x, x, x, x, x]\n";
  for (int i = 1; i < 9; ++i) {
    y += "l" + std::to_string(i) + ": &l" + std::to_string(i) + " [";
    for (int j = 0; j < 10; ++j) y += (j ? ", *l" : "*l") + std::to_string(i - 1);
    y += "]\n";
  }
  // 11, 111, 1111, 11111, 111111 nodes per level: the second alias of line 6 passes 200000.
  EXPECT_EQ(test::error_of([&] { load_yaml_document(y, "laughs.yaml"); }),
            "laughs.yaml:6: holds more than 200000 YAML nodes once its aliases are expanded");
}

TEST(YamlDocument, AnAliasInsideItsOwnAnchorIsACycleAndRefused) {
  EXPECT_EQ(test::error_of([] { load_yaml_document("a:\n  b: &x [1, *x]\n", "cycle.yaml"); }),
            "cycle.yaml:2: a.b[1]: an alias inside the node its anchor names (a cycle)");
  EXPECT_EQ(test::error_of([] { load_yaml_document("a: &m {k: *m}\n", "cycle.yaml"); }),
            "cycle.yaml:1: a.k: an alias inside the node its anchor names (a cycle)");
}

TEST(YamlDocument, DuplicateKeysAreFoundOnceWhereTheyAreWritten) {
  // The anchored mapping is used 50 times; its duplicate is reported at its own line and path.
  std::string y = "base: &b\n  x: 1\n  x: 2\nuses: [";
  for (int i = 0; i < 50; ++i) y += i ? ", *b" : "*b";
  y += "]\n";
  EXPECT_EQ(test::error_of([&] { load_yaml_document(y, "dup.yaml"); }), "dup.yaml:3: base.x: duplicate key");
  EXPECT_EQ(test::error_of([] { load_yaml_document("a:\n  - {c: 1}\n  - {c: 1, c: 2}\n", "dup.yaml"); }),
            "dup.yaml:3: a[1].c: duplicate key");
  // The same key in different mappings is no duplicate.
  EXPECT_NO_THROW(load_yaml_document("a: {c: 1}\nb: {c: 1}\nl: [{c: 1}, {c: 2}]\n", "ok.yaml"));
}

TEST(YamlDocument, SizeIsCheckedBeforeReading) {
  test::ScratchDir dir;
  const std::string big = dir.file("big.yaml");
  test::write_text(big, "a: 1\n");
  std::filesystem::resize_file(big, kMaxYamlBytes + 1);  // sparse: nothing is read to refuse it
  EXPECT_NE(test::error_of([&] { read_yaml_file(big); }).find("more than the 4194304 read at most"), std::string::npos);
  const std::string text(kMaxYamlBytes + 1, ' ');
  EXPECT_NE(test::error_of([&] { load_yaml_document(text, "t.yaml"); }).find("more than the 4194304 a YAML document may have"),
            std::string::npos);
  EXPECT_EQ(test::error_of([] { load_yaml_document("a: [1,\n", "syntax.yaml"); }).rfind("syntax.yaml:", 0), 0u);
}

}  // namespace
}  // namespace starnav
