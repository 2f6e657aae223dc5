// Internal to src/scene: the depth of a glTF file's node graph, read before assimp sees the file (assimp's glTF
// readers recurse once per level and overflow the stack on a chain some ten thousand nodes deep).
#pragma once

#include <filesystem>

namespace rayaccel::gltf {

/// The deepest node graph import accepts: far above real scenes (skeletons are tens of joints deep), far below the
/// depth at which assimp's recursion runs out of stack.
inline constexpr int kMaxNodeDepth = 1000;

/// For a glTF file (.gltf JSON of glTF 1 or 2, or a glTF 2 .glb's JSON chunk): throws Error naming the file
/// when its node graph is deeper than kMaxNodeDepth, has a cycle or a node with two parents, or its JSON nests
/// deeper than assimp's reader can follow. Any other file, and a glTF whose JSON does not parse (assimp then reports
/// it), passes unchecked.
void check_node_depth(const std::filesystem::path& path);

}  // namespace rayaccel::gltf
