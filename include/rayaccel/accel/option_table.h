// OptionTable<T>: a structure's options written once as rows (key, member, range, doc), from which the registry's
// OptionSpecs, the key=value parsing and the check() every constructor calls all come.
#pragma once

#include <charconv>
#include <cmath>
#include <concepts>
#include <cstdint>
#include <functional>
#include <memory>
#include <limits>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "rayaccel/accel/registry.h"
#include "rayaccel/core/error.h"

namespace rayaccel {

/// A real option's allowed interval; an open end excludes its bound. Values must be finite either way.
struct RealRange {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false;
  bool hi_open = false;

  static constexpr RealRange closed(double lo, double hi) { return {lo, hi, false, false}; }
  static constexpr RealRange at_least(double lo) { return {lo, std::numeric_limits<double>::infinity(), false, true}; }
  static constexpr RealRange positive() { return {0.0, std::numeric_limits<double>::infinity(), true, true}; }
  bool contains(double v) const {
    return std::isfinite(v) && (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi);
  }
  /// "[0, 1)", "(0, inf)".
  std::string text() const;
};

/// Shortest text that reads back as the same float or double ("15", "0.2", "1e-5").
std::string format_real(double value, bool as_float);

template <class T>
class OptionTable {
 public:
  /// The type of the field `Access` (a pointer to member, or a callable returning a reference) reaches in a T.
  template <class Access>
  using Value = std::remove_cvref_t<std::invoke_result_t<Access, T&>>;

  template <class Access>
  static decltype(auto) ref(const Access& member, T& t) { return std::invoke(member, t); }
  template <class Access>
  static auto ref(const Access& member, const T& t) { return std::invoke(member, const_cast<T&>(t)); }

  /// `structure` names the registry entry in error messages ("kdtree: max_depth=99 is outside [0, 64]").
  explicit OptionTable(std::string structure) : structure_(std::move(structure)) {}

  /// An integer member (any integral type) in [lo, hi]. `member` is a pointer to member or a callable returning a
  /// reference to the field (for nested structs).
  template <class Access>
  OptionTable& integer(std::string key, Access member, long long lo, long long hi, std::string doc) {
    using V = Value<Access>;
    static_assert(std::is_integral_v<V> && !std::is_same_v<V, bool>);
    std::string range = "[";
    range.append(std::to_string(lo)).append(", ").append(std::to_string(hi)).append("]");
    Row row;
    row.spec = {key, OptionType::integer, {}, std::move(doc), {}, range};
    row.format = [member](const T& t) { return std::to_string(ref(member, t)); };
    row.check = [s = structure_, key, member, lo, hi, range](const T& t) {
      const auto v = ref(member, t);
      if (!std::in_range<long long>(v) || static_cast<long long>(v) < lo || static_cast<long long>(v) > hi) {
        fail(s, key, std::to_string(v), "is outside " + range);
      }
    };
    row.assign = [s = structure_, key, member, lo, hi, range](T& t, const OptionValues& values) {
      const long long v = values.get_int(key);
      if (v < lo || v > hi) fail(s, key, values.get(key), "is outside " + range);
      ref(member, t) = static_cast<V>(v);
    };
    return add(std::move(row));
  }

  /// A float or double member inside `range`.
  template <class Access>
  OptionTable& real(std::string key, Access member, RealRange range, std::string doc) {
    using V = Value<Access>;
    static_assert(std::is_floating_point_v<V>);
    constexpr bool as_float = std::is_same_v<V, float>;
    Row row;
    row.spec = {key, OptionType::real, {}, std::move(doc), {}, range.text()};
    row.format = [member](const T& t) { return format_real(ref(member, t), as_float); };
    row.check = [s = structure_, key, member, range](const T& t) {
      const V v = ref(member, t);
      if (!range.contains(v)) fail(s, key, format_real(v, as_float), "is outside " + range.text());
    };
    row.assign = [s = structure_, key, member, range](T& t, const OptionValues& values) {
      const double v = values.get_real(key);
      // A float member is checked after rounding, so the value stored is the value checked.
      const V stored = static_cast<V>(v);
      if (!range.contains(stored)) fail(s, key, values.get(key), "is outside " + range.text());
      ref(member, t) = stored;
    };
    return add(std::move(row));
  }

  template <class Access>
  OptionTable& boolean(std::string key, Access member, std::string doc) {
    static_assert(std::is_same_v<Value<Access>, bool>);
    Row row;
    row.spec = {key, OptionType::boolean, {}, std::move(doc), {}, {}};
    row.format = [member](const T& t) { return std::string(ref(member, t) ? "true" : "false"); };
    row.check = [](const T&) {};
    row.assign = [key, member](T& t, const OptionValues& values) { ref(member, t) = values.get_bool(key); };
    return add(std::move(row));
  }

  /// A member that takes one of named values (an enum, or e.g. a width 0/4/8 named auto/4/8).
  template <class Access>
  OptionTable& choice(std::string key, Access member, std::vector<std::pair<std::string, Value<Access>>> choices,
                      std::string doc) {
    std::vector<std::string> names;
    for (const auto& c : choices) names.push_back(c.first);
    Row row;
    row.spec = {key, OptionType::choice, {}, std::move(doc), names, {}};
    row.format = [s = structure_, key, member, choices](const T& t) {
      for (const auto& c : choices) {
        if (c.second == ref(member, t)) return c.first;
      }
      fail(s, key, "(a value with no name)", "is not one of its choices");
    };
    row.check = [row_format = row.format](const T& t) { row_format(t); };
    row.assign = [key, member, choices](T& t, const OptionValues& values) {
      for (const auto& c : choices) {
        if (c.first == values.get(key)) ref(member, t) = c.second;
      }
    };
    return add(std::move(row));
  }

  /// A check that involves several options (e.g. one that applies only with another's value); throws Error.
  OptionTable& rule(std::function<void(const T&)> check) {
    rules_.push_back(std::move(check));
    return *this;
  }

  /// The rows as the registry's OptionSpecs, defaults printed from T{}.
  std::vector<OptionSpec> specs() const {
    const T defaults{};
    std::vector<OptionSpec> out;
    for (const Row& row : rows_) {
      out.push_back(row.spec);
      out.back().default_value = row.format(defaults);
    }
    return out;
  }

  /// T{} with every row's value taken from `values` (resolved by resolve_options(), so every key is present and
  /// of its type), then checked.
  T parse(const OptionValues& values) const {
    T t{};
    for (const Row& row : rows_) row.assign(t, values);
    check(t);
    return t;
  }

  /// Throws Error naming the structure, the key and the value of the first option outside its range.
  void check(const T& t) const {
    for (const Row& row : rows_) row.check(t);
    for (const auto& rule : rules_) rule(t);
  }

  const std::string& structure() const { return structure_; }

 private:
  struct Row {
    OptionSpec spec;
    std::function<std::string(const T&)> format;
    std::function<void(const T&)> check;
    std::function<void(T&, const OptionValues&)> assign;
  };

  OptionTable& add(Row row) {
    rows_.push_back(std::move(row));
    return *this;
  }

  [[noreturn]] static void fail(const std::string& structure, const std::string& key, const std::string& value,
                                const std::string& problem) {
    throw Error(structure + ": " + key + "=" + value + " " + problem);
  }

  std::string structure_;
  std::vector<Row> rows_;
  std::vector<std::function<void(const T&)>> rules_;
};

/// The registry entry of a structure whose options are all in `table`: named table.structure(), with the table's
/// OptionSpecs and a create() that makes Structure(table.parse(values)). `table` must outlive the registry (the
/// option-table functions return function-local statics).
template <class Structure, class O>
AcceleratorInfo registry_entry(const OptionTable<O>& table, std::string description,
                               std::vector<std::string> variants) {
  return {table.structure(), std::move(description), table.specs(), std::move(variants),
          [&table](const OptionValues& values) -> std::unique_ptr<Accelerator> {
            return std::make_unique<Structure>(table.parse(values));
          },
          false, {}};
}

}  // namespace rayaccel
