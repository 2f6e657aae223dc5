// The depth of a glTF file's node graph (gltf_depth.h): the JSON read with nlohmann's iterative parser, the graph
// walked with an explicit stack.
#include "gltf_depth.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "rayaccel/core/error.h"
#include "rayaccel/scene/file_extension.h"

namespace rayaccel::gltf {

namespace {

/// Throws Error "glTF file 'PATH': WHY" (appended piece by piece: GCC 12 warns, wrongly, about "..." + string&&).
[[noreturn]] void refuse(const std::filesystem::path& path, const std::string& why) {
  std::string message = "glTF file '";
  message += path.string();
  message += "': ";
  message += why;
  throw Error(message);
}

/// JSON nesting beyond this is refused: assimp's JSON reader recurses once per level.
constexpr int kMaxJsonNesting = 256;

std::uint32_t little_u32(const char* bytes) {
  std::uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = (v << 8) | static_cast<unsigned char>(bytes[i]);
  return v;
}

/// The file's JSON text: a .glb's first chunk when it is JSON (only that chunk is read), a .gltf (or extensionless)
/// file that starts with '{' whole; empty for anything else.
std::string json_text(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  char header[20] = {};
  in.read(header, sizeof header);
  const auto got = static_cast<std::size_t>(in.gcount());
  if (got == sizeof header && std::memcmp(header, "glTF", 4) == 0) {
    std::error_code ec;
    const std::uintmax_t size = std::filesystem::file_size(path, ec);
    const std::uint32_t length = little_u32(header + 12);
    if (ec || std::memcmp(header + 16, "JSON", 4) != 0 || length > size - sizeof header) return {};
    std::string json(length, '\0');
    in.read(json.data(), static_cast<std::streamsize>(length));
    return in ? json : std::string();
  }
  const std::string ext = lowercase_extension(path);
  if (ext != ".gltf" && !ext.empty()) return {};
  std::string text(header, got);
  text.append(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  const std::size_t first = text.find_first_not_of(" \t\r\n");
  return first != std::string::npos && text[first] == '{' ? text : std::string();
}

/// The children of every node, as node indices (glTF 2: an array of nodes with index lists; glTF 1: an object of
/// named nodes with name lists). Entries that name no node are left out (assimp reports them).
std::vector<std::vector<std::size_t>> node_children(const nlohmann::json& nodes) {
  std::vector<std::vector<std::size_t>> children(nodes.size());
  std::map<std::string, std::size_t> index_of;
  if (nodes.is_object()) {
    for (const auto& [name, node] : nodes.items()) index_of.emplace(name, index_of.size());
  }
  std::size_t i = 0;
  for (const auto& node : nodes) {
    const auto list = node.is_object() ? node.find("children") : node.end();
    if (list != node.end() && list->is_array()) {
      for (const auto& c : *list) {
        if (c.is_number_unsigned() && c.get<std::uint64_t>() < nodes.size()) {
          children[i].push_back(c.get<std::size_t>());
        } else if (c.is_string() && index_of.count(c.get<std::string>())) {
          children[i].push_back(index_of[c.get<std::string>()]);
        }
      }
    }
    ++i;
  }
  return children;
}

}  // namespace

void check_node_depth(const std::filesystem::path& path) {
  const std::string text = json_text(path);
  if (text.empty()) return;
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(text, [&](int depth, nlohmann::json::parse_event_t, nlohmann::json&) {
      if (depth > kMaxJsonNesting) {
        refuse(path, "its JSON nests more than " + std::to_string(kMaxJsonNesting) +
                    " levels deep, more than the glTF reader can follow");
      }
      return true;
    });
  } catch (const nlohmann::json::exception&) {
    return;  // not JSON: assimp says what is wrong with it
  }
  const auto nodes = doc.is_object() ? doc.find("nodes") : doc.end();
  if (nodes == doc.end() || !(nodes->is_array() || nodes->is_object())) return;
  const std::vector<std::vector<std::size_t>> children = node_children(*nodes);
  // glTF's nodes form trees: a node with two parents would be walked once per path (2^depth times down a lattice).
  std::vector<std::uint8_t> has_parent(children.size(), 0);
  for (const auto& list : children) {
    for (const std::size_t c : list) {
      if (has_parent[c]) {
        refuse(path, "node " + std::to_string(c) +
                    " is the child of two nodes (glTF's nodes form trees)");
      }
      has_parent[c] = 1;
    }
  }
  // Depth-first from every root with an explicit stack (node, next child); a node still unvisited after every root
  // lies on a cycle.
  std::vector<std::uint8_t> visited(children.size(), 0);
  std::size_t deepest = 0;
  for (std::size_t root = 0; root < children.size(); ++root) {
    if (has_parent[root]) continue;
    std::vector<std::pair<std::size_t, std::size_t>> stack{{root, 0}};
    visited[root] = 1;
    while (!stack.empty()) {
      deepest = std::max(deepest, stack.size());
      auto& [node, next] = stack.back();
      if (next == children[node].size()) {
        stack.pop_back();
        continue;
      }
      const std::size_t child = children[node][next++];
      visited[child] = 1;
      stack.emplace_back(child, 0);
    }
  }
  const auto unvisited = std::find(visited.begin(), visited.end(), 0);
  if (unvisited != visited.end()) {
    refuse(path, "node " + std::to_string(unvisited - visited.begin()) +
                " lies on a cycle of the node graph (a node is its own ancestor)");
  }
  if (deepest > static_cast<std::size_t>(kMaxNodeDepth)) {
    refuse(path, "its node hierarchy is " + std::to_string(deepest) +
                " levels deep; rayaccel reads at most " + std::to_string(kMaxNodeDepth));
  }
}

}  // namespace rayaccel::gltf
