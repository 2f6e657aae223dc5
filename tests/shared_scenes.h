// The rule for tests that read ../shared/scenes (the benchmark meshes and their MANIFEST.md): in a bare clone they
// are skipped with the missing file named; with RAYACCEL_REQUIRE_SHARED=1 in the environment (.ci/run sets it) a
// missing file fails the test instead, so CI cannot pass by skipping.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include "test_paths.h"

namespace rayaccel::testing {

/// ../shared/scenes beside the source tree, or the folder named by the environment variable RAYACCEL_SHARED_SCENES.
inline std::filesystem::path shared_scenes_dir() {
  const char* dir = std::getenv("RAYACCEL_SHARED_SCENES");
  return dir != nullptr && *dir != '\0' ? dir : default_shared_scenes_dir();
}

/// True when RAYACCEL_REQUIRE_SHARED is set to 1.
inline bool shared_scenes_required() {
  const char* value = std::getenv("RAYACCEL_REQUIRE_SHARED");
  return value != nullptr && std::string(value) == "1";
}

}  // namespace rayaccel::testing

/// In a test body: skips the test (or fails it under RAYACCEL_REQUIRE_SHARED=1) when `file` does not exist.
#define RAYACCEL_NEED_SHARED_FILE(file)                                                                       \
  do {                                                                                                        \
    const std::filesystem::path rayaccel_needed_file_ = (file);                                               \
    if (!std::filesystem::exists(rayaccel_needed_file_)) {                                                    \
      if (::rayaccel::testing::shared_scenes_required()) {                                                    \
        FAIL() << "shared scene file missing: " << rayaccel_needed_file_ << " (RAYACCEL_REQUIRE_SHARED=1)";   \
      }                                                                                                       \
      GTEST_SKIP() << "shared scene file missing: " << rayaccel_needed_file_                                  \
                   << " (clone the shared scenes beside the checkout; RAYACCEL_REQUIRE_SHARED=1 makes this a " \
                      "failure)";                                                                             \
    }                                                                                                         \
  } while (false)
