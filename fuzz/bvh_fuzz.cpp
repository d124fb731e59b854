// bvh_fuzz.cpp — fuzz target: one ray against a scene of 0 to 64 primitives of every kind
// (bvh_decode.hpp), float and double. The brute-force closest hit (closest.hpp) is judged
// by the exact oracle, and Bvh<T, 4> and Bvh<T, 8>, built with the leaf size and bin
// count the input gives, are held to brute force in every mode, any_hit and
// for_each_candidate included (rayproof/generators/scene_check.hpp says exactly what;
// the same checks as tests/props/bvh_props.cpp). A violation prints the scene and the
// ray in hexadecimal floating point and what broke, then aborts.
#include "bvh_decode.hpp"
#include "fuzz_common.hpp"

#include <rayproof/bvh.hpp>
#include <rayproof/generators/scene_check.hpp>
#include <rayproof/generators/scene_gen.hpp>  // print_primitive
#include <rayproof/io.hpp>

#include <cstdlib>
#include <iostream>
#include <string>

namespace rayproof::fuzz {
namespace {

// RAYPROOF_FUZZ_PRINT set: every decoded case is printed before it is checked.
bool print_cases() {
    static const bool on = [] {
        const char* v = std::getenv("RAYPROOF_FUZZ_PRINT");
        return v && *v;
    }();
    return on;
}

template <class T> void print_scene(std::ostream& os, const SceneInput<T>& in) {
    os << "ray:      " << in.ray << "\nbvh:      leaf_size " << in.leaf_size << ", bins " << in.bins << "\nscene:    "
       << in.prims.size() << " primitives";
    for (std::size_t i = 0; i < in.prims.size(); ++i) {
        os << "\n    [" << i << "] ";
        gen::print_primitive(os, in.prims[i]);
    }
    os << '\n';
}

template <class T> [[noreturn]] void scene_violation(const std::string& what, const SceneInput<T>& in) {
    const std::string d = what.substr(0, what.find(':')) + " (" + (std::is_same_v<T, float> ? "float" : "double") + ")";
    filter(d);
    std::cerr << "\n==== rayproof fuzz: contract violation: " << d << '\n';
    if (!current_input().empty()) std::cerr << "input:    " << current_input() << '\n';
    std::cerr << "what:     " << what << '\n';
    print_scene(std::cerr, in);
    std::cerr.flush();
    std::abort();
}

template <class T> void check_scene(const std::uint8_t* data, std::size_t size) {
    const SceneInput<T> in = decode_scene<T>(data, size);
    if (print_cases()) print_scene(std::cerr, in);
    const auto prims = in.view();
    const auto ex = gen::exact_answers(in.ray, prims);
    if (const auto f = gen::check_brute_force(in.ray, prims, ex)) scene_violation(*f, in);
    const BvhOptions opt{in.leaf_size, in.bins};
    std::uint64_t choice = size;
    for (std::size_t i = 0; i < size; ++i) choice = choice * 0x100000001b3ull ^ data[i];
    if (const auto f = gen::check_structure(Bvh<T, 4>(prims, opt), in.ray, prims, ex, choice)) scene_violation(*f, in);
    if (const auto f = gen::check_structure(Bvh<T, 8>(prims, opt), in.ray, prims, ex, choice >> 7)) scene_violation(*f, in);
}

}  // namespace
}  // namespace rayproof::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace rayproof::fuzz;
    try {
        if (is_double(data, size)) check_scene<double>(data, size);
        else check_scene<float>(data, size);
    } catch (const Filtered&) {
    }
    return 0;
}
