// Numbers and switches read from text (see number_text.h).
#include "rayaccel/core/number_text.h"

#include <charconv>
#include <cmath>
#include <exception>
#include <string>

namespace rayaccel {

std::optional<long long> parse_integer(std::string_view text) {
  long long out = 0;
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, out);
  if (text.empty() || ec != std::errc() || ptr != end) return std::nullopt;
  return out;
}

std::optional<double> parse_real(std::string_view text) {
  if (text.empty()) return std::nullopt;
  const std::string s(text);
  std::size_t used = 0;
  double out = 0;
  try {
    out = std::stod(s, &used);
  } catch (const std::exception&) {
    return std::nullopt;
  }
  if (used != s.size() || !std::isfinite(out)) return std::nullopt;
  return out;
}

std::optional<bool> parse_bool(std::string_view text) {
  if (text == "1" || text == "true" || text == "on" || text == "yes") return true;
  if (text == "0" || text == "false" || text == "off" || text == "no") return false;
  return std::nullopt;
}

}  // namespace rayaccel
