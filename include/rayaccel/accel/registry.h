// The accelerator registry: structures by name, each with documented key=value options, created from a spec
// "name" or "name:key=value,key=value". Unknown names and keys are errors that list the known ones.
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "rayaccel/accel/accelerator.h"

namespace rayaccel {

enum class OptionType { choice, integer, real, boolean };
/// "choice", "integer", "real" or "boolean".
const char* to_string(OptionType type);

struct OptionSpec {
  std::string key;
  OptionType type = OptionType::integer;
  std::string default_value;
  std::string description;
  std::vector<std::string> choices;  ///< the allowed values of a choice option
  std::string range;                 ///< the allowed interval of a number ("[1, 255]", "(0, inf)"); empty otherwise
};

/// Option values as text after validation against the structure's OptionSpecs; every declared key has a value (its
/// default when not given). A structure's OptionTable turns them into its options struct.
class OptionValues {
 public:
  OptionValues() = default;
  explicit OptionValues(std::map<std::string, std::string> values) : values_(std::move(values)) {}
  const std::string& get(const std::string& key) const;
  long long get_int(const std::string& key) const;
  double get_real(const std::string& key) const;
  bool get_bool(const std::string& key) const;
  const std::map<std::string, std::string>& values() const { return values_; }

 private:
  std::map<std::string, std::string> values_;
};

struct AcceleratorInfo {
  std::string name;
  std::string description;  ///< one line
  std::vector<OptionSpec> options;
  /// Specs `rayaccel list --names` prints for this structure (every meaningful combination, e.g.
  /// "bvh:bv=obb,builder=ploc"); empty means just the name.
  std::vector<std::string> variants;
  std::function<std::unique_ptr<Accelerator>(const OptionValues&)> create;
  /// Another library's structure, for comparisons (Embree): created by spec like any other, but not among
  /// accelerator_variant_names() (so not in `list --names`, `--accel all` or the conformance suite).
  bool comparison = false;
  /// Structures with save(): given a file's first bytes (up to kSavedHeadBytes), the spec that loads it when the
  /// file is in this structure's format, else an empty string. load_accelerator() asks every entry.
  std::function<std::string(std::span<const std::byte> head)> saved_spec;
};

/// Bytes of a saved file that AcceleratorInfo::saved_spec sees (every format's header fits).
inline constexpr std::size_t kSavedHeadBytes = 256;

/// Every registered structure, brute force first.
const std::vector<AcceleratorInfo>& accelerator_registry();
/// Looks a structure up by name; throws Error listing the known names when there is none.
const AcceleratorInfo& find_accelerator(std::string_view name);
/// Whether a structure of this name is registered (e.g. "embree", which is only where it was found at build time).
bool has_accelerator(std::string_view name);
/// Every spec `rayaccel list --names` prints, in registry order (comparison entries left out).
std::vector<std::string> accelerator_variant_names();

/// A parsed spec: name plus given key=value pairs.
struct AcceleratorSpec {
  std::string name;
  std::map<std::string, std::string> options;
};
AcceleratorSpec parse_accelerator_spec(std::string_view spec);
/// Checks keys and values against the structure's options and fills in defaults; throws Error naming the bad key
/// or value and listing the known keys or allowed values.
OptionValues resolve_options(const AcceleratorInfo& info, const std::map<std::string, std::string>& given);

/// Creates an unbuilt accelerator from a spec such as "kdtree:builder=sah,leaf_size=4".
std::unique_ptr<Accelerator> make_accelerator(std::string_view spec);
/// As make_accelerator(spec), with `fallback` values for the options the structure has and the spec leaves out
/// (the CLI's --threads for a structure with a `threads` option of its own); fallback keys it lacks are ignored.
std::unique_ptr<Accelerator> make_accelerator(std::string_view spec,
                                              const std::map<std::string, std::string>& fallback);

/// Makes the structure saved in `path` by Accelerator::save() (a structure of whichever format the file holds) and
/// loads it over `scene`. Throws Error naming the file when it is missing or no registered structure recognises it,
/// and as Accelerator::load() for a truncated, wrong-version, corrupted or stale (other scene) file.
std::unique_ptr<Accelerator> load_accelerator(const std::filesystem::path& path, const Scene& scene);

/// Registration hooks, one per structure module, called in this order by accelerator_registry() (see
/// src/catalog/builtin_registry.cpp, the one file above every structure).
void register_builtin_accelerators(std::vector<AcceleratorInfo>& registry);

}  // namespace rayaccel
