// The test binary's registry has "embree" (rayaccel::compare) as the CLI's has: added before main, as
// add_registry_hook() requires.
#include "rayaccel/compare/embree_accelerator.h"

#ifdef RAYACCEL_HAVE_EMBREE
namespace {
[[maybe_unused]] const bool kEmbreeRegistered = (rayaccel::enable_embree_comparison(), true);
}  // namespace
#endif
