// The text an OptionTable prints: ranges and shortest round-trip reals (see option_table.h).
#include "rayaccel/accel/option_table.h"

#include <array>

namespace rayaccel {

std::string format_real(double value, bool as_float) {
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  std::array<char, 64> buffer{};
  const auto result = as_float ? std::to_chars(buffer.data(), buffer.data() + buffer.size(), static_cast<float>(value))
                               : std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
  std::string text(buffer.data(), result.ptr);
  // "1e-05" -> "1e-5": the exponent without the zero padding to_chars writes.
  const auto e = text.find('e');
  if (e != std::string::npos) {
    std::size_t digits = e + 1;
    if (digits < text.size() && (text[digits] == '-' || text[digits] == '+')) ++digits;
    while (digits + 1 < text.size() && text[digits] == '0') text.erase(digits, 1);
    if (text[e + 1] == '+') text.erase(e + 1, 1);
  }
  return text;
}

std::string RealRange::text() const {
  std::string text(lo_open ? "(" : "[");
  text.append(format_real(lo, false)).append(", ").append(format_real(hi, false)).append(hi_open ? ")" : "]");
  return text;
}

}  // namespace rayaccel
