// ray_sphere_fuzz.cpp — fuzz target: ray against Sphere (float and double, all three modes),
// judged by the exact oracle. Input format: fuzz_decode.hpp; checks: fuzz_check.hpp.
#include "fuzz_check.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    return rayproof::fuzz::run_shape_target<rayproof::Sphere>(data, size);
}
