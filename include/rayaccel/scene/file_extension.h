// A file name's extension in lower case: what picks a mesh file's reader (ply_reader.h, import.h) and tells .rays
// from .rays64 (ray_io.h).
#pragma once

#include <filesystem>
#include <string>

namespace rayaccel {

/// The extension with its dot, in lower case (".ply" for "Bunny.PLY"); empty when there is none.
std::string lowercase_extension(const std::filesystem::path& path);

}  // namespace rayaccel
