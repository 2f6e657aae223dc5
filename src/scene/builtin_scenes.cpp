// The built-in scene table: names, documented parameters with their ranges, validation, and the compositions
// (teapot in a stadium, the default scene) assembled from the generators in procedural_*.cpp.
#include "rayaccel/scene/builtin_scenes.h"

#include <charconv>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <string>
#include <system_error>

#include "procedural.h"
#include "rayaccel/core/error.h"

namespace rayaccel {

namespace procedural {

void append_mesh(TriangleMesh& dst, const TriangleMesh& src, float scale, Vec3 offset) {
  const auto base = static_cast<std::uint32_t>(dst.vertices.size());
  dst.vertices.reserve(dst.vertices.size() + src.vertices.size());
  for (const Vec3& p : src.vertices) dst.vertices.push_back(p * scale + offset);
  dst.triangles.reserve(dst.triangles.size() + src.triangles.size());
  for (const auto& t : src.triangles) dst.triangles.push_back({base + t[0], base + t[1], base + t[2]});
}

}  // namespace procedural

namespace {

struct ParamSpec {
  std::string key;
  std::string default_value;
  bool integer = true;
  double lo = 0.0;  ///< inclusive range of valid values
  double hi = 0.0;
};

/// Validated parameter values of one scene (every declared key present).
class Params {
 public:
  std::map<std::string, double> values;
  int integer(const std::string& key) const { return static_cast<int>(values.at(key)); }
  float real(const std::string& key) const { return static_cast<float>(values.at(key)); }
  std::uint64_t seed() const { return static_cast<std::uint64_t>(values.at("seed")); }
};

struct SceneEntry {
  std::string name;
  std::string description;
  std::vector<ParamSpec> params;
  std::function<Scene(const Params&)> make;
};

constexpr double kMaxSeed = 9007199254740992.0;  // 2^53: every seed is exact in a double
constexpr double kHuge = 1e30;
constexpr double kTiny = 1e-30;

ParamSpec seed_param(const char* value = "1") { return {"seed", value, true, 0.0, kMaxSeed}; }

Scene make_teapot_stadium(const Params& p) {
  // The dense object: a (2,3) torus-knot tube about 2.2 units across standing on the field of a stadium whose
  // extent is `stadium` units (1000 by default, so the object is ~1/500 of the scene).
  constexpr float kScale = 0.3f, kTube = 0.6f;
  if (static_cast<long long>(p.integer("segments")) * p.integer("tube") > (1 << 24)) {
    throw Error("builtin scene 'teapot_stadium': segments=" + std::to_string(p.integer("segments")) +
                " times tube=" + std::to_string(p.integer("tube")) + " exceeds 2^24 vertices");
  }
  TriangleMesh mesh = procedural::torus_knot(2, 3, p.integer("segments"), p.integer("tube"), kTube, kScale);
  for (Vec3& v : mesh.vertices) v.y += (1.0f + kTube) * kScale;
  procedural::append_mesh(mesh, procedural::stadium(p.real("stadium"), 64, 6));
  return Scene::from_mesh(std::move(mesh), "teapot_stadium");
}

Scene make_default(const Params& p) {
  // Fractal ground 16 units wide with three objects resting on it: a Sierpinski tetrahedron, a tessellated sphere
  // and a torus knot (about 13.5k triangles).
  TriangleMesh mesh = procedural::mountain(6, 16.0f, 0.08f, 0.55f, p.seed());
  auto ground = [&](float x, float z, float radius) { return procedural::highest_point_near(mesh, x, z, radius); };
  constexpr float kEdge = 5.0f;
  const TriangleMesh tetra = procedural::sierpinski(4, kEdge);
  const TriangleMesh ball = procedural::icosphere(3, 1.6f);
  constexpr float kKnotScale = 0.45f, kKnotTube = 0.6f;
  const TriangleMesh knot = procedural::torus_knot(2, 3, 192, 8, kKnotTube, kKnotScale);
  const float tetra_y = ground(-3.5f, -1.0f, kEdge / std::numbers::sqrt3_v<float>);
  const float ball_y = ground(3.5f, 0.5f, 1.6f) + 1.6f;
  const float knot_y = ground(0.5f, 4.0f, 3.6f * kKnotScale) + (1.0f + kKnotTube) * kKnotScale;
  procedural::append_mesh(mesh, tetra, 1.0f, {-3.5f, tetra_y, -1.0f});
  procedural::append_mesh(mesh, ball, 1.0f, {3.5f, ball_y, 0.5f});
  procedural::append_mesh(mesh, knot, 1.0f, {0.5f, knot_y, 4.0f});
  return Scene::from_mesh(std::move(mesh), "default");
}

Scene make_glass(const Params& p) {
  // A floor square (triangles 0 and 1, the layout default_materials() relies on) with a closed ball resting on it.
  const float half = static_cast<float>(p.real("floor")) * 0.5f;
  TriangleMesh mesh;
  mesh.vertices = {{-half, 0.0f, -half}, {half, 0.0f, -half}, {half, 0.0f, half}, {-half, 0.0f, half}};
  mesh.triangles = {{0, 2, 1}, {0, 3, 2}};
  procedural::append_mesh(mesh, procedural::icosphere(p.integer("level"), 1.0f), 1.0f, {0.0f, 1.0f, 0.0f});
  return Scene::from_mesh(std::move(mesh), "glass");
}

const std::vector<SceneEntry>& scene_table() {
  static const std::vector<SceneEntry> table = {
      {"default",
       "the README's main scene: fractal ground with a Sierpinski tetrahedron, a sphere and a torus knot (13,568 "
       "triangles)",
       {seed_param()},
       make_default},
      {"sphereflake",
       "Haines' SPD sphereflake: analytic spheres, 9 children per sphere, sum of 9^i for i <= level spheres",
       {{"level", "4", true, 0, 7}, {"radius", "1", false, kTiny, kHuge}},
       [](const Params& p) {
         return Scene::from_spheres(procedural::sphereflake(p.integer("level"), p.real("radius")), "sphereflake");
       }},
      {"mountain",
       "fractal mountain by midpoint displacement, 2*4^level triangles over a size x size square",
       {{"level", "7", true, 0, 11},
        {"size", "100", false, kTiny, kHuge},
        {"height", "0.25", false, 0, 10},
        {"roughness", "0.5", false, 0, 1},
        seed_param()},
       [](const Params& p) {
         return Scene::from_mesh(procedural::mountain(p.integer("level"), p.real("size"), p.real("height"),
                                                      p.real("roughness"), p.seed()),
                                 "mountain");
       }},
      {"sierpinski",
       "Sierpinski tetrahedron: 4^level tetrahedra, 4^(level+1) triangles",
       {{"level", "6", true, 0, 9}, {"edge", "1", false, kTiny, kHuge}},
       [](const Params& p) {
         return Scene::from_mesh(procedural::sierpinski(p.integer("level"), p.real("edge")), "sierpinski");
       }},
      {"teapot_stadium",
       "a dense closed (2,3) torus-knot tube (2*segments*tube triangles) in a huge sparse stadium (1,568 triangles)",
       {{"segments", "1024", true, 3, 1 << 20}, {"tube", "12", true, 3, 1024}, {"stadium", "1000", false, 1, kHuge}},
       make_teapot_stadium},
      {"slivers",
       "count long thin triangles (length 2, length/width = aspect) at random in [-1,1]^3",
       {{"count", "10000", true, 0, 1 << 24}, {"aspect", "1000", false, 1, 1e7}, seed_param()},
       [](const Params& p) {
         return Scene::from_mesh(procedural::slivers(p.integer("count"), 1.0f, p.real("aspect"), p.seed()),
                                 "slivers");
       }},
      {"soup",
       "count random triangles in [-1,1]^3, vertices up to size from their centre per axis",
       {{"count", "10000", true, 0, 1 << 24}, {"size", "0.05", false, 0, 10}, seed_param()},
       [](const Params& p) {
         return Scene::from_mesh(procedural::soup(p.integer("count"), p.real("size"), p.seed()), "soup");
       }},
      {"glass",
       "a glass ball (subdivided icosahedron of radius 1, 20*4^level triangles) resting on a floor square; `render "
       "--mode whitted` shades it as glass",
       {{"level", "4", true, 0, 8}, {"floor", "8", false, 2.5, kHuge}},
       make_glass},
      {"sphere",
       "closed watertight sphere: subdivided icosahedron with shared vertices, 20*4^level triangles",
       {{"level", "4", true, 0, 8}, {"radius", "1", false, kTiny, kHuge}},
       [](const Params& p) {
         return Scene::from_mesh(procedural::icosphere(p.integer("level"), p.real("radius")), "sphere");
       }},
  };
  return table;
}

std::string join_names(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

std::string format_bound(double v) {
  if (v == kMaxSeed) return "2^53";
  if (v == kHuge) return "1e30";
  if (v == kTiny) return "1e-30";
  std::string s = std::to_string(v);
  s.erase(s.find_last_not_of('0') + 1);
  if (s.back() == '.') s.pop_back();
  return s;
}

/// Parses `text` as the parameter's type; throws Error naming the scene, key and value when it is not valid.
double parse_value(const SceneEntry& scene, const ParamSpec& spec, const std::string& text) {
  double value = std::numeric_limits<double>::quiet_NaN();
  const char* first = text.data();
  const char* last = text.data() + text.size();
  bool ok = false;
  if (spec.integer) {
    long long v = 0;
    const auto [ptr, ec] = std::from_chars(first, last, v);
    ok = ec == std::errc{} && ptr == last && !text.empty();
    value = static_cast<double>(v);
  } else {
    const auto [ptr, ec] = std::from_chars(first, last, value);
    ok = ec == std::errc{} && ptr == last && !text.empty() && std::isfinite(value);
  }
  if (!ok || value < spec.lo || value > spec.hi) {
    throw Error("builtin scene '" + scene.name + "': " + spec.key + "='" + text + "' is not " +
                (spec.integer ? "an integer" : "a number") + " in [" + format_bound(spec.lo) + ", " +
                format_bound(spec.hi) + "]");
  }
  return value;
}

}  // namespace

const std::vector<BuiltinSceneInfo>& builtin_scenes() {
  static const std::vector<BuiltinSceneInfo> infos = [] {
    std::vector<BuiltinSceneInfo> out;
    for (const auto& entry : scene_table()) {
      BuiltinSceneInfo info{entry.name, entry.description, {}};
      for (const auto& spec : entry.params) info.defaults[spec.key] = spec.default_value;
      out.push_back(std::move(info));
    }
    return out;
  }();
  return infos;
}

Scene make_builtin_scene(std::string_view name, const std::map<std::string, std::string>& params) {
  const SceneEntry* entry = nullptr;
  std::vector<std::string> names;
  for (const auto& e : scene_table()) {
    names.push_back(e.name);
    if (e.name == name) entry = &e;
  }
  if (!entry) throw Error("unknown builtin scene '" + std::string(name) + "'; known: " + join_names(names));
  std::vector<std::string> keys;
  for (const auto& spec : entry->params) keys.push_back(spec.key);
  for (const auto& [key, value] : params) {
    bool known = false;
    for (const auto& k : keys) known = known || k == key;
    if (!known) {
      throw Error("builtin scene '" + entry->name + "' has no parameter '" + key + "'; known parameters: " +
                  (keys.empty() ? std::string("none") : join_names(keys)));
    }
  }
  Params values;
  for (const auto& spec : entry->params) {
    const auto it = params.find(spec.key);
    values.values[spec.key] = parse_value(*entry, spec, it != params.end() ? it->second : spec.default_value);
  }
  return entry->make(values);
}

}  // namespace rayaccel
