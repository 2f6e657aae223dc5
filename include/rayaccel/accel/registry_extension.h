// Structures registered from outside the library (the Embree comparison of rayaccel::compare): hooks that add
// registry entries after the built-in ones when the registry is first used.
#pragma once

#include <vector>

#include "rayaccel/accel/registry.h"

namespace rayaccel {

using RegistryHook = void (*)(std::vector<AcceleratorInfo>& registry);

/// Runs `hook` after the built-in registrations when the registry is first used. Call it before anything uses the
/// registry (first thing in main, or from a static initializer); afterwards a new hook throws Error, since the
/// registry never changes once in use. Adding a hook that is already added does nothing.
void add_registry_hook(RegistryHook hook);

}  // namespace rayaccel
