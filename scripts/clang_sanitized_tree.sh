#!/usr/bin/env bash
# The Clang tree of CI's two sanitizer tiers, build-fuzz: AddressSanitizer + UndefinedBehaviorSanitizer and
# libFuzzer's coverage on every object, with the fuzz targets, the tests and the CLI. Configured here only, so that
# the fuzz tier (ci_fuzz.sh) and the ASan tier (ci_asan.sh) share its library objects. A unity build (batches of eight
# files per compilation: the library, the CLI and the tests each parse their headers a few times instead of once per
# file). Builds the targets named.
#   scripts/clang_sanitized_tree.sh TARGET...
set -euo pipefail
cd "$(dirname "$0")/.."
CC=clang CXX=clang++ cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_UNITY_BUILD=ON \
  -DRAYACCEL_SANITIZE=ON \
  -DRAYACCEL_BUILD_FUZZERS=ON -DRAYACCEL_BUILD_TESTS=ON -DRAYACCEL_BUILD_CLI=ON -DRAYACCEL_BUILD_BENCH=OFF \
  -DRAYACCEL_BUILD_PYTHON=OFF -DRAYACCEL_BUILD_SHARED=OFF -DRAYACCEL_INSTALL=OFF -DRAYACCEL_WITH_EMBREE=OFF
cmake --build build-fuzz --target "$@"
