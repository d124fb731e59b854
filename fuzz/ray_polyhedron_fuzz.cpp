// ray_polyhedron_fuzz.cpp — fuzz target: ray against ConvexPolyhedron (0 to 64 planes,
// float and double, all three modes), judged by the exact oracle. Input format:
// fuzz_decode.hpp (PolyDecoder); checks: fuzz_check.hpp.
#include "fuzz_check.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    return rayproof::fuzz::run_polyhedron_target(data, size);
}
