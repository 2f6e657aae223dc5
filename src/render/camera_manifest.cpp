// Standard cameras: the ```cameras block of the MANIFEST.md that sits beside the shared scene files.
#include <charconv>
#include <cstdint>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "rayaccel/core/error.h"
#include "rayaccel/render/camera.h"

namespace rayaccel {

namespace {

/// MANIFEST.md is read only up to this size.
constexpr std::uintmax_t kMaxManifestBytes = std::uintmax_t{1} << 20;

float parse_float(std::string_view text, const std::string& where) {
  float value = 0.0f;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(value)) {
    throw Error(where + ": '" + std::string(text) + "' is not a finite number");
  }
  return value;
}

Vec3 parse_vec3(std::string_view text, const std::string& where) {
  std::vector<std::string_view> parts;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = text.find(',', start);
    parts.push_back(text.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start));
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  if (parts.size() != 3) throw Error(where + ": '" + std::string(text) + "' is not three numbers x,y,z");
  return {parse_float(parts[0], where), parse_float(parts[1], where), parse_float(parts[2], where)};
}

/// Parses one camera line "NAME eye=x,y,z at=x,y,z up=x,y,z fov=DEG"; `where` is "file:line" for errors.
std::pair<std::string, Camera> parse_camera_line(const std::string& line, const std::string& where) {
  std::istringstream in(line);
  std::string name;
  in >> name;
  std::map<std::string, std::string> values;
  for (std::string token; in >> token;) {
    const std::size_t eq = token.find('=');
    if (eq == std::string::npos) throw Error(where + ": '" + token + "' is not key=value");
    const std::string key = token.substr(0, eq);
    if (key != "eye" && key != "at" && key != "up" && key != "fov") {
      throw Error(where + ": unknown key '" + key + "' (known: eye, at, up, fov)");
    }
    if (!values.emplace(key, token.substr(eq + 1)).second) throw Error(where + ": key '" + key + "' given twice");
  }
  for (const char* key : {"eye", "at", "up", "fov"}) {
    if (!values.count(key)) throw Error(where + ": camera '" + name + "' lacks " + key + "=");
  }
  Camera cam;
  cam.eye = parse_vec3(values["eye"], where);
  cam.at = parse_vec3(values["at"], where);
  cam.up = parse_vec3(values["up"], where);
  cam.fov_degrees = parse_float(values["fov"], where);
  if (!(cam.fov_degrees > 0.0f && cam.fov_degrees < 180.0f)) {
    throw Error(where + ": fov=" + values["fov"] + " is outside (0, 180) degrees");
  }
  if (length(cam.at - cam.eye) == 0.0f) throw Error(where + ": eye and at are the same point");
  if (cam.up == Vec3{}) throw Error(where + ": up is the zero vector");
  if (length(cross(cam.at - cam.eye, cam.up)) == 0.0f) {
    throw Error(where + ": up=" + values["up"] + " is parallel to the view direction (from eye to at)");
  }
  return {name, cam};
}

}  // namespace

// Beyond camera.h's list: an up parallel to the view is a malformed line too, and a manifest that is not a regular
// file (after symbolic links) or is over kMaxManifestBytes throws Error naming it, unread.
std::optional<Camera> standard_camera(const std::filesystem::path& scene_file) {
  const std::filesystem::path manifest = scene_file.parent_path() / "MANIFEST.md";
  std::error_code ec;
  const std::filesystem::file_status status = std::filesystem::status(manifest, ec);  // follows symbolic links
  if (!std::filesystem::exists(status)) return std::nullopt;
  // A side file the user did not name: only a regular file of sane size is read (a FIFO would block, /dev/zero
  // never end).
  if (!std::filesystem::is_regular_file(status)) {
    throw Error(manifest.string() + " (read for the scene's standard camera) is not a regular file");
  }
  const std::uintmax_t size = std::filesystem::file_size(manifest, ec);
  if (ec || size > kMaxManifestBytes) {
    throw Error(manifest.string() + " (read for the scene's standard camera) is larger than " +
                std::to_string(kMaxManifestBytes >> 20) + " MiB");
  }
  std::ifstream in(manifest);
  if (!in) throw Error("cannot open " + manifest.string() + " (read for the scene's standard camera)");
  const std::string stem = scene_file.stem().string();
  std::optional<Camera> found;
  bool in_block = false, saw_block = false;
  int line_number = 0, block_start = 0;
  for (std::string line; std::getline(in, line);) {
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::size_t first = line.find_first_not_of(" \t");
    const std::string_view trimmed =
        first == std::string::npos ? std::string_view{} : std::string_view(line).substr(first);
    if (!in_block) {
      if (!saw_block && trimmed.starts_with("```cameras")) {
        in_block = saw_block = true;
        block_start = line_number;
      }
      continue;
    }
    if (trimmed.starts_with("```")) {
      in_block = false;
      continue;
    }
    if (trimmed.empty()) continue;
    const std::string where = manifest.string() + ":" + std::to_string(line_number);
    auto [name, cam] = parse_camera_line(line, where);
    if (name == stem && !found) found = cam;
  }
  if (in_block) {
    throw Error(manifest.string() + ":" + std::to_string(block_start) + ": the ```cameras block is never closed");
  }
  return found;
}

}  // namespace rayaccel
