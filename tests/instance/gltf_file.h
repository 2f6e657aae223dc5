// Small glTF 2.0 files written by tests (Khronos glTF 2.0 specification: one mesh of non-indexed triangles in a
// base64 data-URI buffer, placed by the caller's nodes), for the importers and the CLI's --instances.
#pragma once

#include <filesystem>
#include <span>
#include <string>

namespace rayaccel::testing {

/// Writes `path`: mesh 0 holds the triangles of `positions` (x y z per vertex, three vertices per triangle), and
/// the scene is the root nodes `roots` (a JSON array such as "[0, 1]") of `nodes` (a JSON array of node objects
/// that refer to mesh 0).
void write_gltf(const std::filesystem::path& path, std::span<const float> positions, const std::string& roots,
                const std::string& nodes);

}  // namespace rayaccel::testing
