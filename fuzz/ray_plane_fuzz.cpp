// ray_plane_fuzz.cpp — fuzz target: ray against Plane (float and double, all three modes),
// judged by the exact oracle. Input format: fuzz_decode.hpp; checks: fuzz_check.hpp.
#include "fuzz_check.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    return rayproof::fuzz::run_shape_target<rayproof::Plane>(data, size);
}
