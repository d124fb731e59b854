// filter_probe.cpp — a harness whose every input breaks the contract, described the way
// the shape targets describe a violation. Linked with fuzz/replay_main.cpp, it shows that
// the replay judges every input unfiltered: the tests fuzz-replay.ignores-filters.*
// replay a file with RAYPROOF_FUZZ_IGNORE or RAYPROOF_FUZZ_ONLY set so that the filter
// would pass the input, and expect the replay to fail all the same.
#include "fuzz_common.hpp"

#include <cstdint>
#include <cstdio>
#include <cstdlib>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t*, std::size_t size) {
    try {
        rayproof::fuzz::filter("probe violation (mode certified, double, Plane)");
    } catch (const rayproof::fuzz::Filtered&) {
        return 0;  // what a filtered violation does in the shape targets (run_shape_target)
    }
    std::fprintf(stderr, "\n==== rayproof fuzz: contract violation: probe violation (%zu bytes)\n", size);
    std::abort();
}
