// make_double_accelerator(): "brute_force", or "bvh" with the float bvh entry's options (parsed and checked by the
// accelerator registry, so the keys, ranges and messages are the same), and the batch driver.
#include "rayaccel/double/double_accelerator.h"

#include <string>

#include "rayaccel/accel/accelerator.h"
#include "rayaccel/accel/registry.h"
#include "rayaccel/core/error.h"
#include "rayaccel/double/double_brute_force.h"
#include "rayaccel/double/double_bvh.h"

namespace rayaccel {

namespace detail {
void trace_batch_d(std::span<const RayD> rays, std::size_t outputs,
                   const std::function<void(std::size_t, std::size_t)>& body) {
  check_batch_sizes(rays.size(), outputs, 0);
  parallel_for_rays(rays.size(), body);
}
}  // namespace detail

std::vector<std::string> double_accelerator_names() { return {"brute_force", "bvh"}; }

std::unique_ptr<DoubleAccelerator> make_double_accelerator(std::string_view spec) {
  const AcceleratorSpec parsed = parse_accelerator_spec(spec);
  std::unique_ptr<DoubleAccelerator> made;
  if (parsed.name == "brute_force") {
    if (!parsed.options.empty()) {
      throw Error("double brute_force takes no options, got '" + parsed.options.begin()->first + "'");
    }
    made = std::make_unique<DoubleBruteForce>();
  } else if (parsed.name == "bvh") {
    const auto bv = parsed.options.find("bv");
    if (bv != parsed.options.end() && bv->second != "aabb") {
      throw Error("double bvh: bv must be aabb (the double traversal tests float boxes), got '" + bv->second + "'");
    }
    const OptionValues values = resolve_options(find_accelerator("bvh"), parsed.options);
    made = std::make_unique<DoubleBvh>(bvh_option_table().parse(values));
  } else {
    throw Error("unknown double structure '" + parsed.name + "'; known: brute_force, bvh");
  }
  made->set_spec(std::string(spec));
  return made;
}

}  // namespace rayaccel
