// Where the tests find the source tree, the built CLI and ../shared/scenes: defined in a file CMake generates into the
// build tree (tests/CMakeLists.txt), so no other test file's compile command names a path of this checkout.
#pragma once

namespace rayaccel::testing {

/// The checkout's root (its tests/, scripts/ and README.md).
const char* source_dir();
/// The rayaccel command-line tool of this build.
const char* cli_path();
/// ../shared/scenes beside the checkout.
const char* default_shared_scenes_dir();

}  // namespace rayaccel::testing
