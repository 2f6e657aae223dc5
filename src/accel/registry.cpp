// Registry lookup, spec parsing, option validation, and loading a saved structure of any registered format.
#include "rayaccel/accel/registry.h"

#include <algorithm>
#include <fstream>
#include <mutex>
#include <string>

#include "rayaccel/accel/registry_extension.h"
#include "rayaccel/core/error.h"
#include "rayaccel/core/number_text.h"

namespace rayaccel {

namespace {

std::string join(const std::vector<std::string>& items) {
  std::string out;
  for (const auto& item : items) out += (out.empty() ? "" : ", ") + item;
  return out;
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

}  // namespace

const char* to_string(OptionType type) {
  switch (type) {
    case OptionType::choice: return "choice";
    case OptionType::integer: return "integer";
    case OptionType::real: return "real";
    case OptionType::boolean: return "boolean";
  }
  return "?";
}

const std::string& OptionValues::get(const std::string& key) const {
  auto it = values_.find(key);
  if (it == values_.end()) throw Error("option '" + key + "' is not defined for this structure");
  return it->second;
}

long long OptionValues::get_int(const std::string& key) const {
  const auto v = parse_integer(get(key));
  if (!v) throw Error("option '" + key + "': '" + get(key) + "' is not an integer");
  return *v;
}

double OptionValues::get_real(const std::string& key) const {
  const auto v = parse_real(get(key));
  if (!v) throw Error("option '" + key + "': '" + get(key) + "' is not a number");
  return *v;
}

bool OptionValues::get_bool(const std::string& key) const {
  const auto v = parse_bool(get(key));
  if (!v) throw Error("option '" + key + "': '" + get(key) + "' is not a boolean");
  return *v;
}

namespace {

/// Hooks of add_registry_hook(); `sealed` once the registry is built.
struct RegistryHooks {
  std::mutex mutex;
  std::vector<RegistryHook> hooks;
  bool sealed = false;
};

RegistryHooks& registry_hooks() {
  static RegistryHooks hooks;
  return hooks;
}

}  // namespace

void add_registry_hook(RegistryHook hook) {
  RegistryHooks& h = registry_hooks();
  const std::lock_guard lock(h.mutex);
  if (std::find(h.hooks.begin(), h.hooks.end(), hook) != h.hooks.end()) return;
  if (h.sealed) {
    throw Error("add_registry_hook: the accelerator registry is already in use; add structures before anything "
                "uses it (first thing in main)");
  }
  h.hooks.push_back(hook);
}

const std::vector<AcceleratorInfo>& accelerator_registry() {
  static const std::vector<AcceleratorInfo> registry = [] {
    std::vector<AcceleratorInfo> r;
    register_builtin_accelerators(r);
    RegistryHooks& h = registry_hooks();
    const std::lock_guard lock(h.mutex);
    h.sealed = true;
    for (const RegistryHook hook : h.hooks) hook(r);
    return r;
  }();
  return registry;
}

const AcceleratorInfo& find_accelerator(std::string_view name) {
  std::vector<std::string> names;
  for (const auto& info : accelerator_registry()) {
    if (info.name == name) return info;
    names.push_back(info.name);
  }
  throw Error("unknown accelerator '" + std::string(name) + "'; known: " + join(names));
}

bool has_accelerator(std::string_view name) {
  for (const auto& info : accelerator_registry()) {
    if (info.name == name) return true;
  }
  return false;
}

std::vector<std::string> accelerator_variant_names() {
  std::vector<std::string> out;
  for (const auto& info : accelerator_registry()) {
    if (info.comparison) continue;
    if (info.variants.empty()) {
      out.push_back(info.name);
    } else {
      out.insert(out.end(), info.variants.begin(), info.variants.end());
    }
  }
  return out;
}

AcceleratorSpec parse_accelerator_spec(std::string_view spec) {
  AcceleratorSpec out;
  const auto colon = spec.find(':');
  out.name = std::string(trim(spec.substr(0, colon)));
  if (out.name.empty()) throw Error("accelerator spec '" + std::string(spec) + "' has no name");
  if (colon == std::string_view::npos) return out;
  std::string_view rest = spec.substr(colon + 1);
  while (!rest.empty()) {
    const auto comma = rest.find(',');
    const std::string_view item = trim(rest.substr(0, comma));
    rest = comma == std::string_view::npos ? std::string_view{} : rest.substr(comma + 1);
    if (item.empty()) continue;
    const auto eq = item.find('=');
    if (eq == std::string_view::npos) {
      throw Error("accelerator spec '" + std::string(spec) + "': option '" + std::string(item) +
                  "' is not of the form key=value");
    }
    const std::string key(trim(item.substr(0, eq)));
    const std::string value(trim(item.substr(eq + 1)));
    if (out.options.count(key)) {
      throw Error("accelerator spec '" + std::string(spec) + "': option '" + key + "' is given twice");
    }
    out.options[key] = value;
  }
  return out;
}

OptionValues resolve_options(const AcceleratorInfo& info, const std::map<std::string, std::string>& given) {
  std::map<std::string, std::string> values;
  std::vector<std::string> known;
  for (const auto& opt : info.options) {
    values[opt.key] = opt.default_value;
    known.push_back(opt.key);
  }
  for (const auto& [key, value] : given) {
    const OptionSpec* spec = nullptr;
    for (const auto& opt : info.options) {
      if (opt.key == key) spec = &opt;
    }
    if (!spec) {
      throw Error("accelerator '" + info.name + "' has no option '" + key + "'; known options: " +
                  (known.empty() ? std::string("(none)") : join(known)));
    }
    bool ok = true;
    std::string expected;
    switch (spec->type) {
      case OptionType::choice: {
        ok = false;
        for (const auto& c : spec->choices) ok = ok || c == value;
        expected = "one of " + join(spec->choices);
        break;
      }
      case OptionType::integer: {
        ok = parse_integer(value).has_value();
        expected = "an integer";
        break;
      }
      case OptionType::real: {
        ok = parse_real(value).has_value();
        expected = "a finite number";
        break;
      }
      case OptionType::boolean: {
        ok = parse_bool(value).has_value();
        expected = "true or false";
        break;
      }
    }
    if (!ok) {
      throw Error("accelerator '" + info.name + "', option '" + key + "': '" + value + "' is not " + expected);
    }
    values[key] = value;
  }
  return OptionValues(std::move(values));
}

std::unique_ptr<Accelerator> make_accelerator(std::string_view spec_text) { return make_accelerator(spec_text, {}); }

std::unique_ptr<Accelerator> make_accelerator(std::string_view spec_text,
                                              const std::map<std::string, std::string>& fallback) {
  AcceleratorSpec spec = parse_accelerator_spec(spec_text);
  const AcceleratorInfo& info = find_accelerator(spec.name);
  for (const auto& [key, value] : fallback) {
    for (const auto& option : info.options) {
      if (option.key == key) spec.options.try_emplace(key, value);
    }
  }
  const OptionValues options = resolve_options(info, spec.options);
  auto accel = info.create(options);
  accel->set_spec(std::string(trim(spec_text)));
  return accel;
}

std::unique_ptr<Accelerator> load_accelerator(const std::filesystem::path& path, const Scene& scene) {
  const std::string where = "saved structure '" + path.string() + "': ";
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw Error(where + "cannot be opened for reading (not a regular file, or missing)");
  }
  std::ifstream in(path, std::ios::binary);
  std::vector<std::byte> head(kSavedHeadBytes);
  in.read(reinterpret_cast<char*>(head.data()), static_cast<std::streamsize>(head.size()));
  if (in.bad()) throw Error(where + "read failed");
  head.resize(static_cast<std::size_t>(in.gcount()));
  for (const AcceleratorInfo& info : accelerator_registry()) {
    if (!info.saved_spec) continue;
    const std::string spec = info.saved_spec(head);
    if (spec.empty()) continue;
    std::unique_ptr<Accelerator> accel;
    try {
      accel = make_accelerator(spec);
    } catch (const Error& e) {
      throw Error(where + "its header names no valid structure (" + e.what() + ")");
    }
    accel->load(path, scene);
    return accel;
  }
  std::vector<std::string> formats;
  for (const AcceleratorInfo& info : accelerator_registry()) {
    if (info.saved_spec) formats.push_back(info.name);
  }
  throw Error(where + "not a saved rayaccel structure (the formats known: " + join(formats) + ")");
}

}  // namespace rayaccel
