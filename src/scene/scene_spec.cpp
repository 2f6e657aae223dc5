// Scene specs: "builtin:NAME[:key=value,...]" or a mesh file path (read by import_mesh()).
#include "rayaccel/scene/import.h"

#include <map>
#include <string>

#include "rayaccel/core/error.h"
#include "rayaccel/scene/builtin_scenes.h"

namespace rayaccel {

namespace {

/// "key=value,key=value" -> map; throws Error naming the spec for a malformed or repeated item.
std::map<std::string, std::string> parse_params(std::string_view spec, std::string_view text) {
  std::map<std::string, std::string> params;
  while (!text.empty()) {
    const auto comma = text.find(',');
    const std::string_view item = text.substr(0, comma);
    text = comma == std::string_view::npos ? std::string_view{} : text.substr(comma + 1);
    if (item.empty()) continue;
    const auto eq = item.find('=');
    if (eq == std::string_view::npos || eq == 0) {
      throw Error("scene spec '" + std::string(spec) + "': '" + std::string(item) + "' is not of the form key=value");
    }
    const std::string key(item.substr(0, eq));
    if (!params.emplace(key, std::string(item.substr(eq + 1))).second) {
      throw Error("scene spec '" + std::string(spec) + "': parameter '" + key + "' is given twice");
    }
  }
  return params;
}

}  // namespace

Scene load_scene(std::string_view spec, GeometryTable* geometries) {
  constexpr std::string_view kPrefix = "builtin:";
  if (spec.substr(0, kPrefix.size()) == kPrefix) {
    const std::string_view rest = spec.substr(kPrefix.size());
    const auto colon = rest.find(':');
    const std::string_view name = rest.substr(0, colon);
    const auto params = colon == std::string_view::npos ? std::map<std::string, std::string>{}
                                                        : parse_params(spec, rest.substr(colon + 1));
    Scene scene = make_builtin_scene(name, params);
    if (geometries) {
      *geometries = GeometryTable();
      geometries->add(static_cast<std::uint32_t>(scene.primitive_count()));
    }
    return scene;
  }
  if (spec.empty()) throw Error("empty scene spec: give a mesh file or builtin:NAME");
  const std::filesystem::path path(spec);
  return Scene::from_mesh(import_mesh(path, geometries), path.stem().string());
}

}  // namespace rayaccel
