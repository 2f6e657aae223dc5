// Unit tests of OptionTable (accel/option_table.h): the printed defaults, parsing and range checks derived from one
// table, checked on a small struct; every registered structure enforcing each declared range at both ends; and the
// same checks for C++ users who construct a structure directly, without the registry.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "rayaccel/accel/bsp_tree.h"
#include "rayaccel/accel/kd_tree.h"
#include "rayaccel/accel/octree.h"
#include "rayaccel/accel/option_table.h"
#include "rayaccel/accel/two_level_grid.h"
#include "rayaccel/accel/uniform_grid.h"
#include "rayaccel/bvh/bvh.h"
#include "rayaccel/core/error.h"
#include "../error_message.h"
#include "rayaccel/wide/wide_bvh.h"

namespace rayaccel {
namespace {

using testing::contains;
using testing::error_message;

enum class Shape { box, ball };
struct Inner {
  std::uint32_t count = 16;
};
struct Fake {
  Shape shape = Shape::ball;
  int depth = 3;
  float ratio = 0.2f;
  double scale = 1e-5;
  bool fast = false;
  Inner inner;
};

OptionTable<Fake> fake_table() {
  OptionTable<Fake> t("fake");
  t.choice("shape", &Fake::shape, {{"box", Shape::box}, {"ball", Shape::ball}}, "a shape");
  t.integer("depth", &Fake::depth, 0, 10, "a depth");
  t.real("ratio", &Fake::ratio, {0.0, 1.0, false, true}, "a ratio");
  t.real("scale", &Fake::scale, RealRange::positive(), "a scale");
  t.boolean("fast", &Fake::fast, "a switch");
  t.integer("count", [](Fake& f) -> std::uint32_t& { return f.inner.count; }, 2, 64, "a nested count");
  t.rule([](const Fake& f) {
    if (f.fast && f.shape == Shape::box) throw Error("fake: fast applies to balls only");
  });
  return t;
}

AcceleratorInfo fake_info() { return {"fake", "test entry", fake_table().specs(), {}, {}, false, {}}; }

Fake parse(const std::map<std::string, std::string>& given) {
  return fake_table().parse(resolve_options(fake_info(), given));
}

TEST(OptionTable, FormatsRealsAsTheShortestTextThatReadsBack) {
  EXPECT_EQ(format_real(15.0f, true), "15");
  EXPECT_EQ(format_real(0.2f, true), "0.2");
  EXPECT_EQ(format_real(1e-5f, true), "1e-5");
  EXPECT_EQ(format_real(0.1, false), "0.1");
  EXPECT_EQ(format_real(1e30, false), "1e30");
  EXPECT_EQ(format_real(-2.5, false), "-2.5");
  EXPECT_EQ(format_real(1.0 / 0.0, false), "inf");
  // Round trip: the printed float reads back as the same float.
  for (const float v : {0.1f, 1.3f, 3.0f / 7.0f, 1e-5f, 123456.78f}) {
    EXPECT_EQ(std::stof(format_real(v, true)), v) << format_real(v, true);
  }
}

TEST(OptionTable, SpecsPrintTheStructDefaultsAndRanges) {
  const std::vector<OptionSpec> specs = fake_table().specs();
  ASSERT_EQ(specs.size(), 6u);
  const auto at = [&](const char* key) {
    for (const auto& s : specs) {
      if (s.key == key) return s;
    }
    ADD_FAILURE() << key;
    return OptionSpec{};
  };
  EXPECT_EQ(at("shape").default_value, "ball");
  EXPECT_EQ(at("shape").choices, (std::vector<std::string>{"box", "ball"}));
  EXPECT_EQ(at("depth").default_value, "3");
  EXPECT_EQ(at("depth").range, "[0, 10]");
  EXPECT_EQ(at("ratio").default_value, "0.2");
  EXPECT_EQ(at("ratio").range, "[0, 1)");
  EXPECT_EQ(at("scale").default_value, "1e-5");
  EXPECT_EQ(at("scale").range, "(0, inf)");
  EXPECT_EQ(at("fast").default_value, "false");
  EXPECT_EQ(at("count").default_value, "16");
  EXPECT_EQ(at("count").type, OptionType::integer);
}

TEST(OptionTable, ParsesEveryRowIntoItsMember) {
  const Fake d = parse({});
  EXPECT_EQ(d.shape, Shape::ball);
  EXPECT_EQ(d.depth, 3);
  EXPECT_EQ(d.inner.count, 16u);
  const Fake f = parse({{"shape", "box"}, {"depth", "10"}, {"ratio", "0"}, {"scale", "2e3"}, {"count", "2"}});
  EXPECT_EQ(f.shape, Shape::box);
  EXPECT_EQ(f.depth, 10);
  EXPECT_EQ(f.ratio, 0.0f);
  EXPECT_EQ(f.scale, 2e3);
  EXPECT_EQ(f.inner.count, 2u);
  EXPECT_TRUE(parse({{"fast", "on"}}).fast);
}

TEST(OptionTable, OutOfRangeValuesNameTheStructureKeyValueAndRange) {
  struct Case {
    const char* key;
    const char* value;
    const char* range;
  };
  for (const Case& c : {Case{"depth", "-1", "[0, 10]"}, Case{"depth", "11", "[0, 10]"}, Case{"ratio", "1", "[0, 1)"},
                        Case{"ratio", "-0.5", "[0, 1)"}, Case{"scale", "0", "(0, inf)"}, Case{"count", "65", "[2, 64]"},
                        Case{"count", "-3", "[2, 64]"}}) {
    const std::string message = error_message([&] { parse({{c.key, c.value}}); });
    EXPECT_TRUE(contains(message, std::string("fake: ") + c.key + "=" + c.value + " is outside " + c.range))
        << message;
  }
  // A float member is checked after rounding: 0.99999999 rounds to 1.0f, outside [0, 1).
  EXPECT_TRUE(contains(error_message([] { parse({{"ratio", "0.99999999"}}); }), "ratio=0.99999999"));
  EXPECT_TRUE(contains(error_message([] { parse({{"fast", "1"}, {"shape", "box"}}); }), "balls only"));
}

TEST(OptionTable, CheckNamesTheMemberValueOfAHandBuiltStruct) {
  Fake f;
  EXPECT_NO_THROW(fake_table().check(f));
  f.inner.count = 1;
  EXPECT_TRUE(contains(error_message([&] { fake_table().check(f); }), "fake: count=1 is outside [2, 64]"));
  f = Fake{};
  f.scale = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(contains(error_message([&] { fake_table().check(f); }), "fake: scale=nan is outside (0, inf)"));
  f = Fake{};
  f.shape = static_cast<Shape>(7);
  EXPECT_TRUE(contains(error_message([&] { fake_table().check(f); }), "shape"));
}

/// The lower and upper ends of a range text "[lo, hi)" and whether each is open.
struct Ends {
  std::string lo, hi;
  bool lo_open, hi_open;
};
Ends ends(const std::string& range) {
  const auto comma = range.find(", ");
  return {range.substr(1, comma - 1), range.substr(comma + 2, range.size() - comma - 3), range.front() == '(',
          range.back() == ')'};
}

std::string outside(const std::string& bound, bool below, OptionType type) {
  if (type == OptionType::integer) return std::to_string(std::stoll(bound) + (below ? -1 : 1));
  const double v = std::stod(bound);
  char text[64];
  std::snprintf(text, sizeof text, "%.17g", below ? v - 1.0 - std::abs(v) : v + 1.0 + std::abs(v));
  return text;
}

TEST(OptionTable, EveryStructureEnforcesEachRangeAtBothEnds) {
  int ranges = 0;
  for (const auto& info : accelerator_registry()) {
    if (info.comparison) continue;  // another library: creating it starts its own device
    for (const auto& option : info.options) {
      if (option.range.empty()) continue;
      ++ranges;
      const Ends e = ends(option.range);
      const auto spec = [&](const std::string& value) { return info.name + ":" + option.key + "=" + value; };
      for (const bool low : {true, false}) {
        const std::string& bound = low ? e.lo : e.hi;
        if (bound == "inf" || bound == "-inf") continue;
        const bool open = low ? e.lo_open : e.hi_open;
        if (open) {
          EXPECT_THROW(make_accelerator(spec(bound)), Error) << spec(bound);
        } else {
          EXPECT_NO_THROW(make_accelerator(spec(bound))) << spec(bound);
        }
        const std::string beyond = spec(outside(bound, low, option.type));
        const std::string message = error_message([&] { make_accelerator(beyond); });
        EXPECT_TRUE(contains(message, option.key)) << beyond << ": " << message;
      }
    }
  }
  EXPECT_GE(ranges, 20);
}

TEST(OptionTable, DirectlyConstructedStructuresRunTheSameChecks) {
  const auto throws_naming = [](const char* what, auto make) {
    const std::string message = error_message(make);
    EXPECT_TRUE(contains(message, what)) << message;
  };
  throws_naming("kdtree: max_depth=-1", [] { KdTree(KdTreeOptions{.max_depth = -1}); });
  throws_naming("kdtree: empty_bonus=1", [] { KdTree(KdTreeOptions{.empty_bonus = 1.0f}); });
  throws_naming("bsp: leaf_size=0", [] { BspTree(BspTreeOptions{.leaf_size = 0}); });
  throws_naming("grid: density=0", [] { UniformGrid(UniformGridOptions{.density = 0.0}); });
  throws_naming("grid2: max_leaf_resolution=300",
                [] { TwoLevelGrid(TwoLevelGridOptions{.max_leaf_resolution = 300}); });
  throws_naming("octree: max_prims=0", [] {
    OctreeOptions o;
    o.max_prims = 0;
    Octree{o};
  });
  throws_naming("bvh: bins=1", [] {
    BvhOptions o;
    o.bin_count = 1;
    Bvh<AabbVolume>{o};
  });
  throws_naming("bvh_wide: presplit=5", [] { wide::WideBvh(wide::WideBvhOptions{.presplit = 5.0f}); });
  throws_naming("not width=4", [] { wide::WideBvh(wide::WideBvhOptions{.width = 4, .isa = wide::WideIsa::avx2}); });
  throws_naming("bvh_wide: width=", [] { wide::WideBvh(wide::WideBvhOptions{.width = 6}); });
  EXPECT_NO_THROW(KdTree{});
  EXPECT_NO_THROW(wide::WideBvh{});
}

}  // namespace
}  // namespace rayaccel
