// `rayaccel info SCENE`: what a scene holds (kind, primitive counts, invalid and degenerate primitives, bounds) and
// how long it took to load.
#include <fmt/core.h>

#include <memory>
#include <string>

#include "cli_common.h"
#include "commands.h"

namespace rayaccel::cli {

Command add_info_command(CLI::App& root) {
  auto scene_spec = std::make_shared<std::string>();
  CLI::App* app = root.add_subcommand("info", "Describe a scene: kind, primitive counts, bounds, load time");
  app->add_option("scene", *scene_spec, "Mesh file (PLY, OBJ, glTF, ...) or builtin:NAME[:key=value,...]")
      ->required();
  return {app, [scene_spec] {
            const Stopwatch clock;
            const Scene scene = load_scene_checked(*scene_spec);
            const double load_ms = clock.milliseconds();
            const AABB& b = scene.bounds();
            fmt::print("scene:       {}\n", scene.name());
            fmt::print("kind:        {}\n", to_string(scene.kind()));
            fmt::print("primitives:  {}\n", scene.primitive_count());
            fmt::print("invalid:     {}\n", scene.invalid_count());
            fmt::print("degenerate:  {}\n", scene.degenerate_count());
            if (scene.kind() == PrimitiveKind::triangles) fmt::print("vertices:    {}\n", scene.vertex_count());
            if (b.is_empty()) {
              fmt::print("bounds:      empty\n");
            } else {
              fmt::print("bounds:      ({:g}, {:g}, {:g}) - ({:g}, {:g}, {:g})\n", b.lo.x, b.lo.y, b.lo.z, b.hi.x, b.hi.y,
                         b.hi.z);
            }
            fmt::print("memory:      {} bytes\n", scene.memory_bytes());
            fmt::print("load time:   {:.2f} ms\n", load_ms);
            return 0;
          }};
}

}  // namespace rayaccel::cli
