#!/usr/bin/env bash
# CI tier: ThreadSanitizer on the parallel batch and packet queries (tests/sanitize/batch_threads_test.cpp), in
# build-tsan, at -O1 (ThreadSanitizer's usual level, and far less compile time than -O3). Configures the tests (they
# need the CLI configured) but builds only the library and that one executable. (A unity build did not pay here: 248 s
# against 233 s, its batches of the heaviest files finishing last.)
set -euo pipefail
cd "$(dirname "$0")/.."
start=$(date +%s)
cmake -S . -B build-tsan -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE="-O1 -DNDEBUG" \
  -DRAYACCEL_SANITIZE_THREAD=ON -DRAYACCEL_BUILD_CLI=ON -DRAYACCEL_BUILD_BENCH=OFF -DRAYACCEL_BUILD_PYTHON=OFF -DRAYACCEL_BUILD_SHARED=OFF \
  -DRAYACCEL_INSTALL=OFF -DRAYACCEL_WITH_EMBREE=OFF
cmake --build build-tsan --target rayaccel_tsan_test
built=$(date +%s)
export TSAN_OPTIONS="halt_on_error=1 second_deadlock_stack=1 suppressions=$PWD/tests/sanitize/tsan.supp"
build-tsan/bin/rayaccel_tsan_test
end=$(date +%s)
echo "ci_tsan: build $((built - start)) s, test $((end - built)) s"
