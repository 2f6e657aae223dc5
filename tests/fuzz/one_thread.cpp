// Linked into every fuzz target: the library's parallel loops (TBB) run on the calling thread only, so that a run
// from a given corpus and seed visits the same code in the same order every time. libFuzzer's choice of the next
// input follows the coverage of the last ones, so a thread schedule in the coverage made CI's fixed-seed runs differ
// from one machine to the next (scripts/ci_fuzz.sh replays the same runs by count, not by time). Races are
// ThreadSanitizer's tier (scripts/ci_tsan.sh).
#include <tbb/global_control.h>

namespace {

const tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);

}  // namespace
