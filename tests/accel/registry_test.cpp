// Unit tests of the accelerator registry: spec parsing, option validation against declared types, error messages
// that name the culprit and list the known names or keys, and the shape of the real registry (brute force first,
// unique names, every listed variant creatable, every default valid).
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <string>

#include "rayaccel/accel/default_spec.h"
#include "rayaccel/accel/registry.h"
#include "rayaccel/accel/registry_extension.h"
#include "rayaccel/compare/embree_accelerator.h"
#include "rayaccel/core/error.h"
#include "../error_message.h"

namespace rayaccel {
namespace {

using testing::contains;
using testing::error_message;

/// A registry entry with one option of each type, for option validation.
AcceleratorInfo fake_entry() {
  AcceleratorInfo info;
  info.name = "fake";
  info.description = "test entry";
  info.options = {{"bv", OptionType::choice, "aabb", "volume", {"aabb", "obb"}, {}},
                  {"leaf_size", OptionType::integer, "4", "primitives per leaf", {}, {}},
                  {"ratio", OptionType::real, "0.5", "a ratio", {}, {}},
                  {"fast", OptionType::boolean, "false", "a switch", {}, {}}};
  return info;
}

TEST(RegistrySpec, ParsesNameAndOptions) {
  const AcceleratorSpec plain = parse_accelerator_spec("bvh");
  EXPECT_EQ(plain.name, "bvh");
  EXPECT_TRUE(plain.options.empty());
  const AcceleratorSpec full = parse_accelerator_spec(" bvh : bv = obb , builder=ploc,");
  EXPECT_EQ(full.name, "bvh");
  ASSERT_EQ(full.options.size(), 2u);
  EXPECT_EQ(full.options.at("bv"), "obb");
  EXPECT_EQ(full.options.at("builder"), "ploc");
  EXPECT_TRUE(parse_accelerator_spec("bvh:").options.empty());
}

TEST(RegistrySpec, MalformedSpecsAreErrors) {
  EXPECT_TRUE(contains(error_message([] { parse_accelerator_spec(""); }), "no name"));
  EXPECT_TRUE(contains(error_message([] { parse_accelerator_spec(":a=1"); }), "no name"));
  EXPECT_TRUE(contains(error_message([] { parse_accelerator_spec("bvh:leaf"); }), "'leaf'"));
  EXPECT_TRUE(contains(error_message([] { parse_accelerator_spec("bvh:a=1,a=2"); }), "twice"));
}

TEST(RegistryOptions, DefaultsFillEveryKey) {
  const OptionValues o = resolve_options(fake_entry(), {});
  EXPECT_EQ(o.get("bv"), "aabb");
  EXPECT_EQ(o.get_int("leaf_size"), 4);
  EXPECT_DOUBLE_EQ(o.get_real("ratio"), 0.5);
  EXPECT_FALSE(o.get_bool("fast"));
  EXPECT_THROW(o.get("missing"), Error);
  const OptionValues given = resolve_options(fake_entry(), {{"bv", "obb"}, {"leaf_size", "-3"}, {"ratio", "2e-3"}, {"fast", "on"}});
  EXPECT_EQ(given.get("bv"), "obb");
  EXPECT_EQ(given.get_int("leaf_size"), -3);
  EXPECT_DOUBLE_EQ(given.get_real("ratio"), 2e-3);
  EXPECT_TRUE(given.get_bool("fast"));
}

TEST(RegistryOptions, UnknownKeyListsKnownKeys) {
  const std::string message = error_message([] { resolve_options(fake_entry(), {{"leafsize", "4"}}); });
  EXPECT_TRUE(contains(message, "'leafsize'")) << message;
  for (const char* key : {"bv", "leaf_size", "ratio", "fast"}) EXPECT_TRUE(contains(message, key)) << message;
  const std::string none = error_message([] { make_accelerator("brute_force:depth=3"); });
  EXPECT_TRUE(contains(none, "'depth'")) << none;
  EXPECT_TRUE(contains(none, "brute_force")) << none;
}

TEST(RegistryOptions, BadValuesNameTheValueAndTheExpectedType) {
  struct Case {
    const char* key;
    const char* value;
    const char* expected;
  };
  for (const Case& c : {Case{"bv", "kdop", "aabb, obb"}, Case{"leaf_size", "four", "integer"},
                        Case{"leaf_size", "4.5", "integer"}, Case{"leaf_size", "", "integer"},
                        Case{"ratio", "nan", "number"}, Case{"ratio", "inf", "number"}, Case{"ratio", "1.5x", "number"},
                        Case{"fast", "maybe", "true or false"}}) {
    const std::string message = error_message([&] { resolve_options(fake_entry(), {{c.key, c.value}}); });
    EXPECT_TRUE(contains(message, std::string("'") + c.value + "'")) << message;
    EXPECT_TRUE(contains(message, c.key)) << message;
    EXPECT_TRUE(contains(message, c.expected)) << message;
  }
}

TEST(RegistryLookup, UnknownNameListsKnownNames) {
  const std::string message = error_message([] { make_accelerator("octtree"); });
  EXPECT_TRUE(contains(message, "'octtree'")) << message;
  for (const auto& info : accelerator_registry()) EXPECT_TRUE(contains(message, info.name)) << message;
  EXPECT_THROW(find_accelerator("Brute_Force"), Error) << "names are case-sensitive";
}

TEST(RegistryLookup, BruteForceIsFirst) {
  ASSERT_FALSE(accelerator_registry().empty());
  EXPECT_EQ(accelerator_registry().front().name, "brute_force");
  ASSERT_FALSE(accelerator_variant_names().empty());
  EXPECT_EQ(accelerator_variant_names().front(), "brute_force");
  EXPECT_EQ(&find_accelerator("brute_force"), &accelerator_registry().front());
}

TEST(RegistryLookup, DefaultSpecIsAListedStructureOfRayaccel) {
  const std::string spec = default_accelerator_spec();
  const auto names = accelerator_variant_names();
  EXPECT_NE(std::find(names.begin(), names.end(), spec), names.end()) << spec;
  EXPECT_FALSE(find_accelerator(parse_accelerator_spec(spec).name).comparison);
  EXPECT_NE(spec, "brute_force");
  EXPECT_EQ(make_accelerator(spec)->spec(), spec);
}

TEST(RegistryLookup, MakeAcceleratorRecordsTheSpec) {
  const auto accel = make_accelerator("  brute_force  ");
  ASSERT_NE(accel, nullptr);
  EXPECT_EQ(accel->spec(), "brute_force");
}

TEST(RegistryContents, NamesAndVariantsAreUniqueAndCreatable) {
  std::set<std::string> names;
  for (const auto& info : accelerator_registry()) {
    EXPECT_TRUE(names.insert(info.name).second) << "duplicate name " << info.name;
    EXPECT_FALSE(info.description.empty()) << info.name;
    EXPECT_TRUE(info.create) << info.name;
    for (const auto& variant : info.variants) {
      EXPECT_EQ(parse_accelerator_spec(variant).name, info.name) << variant << " is listed under " << info.name;
    }
  }
  std::set<std::string> variants;
  for (const auto& spec : accelerator_variant_names()) {
    EXPECT_TRUE(variants.insert(spec).second) << "duplicate variant " << spec;
    std::unique_ptr<Accelerator> accel;
    EXPECT_NO_THROW(accel = make_accelerator(spec)) << spec;
    if (accel) {
      EXPECT_EQ(accel->spec(), spec);
    }
  }
}

TEST(RegistryContents, EveryDefaultIsAValidValue) {
  for (const auto& info : accelerator_registry()) {
    std::set<std::string> keys;
    for (const auto& option : info.options) {
      EXPECT_TRUE(keys.insert(option.key).second) << info.name << ": duplicate option " << option.key;
      EXPECT_FALSE(option.description.empty()) << info.name << "." << option.key;
      EXPECT_NO_THROW(resolve_options(info, {{option.key, option.default_value}}))
          << info.name << "." << option.key << " default '" << option.default_value << "'";
      if (option.type == OptionType::choice) {
        EXPECT_FALSE(option.choices.empty()) << info.name << "." << option.key;
      }
    }
  }
}

/// A structure added from outside the library, too late.
void register_late(std::vector<AcceleratorInfo>& registry) {
  AcceleratorInfo info;
  info.name = "late";
  registry.push_back(std::move(info));
}

TEST(Registry, HooksCloseOnceTheRegistryIsInUse) {
  ASSERT_FALSE(accelerator_registry().empty());
  const std::string message = error_message([] { add_registry_hook(register_late); });
  EXPECT_TRUE(contains(message, "already in use")) << message;
  EXPECT_FALSE(has_accelerator("late"));
#ifdef RAYACCEL_HAVE_EMBREE
  // The test binary adds "embree" before main (tests/compare/embree_registration.cpp), as the CLI does first thing.
  EXPECT_NO_THROW(enable_embree_comparison()) << "adding a hook already added does nothing";
  EXPECT_TRUE(has_accelerator("embree"));
#else
  EXPECT_FALSE(has_accelerator("embree"));
#endif
}

}  // namespace
}  // namespace rayaccel
