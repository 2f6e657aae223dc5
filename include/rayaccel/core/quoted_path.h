// How error messages name a file: in single quotes, as given.
#pragma once

#include <filesystem>
#include <string>

namespace rayaccel {

inline std::string quoted(const std::filesystem::path& path) { return "'" + path.string() + "'"; }

}  // namespace rayaccel
