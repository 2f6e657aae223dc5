#!/usr/bin/env bash
# CI tier: the unit and conformance tests under AddressSanitizer + UndefinedBehaviorSanitizer (GCC), in build-asan.
# Builds only the test executable and the CLI it runs; the slow tier and the package test stay out.
set -euo pipefail
cd "$(dirname "$0")/.."
start=$(date +%s)
cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=Release -DRAYACCEL_SANITIZE=ON \
  -DRAYACCEL_BUILD_BENCH=OFF -DRAYACCEL_BUILD_PYTHON=OFF -DRAYACCEL_BUILD_SHARED=OFF -DRAYACCEL_INSTALL=OFF
cmake --build build-asan --target rayaccel_tests rayaccel_cli
built=$(date +%s)
# halt_on_error: the first report fails the test; detect_leaks stays on.
export ASAN_OPTIONS=halt_on_error=1:abort_on_error=1:detect_stack_use_after_return=0
export UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
ctest --test-dir build-asan --output-on-failure -j2 -L 'unit|conformance' --timeout 900
end=$(date +%s)
echo "ci_sanitizers: build $((built - start)) s, tests $((end - built)) s"
