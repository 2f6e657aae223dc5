// Numbers and switches read from text (structure options, command-line values): the whole text must be the value,
// so "4x" or "" is rejected rather than read as 4 or 0. The registry and the CLI both read through these.
#pragma once

#include <optional>
#include <string_view>

namespace rayaccel {

/// A decimal integer that fills the whole text and fits in a long long.
std::optional<long long> parse_integer(std::string_view text);
/// A finite number (as std::stod reads it: decimal or hex float, optional sign) that fills the whole text.
std::optional<double> parse_real(std::string_view text);
/// 1/true/on/yes or 0/false/off/no.
std::optional<bool> parse_bool(std::string_view text);

}  // namespace rayaccel
