// The benchmark executable's main (Google Benchmark). Kept in its own file so the bench folder has exactly one.
#include <benchmark/benchmark.h>

BENCHMARK_MAIN();
