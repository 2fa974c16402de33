// Declared parameters (core/params.hpp): one parser for YAML and --set values, ranges, choices,
// unknown keys, defaults read back from the configuration, errors naming file, line and key.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "starnav/core/angle.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/params.hpp"

namespace starnav {
namespace {

struct Inner {
  int count = 3;
};
struct Config {
  double speed_mps = 0.2;
  double yaw_rate_radps = 1.0;
  bool enabled = true;
  std::string mode = "a";
  Inner inner;
};

const ParamTable<Config>& table() {
  static const ParamTable<Config> t = [] {
    ParamTable<Config> t;
    t.real("speed_mps", &Config::speed_mps, positive(), "m/s", "speed");
    t.real("yaw_rate_degps", &Config::yaw_rate_radps, closed(0.0, 360.0), "deg/s", "yaw rate", kPi / 180.0);
    t.boolean("enabled", &Config::enabled, "on or off");
    t.choice("mode", {"a", "b"}, [](Config& c, const std::string& v) { c.mode = v; }, [](const Config& c) { return c.mode; },
             "mode");
    t.integer("inner.count", [](Config& c) -> int& { return c.inner.count; }, closed(1, 10), "", "count");
    return t;
  }();
  return t;
}

ParamSetting at(const std::string& key, const std::string& value) { return {key, value, "s.yaml", 7, "nav." + key}; }

Error error_applying(const ParamSetting& v) {
  Config c;
  try {
    table().apply(c, v);
  } catch (const Error& e) {
    return e;
  }
  ADD_FAILURE() << "accepted " << v.key << "=" << v.value;
  return Error("none");
}

TEST(Params, AppliesValuesThroughTheDeclaredScaleAndReadsDefaultsBack) {
  Config c;
  table().apply(c, at("speed_mps", "0.35"));
  table().apply(c, at("yaw_rate_degps", "90"));
  table().apply(c, at("enabled", "false"));
  table().apply(c, at("mode", "b"));
  table().apply(c, at("inner.count", "7"));
  EXPECT_EQ(c.speed_mps, 0.35);
  EXPECT_EQ(c.yaw_rate_radps, 90.0 * (kPi / 180.0));
  EXPECT_FALSE(c.enabled);
  EXPECT_EQ(c.mode, "b");
  EXPECT_EQ(c.inner.count, 7);
  const auto specs = table().specs();
  ASSERT_EQ(specs.size(), 5u);
  EXPECT_EQ(specs[0].default_value, "0.2");
  EXPECT_EQ(specs[1].default_value, format_param_real(180.0 / kPi));  // 1 rad/s in deg/s
  EXPECT_EQ(specs[2].default_value, "true");
  EXPECT_EQ(specs[3].default_value, "a");
  EXPECT_EQ(specs[4].default_value, "3");
  EXPECT_EQ(specs[1].range_text(), "[0, 360]");
  EXPECT_EQ(specs[3].range_text(), "a | b");
}

TEST(Params, EveryDefaultReadsBackToTheSameConfiguration) {
  // Round trip: applying each declared default as text leaves the defaults unchanged.
  Config c;
  for (const ParamSpec& s : table().specs()) table().apply(c, at(s.key, s.default_value));
  EXPECT_EQ(table().specs(c)[0].default_value, "0.2");
  for (std::size_t i = 0; i < table().specs().size(); ++i)
    EXPECT_EQ(table().specs(c)[i].default_value, table().specs()[i].default_value) << table().specs()[i].key;
}

TEST(Params, BadValuesNameTheFileLineAndFullKey) {
  for (const auto& [key, value] : std::vector<std::pair<std::string, std::string>>{
           {"speed_mps", "0"}, {"speed_mps", "-1"}, {"speed_mps", "fast"}, {"speed_mps", "nan"}, {"speed_mps", "inf"},
           {"speed_mps", ""}, {"speed_mps", "1e400"}, {"speed_mps", "0.2m"}, {"yaw_rate_degps", "361"},
           {"enabled", "yes please"}, {"mode", "c"}, {"inner.count", "1.5"}, {"inner.count", "11"}, {"inner.count", "+7"},
           {"inner.count", "99999999999999999999"}, {"nope", "1"}}) {
    const Error e = error_applying(at(key, value));
    EXPECT_EQ(e.file(), "s.yaml") << key << "=" << value;
    EXPECT_EQ(e.line(), 7) << key << "=" << value;
    EXPECT_EQ(e.field(), "nav." + key) << key << "=" << value;
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
  }
  EXPECT_NE(std::string(error_applying(at("nope", "1")).what()).find("known: speed_mps"), std::string::npos);
  EXPECT_NE(std::string(error_applying(at("speed_mps", "0")).what()).find("> 0"), std::string::npos);
}

TEST(Params, RangesIncludeOrExcludeTheirEnds) {
  EXPECT_FALSE(positive().contains(0.0));
  EXPECT_TRUE(positive().contains(1e-300));
  EXPECT_TRUE(non_negative().contains(0.0));
  EXPECT_FALSE(open(0.0, 90.0).contains(90.0));
  EXPECT_TRUE(closed(0.0, 90.0).contains(90.0));
  EXPECT_FALSE(closed(0.0, 90.0).contains(std::nan("")));
  EXPECT_EQ(open(0.0, 90.0).text(), "(0, 90)");
  EXPECT_EQ(non_negative().text(), ">= 0");
  EXPECT_EQ(any_value().text(), "any");
}

TEST(Params, RethrowAtSettingFindsTheSettingOfAValidationError) {
  const std::vector<ParamSetting> given = {at("speed_mps", "0.1"), at("inner.count", "2")};
  try {
    rethrow_at_setting(Error("must not exceed", "", 0, "follower.speed_mps"), given, "s.yaml");
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "nav.speed_mps");
    EXPECT_EQ(e.line(), 7);
  }
  try {
    rethrow_at_setting(Error("bad", "", 0, "other"), given, "s.yaml");
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "other");
    EXPECT_EQ(e.file(), "s.yaml");
  }
}

TEST(ParamPolygons, ReadsNestedListsAndWritesThemBackTheSame) {
  const ParamSetting v{"zones", "[[[0, 0], [2.5, 0], [2.5,1e-1]] ,[[-1, -1],[ -2,-1 ],[-2,-3],[-1.5,-3]]]", "s.yaml", 4, "nav.zones"};
  const std::vector<ParamPolygon> p = parse_param_polygons(v);
  ASSERT_EQ(p.size(), 2u);
  ASSERT_EQ(p[0].size(), 3u);
  ASSERT_EQ(p[1].size(), 4u);
  EXPECT_EQ(p[0][1][0], 2.5);
  EXPECT_EQ(p[0][2][1], 0.1);
  EXPECT_EQ(p[1][3][0], -1.5);
  const std::string text = format_param_polygons(p);
  EXPECT_EQ(text, "[[[0, 0], [2.5, 0], [2.5, 0.1]], [[-1, -1], [-2, -1], [-2, -3], [-1.5, -3]]]");
  EXPECT_EQ(parse_param_polygons({"zones", text, "", 0, "zones"}), p);
  EXPECT_TRUE(parse_param_polygons({"zones", "[]", "", 0, "zones"}).empty());
  EXPECT_TRUE(parse_param_polygons({"zones", " [ ] ", "", 0, "zones"}).empty());
}

TEST(ParamPolygons, RefusesEveryOtherShapeNamingTheSetting) {
  for (const char* bad : {"", "[", "[[[0, 0], [1, 0]]]", "[[0, 0], [1, 0], [1, 1]]", "[[[0, 0], [1, 0], [1, 1]]", "[[[0, 0], [1, 0], [1, 1]]]]",
                          "[[[0, 0, 0], [1, 0], [1, 1]]]", "[[[0], [1, 0], [1, 1]]]", "[[[0, nan], [1, 0], [1, 1]]]",
                          "[[[0, 1e400], [1, 0], [1, 1]]]", "[[[0, x], [1, 0], [1, 1]]]", "[[[0, 0], [1, 0], [1, 1]],]",
                          "[[[0, 0] [1, 0], [1, 1]]]", "[[], [[0, 0], [1, 0], [1, 1]]]", "[a, b]", "0x10"}) {
    try {
      parse_param_polygons({"zones", bad, "s.yaml", 9, "navigation.keepout.zones"});
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const Error& e) {
      EXPECT_EQ(e.file(), "s.yaml") << bad;
      EXPECT_EQ(e.line(), 9) << bad;
      EXPECT_EQ(e.field(), "navigation.keepout.zones") << bad;
    }
  }
}

TEST(ParamPolygons, BoundsThePointsBeforeStoringThem) {
  std::string text = "[[";
  for (std::size_t i = 0; i <= kMaxParamPolygonVertices; ++i) text += i ? ", [1, 2]" : "[1, 2]";
  text += "]]";
  try {
    parse_param_polygons({"zones", text, "", 0, "zones"});
    FAIL() << "accepted " << kMaxParamPolygonVertices + 1 << " points";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("more than 100000 points"), std::string::npos) << e.what();
  }
}

TEST(ParamPolygons, ATableDeclaresAndAppliesThem) {
  struct Zones {
    std::vector<ParamPolygon> zones;
  };
  ParamTable<Zones> t;
  t.polygons("zones", &Zones::zones, "m", "keep-out zones");
  Zones z;
  t.apply(z, ParamSetting{"zones", "[[[0, 0], [1, 0], [0, 1]]]", "", 0, "zones"});
  ASSERT_EQ(z.zones.size(), 1u);
  const std::vector<ParamSpec> specs = t.specs(z);
  ASSERT_EQ(specs.size(), 1u);
  EXPECT_EQ(specs[0].type, ParamType::Polygons);
  EXPECT_EQ(specs[0].default_value, "[[[0, 0], [1, 0], [0, 1]]]");
  EXPECT_STREQ(param_type_name(specs[0].type), "polygons");
}

TEST(ParamReals, ReadsAListAndWritesItBackTheSame) {
  const ParamSetting v{"limits_mps", "[0.3, 1e-1 ,2.5,0]", "s.yaml", 4, "nav.limits_mps"};
  const std::vector<double> x = parse_param_reals(v);
  ASSERT_EQ(x.size(), 4u);
  EXPECT_EQ(x[0], 0.3);
  EXPECT_EQ(x[1], 0.1);
  EXPECT_EQ(x[2], 2.5);
  EXPECT_EQ(x[3], 0.0);
  const std::string text = format_param_reals(x);
  EXPECT_EQ(text, "[0.3, 0.1, 2.5, 0]");
  EXPECT_EQ(parse_param_reals({"l", text, "", 0, "l"}), x);
  // A scenario's empty list arrives as "" (an empty list of names); "[]" on the command line.
  for (const char* none : {"", " ", "[]", " [ ] "}) EXPECT_TRUE(parse_param_reals({"l", none, "", 0, "l"}).empty()) << none;
}

TEST(ParamReals, RefusesEveryOtherShapeNamingTheSetting) {
  for (const char* bad : {"[", "]", "0.3", "0.3, 0.5", "[0.3,]", "[,0.3]", "[0.3 0.5]", "[[0.3]]", "[0.3]]", "[nan]", "[inf]",
                          "[1e400]", "[0x10]", "[a]", "[0.3, 0.5", "[0.3] x", "[0.3,, 0.5]"}) {
    try {
      parse_param_reals({"limits_mps", bad, "s.yaml", 9, "navigation.zone.limits_mps"});
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const Error& e) {
      EXPECT_EQ(e.file(), "s.yaml") << bad;
      EXPECT_EQ(e.line(), 9) << bad;
      EXPECT_EQ(e.field(), "navigation.zone.limits_mps") << bad;
    }
  }
}

TEST(ParamReals, BoundsTheNumbersBeforeStoringThem) {
  std::string text = "[";
  for (std::size_t i = 0; i <= kMaxParamListNumbers; ++i) text += i ? ", 1" : "1";
  text += "]";
  try {
    parse_param_reals({"l", text, "", 0, "l"});
    FAIL() << "accepted " << kMaxParamListNumbers + 1 << " numbers";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("more than 100000 numbers"), std::string::npos) << e.what();
  }
  text.erase(text.size() - 4);  // exactly the bound
  text += "]";
  EXPECT_EQ(parse_param_reals({"l", text, "", 0, "l"}).size(), kMaxParamListNumbers);
}

TEST(ParamReals, ATableChecksEachNumberAndScales) {
  struct Limits {
    std::vector<double> speeds;
  };
  ParamTable<Limits> t;
  t.reals("speeds_cmps", &Limits::speeds, positive(), "cm/s", "speeds", 0.01);
  Limits l;
  t.apply(l, ParamSetting{"speeds_cmps", "[30, 50]", "", 0, "speeds_cmps"});
  ASSERT_EQ(l.speeds.size(), 2u);
  EXPECT_DOUBLE_EQ(l.speeds[0], 0.3);
  EXPECT_DOUBLE_EQ(l.speeds[1], 0.5);
  const std::vector<ParamSpec> specs = t.specs(l);
  ASSERT_EQ(specs.size(), 1u);
  EXPECT_EQ(specs[0].type, ParamType::Reals);
  EXPECT_EQ(specs[0].default_value, "[30, 50]");
  EXPECT_EQ(specs[0].range_text(), "a list of numbers, each > 0");
  EXPECT_STREQ(param_type_name(specs[0].type), "reals");
  try {
    t.apply(l, ParamSetting{"speeds_cmps", "[30, 0, 5]", "s.yaml", 3, "navigation.z.speeds_cmps"});
    FAIL() << "accepted a zero";
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "navigation.z.speeds_cmps");
    EXPECT_EQ(e.line(), 3);
    EXPECT_NE(std::string(e.what()).find("number 2 must be > 0, found 0"), std::string::npos) << e.what();
  }
}

// A custom entry checks its own rule; nest("") puts a table's keys beside the outer ones.
struct Outer {
  Config inner;
  long long whole = 2;
};

TEST(Params, CustomEntriesAndNestingUnderNoPrefix) {
  ParamTable<Outer> t;
  ParamSpec whole{"whole", ParamType::Integer, {}, closed(2, 8), {}, "", "an even number"};
  t.custom(
      std::move(whole),
      [](Outer& o, const ParamSetting& v) {
        const long long n = parse_param_integer(v);
        if (n % 2 != 0) throw Error("must be even, got " + v.value, v.file, v.line, v.field.empty() ? v.key : v.field);
        o.whole = n;
      },
      [](const Outer& o) { return std::to_string(o.whole); });
  t.nest("", table(), [](Outer& o) -> Config& { return o.inner; });
  EXPECT_EQ(t.keys(), (std::vector<std::string>{"whole", "speed_mps", "yaw_rate_degps", "enabled", "mode", "inner.count"}));
  const std::vector<ParamSpec> specs = t.specs();
  EXPECT_EQ(specs[0].default_value, "2");
  EXPECT_EQ(specs[1].default_value, "0.2");
  Outer o;
  t.apply(o, {"whole", "6", "", 0, ""});
  t.apply(o, {"speed_mps", "0.5", "", 0, ""});
  EXPECT_EQ(o.whole, 6);
  EXPECT_DOUBLE_EQ(o.inner.speed_mps, 0.5);
  try {
    t.apply(o, {"whole", "3", "f.yaml", 4, "x.whole"});
    FAIL() << "an odd number passed";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "f.yaml:4: x.whole: must be even, got 3");
  }
  EXPECT_THROW(t.apply(o, {"speed_mps", "-1", "", 0, ""}), Error);  // the nested table's own range
}

}  // namespace
}  // namespace starnav
