// libFuzzer target: the structure spec parser (make_accelerator) and the built-in scene spec parser (load_scene
// with "builtin:..."), each on the input text. Built-in scenes that parse are built over only when small, so the
// target tests parsing and validation, not the time of a legal large scene.
#include <cstddef>
#include <cstdint>
#include <string>

#include "rayaccel/accel/registry.h"
#include "rayaccel/core/error.h"
#include "rayaccel/scene/import.h"

namespace {

/// False when the text asks for a large legal scene: a number above 500, or a level above 5 (every built-in scene
/// stays below ~70k primitives then). Such scenes are slow to generate, not wrong.
bool small_enough(const std::string& text) {
  for (std::size_t i = 0; i < text.size();) {
    if (text[i] < '0' || text[i] > '9') { ++i; continue; }
    double value = 0.0;
    const std::size_t start = i;
    while (i < text.size() && text[i] >= '0' && text[i] <= '9') value = value * 10 + (text[i++] - '0');
    if (value > 500) return false;
    if (value > 5 && start >= 6 && text.compare(start - 6, 6, "level=") == 0) return false;
  }
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size > 256) return 0;
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    rayaccel::make_accelerator(text);
  } catch (const rayaccel::Error&) {
  }
  // Scene specs: only builtin ones (a path would read arbitrary files), and only parameters within the limits the
  // parser itself enforces; a huge legal scene is not a finding.
  if (!small_enough(text)) return 0;
  try {
    const rayaccel::Scene scene = rayaccel::load_scene("builtin:" + text);
    if (scene.primitive_count() < 20000) {
      auto accel = rayaccel::make_accelerator("bvh");
      accel->build(scene);
    }
  } catch (const rayaccel::Error&) {
  }
  return 0;
}
