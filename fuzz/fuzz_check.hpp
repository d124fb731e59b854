// fuzz_check.hpp — what the ray/shape fuzz targets check on every decoded case: each of
// the three modes against the exact oracle, per the contract (the shared checker,
// rayproof/oracle/contract.hpp), plus batch == scalar.
//
//   every mode      invalid exactly when the oracle says invalid (never invalid_mismatch);
//                   a hit never carries NaN in t_enter or t_exit
//   certified       judge(hit, exact).exact_match(): verdict and face exact, each t a
//                   faithful rounding of the exact value
//   conservative    never false_miss; a hit's [t_enter, t_exit] encloses the exact interval
//   certified and   a hit has t_min <= t_enter <= t_exit <= t_max; face in [-1, 5] for
//   conservative    boxes, in [-1, n - 1] for a polyhedron of n planes, -1 for planes and
//                   spheres
//   batch           the batch form answers the ray and its reverse exactly as the scalar
//                   form does, in every mode (bit for bit)
//   verdict         verdict(), scalar and batch, equals the full answer's verdict in
//                   every mode (so the certified one is exact too)
// `fast` promises no accuracy: it is held only to the first line (and to the sanitizers).
// A violation prints the case in hexadecimal floating point, the answer, the oracle's
// exact answer and the judgement, then aborts.
#pragma once

#include "fuzz_common.hpp"
#include "fuzz_decode.hpp"

#include <rayproof/io.hpp>
#include <rayproof/oracle/contract.hpp>
#include <rayproof/oracle/oracle.hpp>
#include <rayproof/rayproof.hpp>

#include <array>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <span>
#include <string>

namespace rayproof::fuzz {

template <class T, class Shape> const char* shape_label() {
    if constexpr (std::is_same_v<Shape, Aabb<T>>) return "Aabb";
    else if constexpr (std::is_same_v<Shape, Obb<T>>) return "Obb";
    else if constexpr (std::is_same_v<Shape, Plane<T>>) return "Plane";
    else if constexpr (std::is_same_v<Shape, ConvexPolyhedron<T>>) return "ConvexPolyhedron";
    else return "Sphere";
}
template <class T, class Shape> std::string describe(const char* what, const char* mode) {
    return std::string(what) + " (mode " + mode + ", " + (std::is_same_v<T, float> ? "float" : "double") + ", " +
           shape_label<T, Shape>() + ")";
}

template <class T, class Shape>
[[noreturn]] void violation(const char* what, const char* mode, const Ray<T>& ray, const Shape& shape, const Hit<T>& hit,
                            const oracle::Exact<T>& ex, const oracle::Judgement* j) {
    const std::string d = describe<T, Shape>(what, mode);
    filter(d);
    std::cerr << "\n==== rayproof fuzz: contract violation: " << d << '\n';
    if (!current_input().empty()) std::cerr << "input:    " << current_input() << '\n';
    std::cerr << "ray:      " << ray << "\nshape:    " << shape << "\nanswer:   " << hit << "\nexact:    " << ex << '\n';
    if (j) std::cerr << "judge:    " << *j << '\n';
    std::cerr.flush();
    std::abort();
}

inline bool same_bits(float a, float b) { return std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b); }
inline bool same_bits(double a, double b) { return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b); }
template <class T> bool same_answer(const Hit<T>& a, const Hit<T>& b) {
    if (a.verdict != b.verdict) return false;
    if (a.verdict != Verdict::hit) return true;
    return same_bits(a.t_enter, b.t_enter) && same_bits(a.t_exit, b.t_exit) && a.face == b.face;
}

// The first breach of the mode's contract, if any, is reported (the breaches of the
// answer's form without the judgement, the others with it).
template <class T, class Shape, class Mode>
void check_mode(const Ray<T>& ray, const Shape& shape, const oracle::Exact<T>& ex, Mode mode) {
    const Hit<T> hit = intersect(ray, shape, mode);
    const oracle::ContractCheck c = oracle::check_contract(ray, shape, hit, ex, mode);
    if (c.ok()) return;
    const oracle::Breach first = c.first();
    const oracle::Judgement j = c.mode_judgement();
    const bool form = first == oracle::Breach::verdict_out_of_range || first == oracle::Breach::nan_in_hit;
    violation(oracle::describe(first), mode_name(mode), ray, shape, hit, ex, form ? nullptr : &j);
}

template <class T, class Shape, class Mode> void check_batch(const Ray<T>& ray, const Shape& shape, Mode mode) {
    const std::array<Ray<T>, 2> rays = {ray, reversed(ray)};
    std::array<Hit<T>, 2> out;
    intersect(std::span<const Ray<T>>(rays), shape, mode, std::span<Hit<T>>(out));
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const Hit<T> scalar = intersect(rays[i], shape, mode);
        if (!same_answer(out[i], scalar)) {
            const std::string d = describe<T, Shape>("batch answer differs from scalar", mode_name(mode));
            filter(d);
            std::cerr << "\n==== rayproof fuzz: contract violation: " << d << '\n';
            if (!current_input().empty()) std::cerr << "input:    " << current_input() << '\n';
            std::cerr << "ray:      " << rays[i] << "\nshape:    " << shape << "\nbatch:    " << out[i]
                      << "\nscalar:   " << scalar << '\n';
            std::abort();
        }
    }
}

template <class T, class Shape, class Mode> void check_verdict(const Ray<T>& ray, const Shape& shape, Mode mode) {
    const std::array<Ray<T>, 2> rays = {ray, reversed(ray)};
    std::array<Verdict, 2> out;
    verdict(std::span<const Ray<T>>(rays), shape, mode, std::span<Verdict>(out));
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const Hit<T> full = intersect(rays[i], shape, mode);
        const Verdict scalar = verdict(rays[i], shape, mode);
        if (scalar != full.verdict || out[i] != full.verdict) {
            const std::string d = describe<T, Shape>("verdict() differs from the full answer's verdict", mode_name(mode));
            filter(d);
            std::cerr << "\n==== rayproof fuzz: contract violation: " << d << '\n';
            if (!current_input().empty()) std::cerr << "input:    " << current_input() << '\n';
            std::cerr << "ray:      " << rays[i] << "\nshape:    " << shape << "\nfull:     " << full
                      << "\nverdict:  " << scalar << " (batch: " << out[i] << ")\n";
            std::abort();
        }
    }
}

// RAYPROOF_FUZZ_PRINT set: every decoded case is printed before it is checked (to see
// the case of a hang or of a sanitizer report).
inline bool print_cases() {
    static const bool on = [] {
        const char* v = std::getenv("RAYPROOF_FUZZ_PRINT");
        return v && *v;
    }();
    return on;
}

template <class T, class Shape> void check_case(const Ray<T>& ray, const Shape& shape) {
    if (print_cases()) std::cerr << "case (" << (std::is_same_v<T, float> ? "float" : "double") << "): " << ray << ' ' << shape << std::endl;
    const oracle::Exact<T> ex = oracle::exact(ray, shape);
    check_mode(ray, shape, ex, certified);
    check_mode(ray, shape, ex, conservative);
    check_mode(ray, shape, ex, fast);
    check_batch(ray, shape, certified);
    check_batch(ray, shape, conservative);
    check_batch(ray, shape, fast);
    check_verdict(ray, shape, certified);
    check_verdict(ray, shape, conservative);
    check_verdict(ray, shape, fast);
}

// The body of a shape target: the header picks float or double.
template <template <class> class Shape> int run_shape_target(const std::uint8_t* data, std::size_t size) {
    try {
        if (is_double(data, size)) {
            const auto in = decode<double, Shape<double>>(data, size);
            check_case(in.ray, in.shape);
        } else {
            const auto in = decode<float, Shape<float>>(data, size);
            check_case(in.ray, in.shape);
        }
    } catch (const Filtered&) {
    }
    return 0;
}

// The body of the polyhedron target (its own byte format, PolyDecoder): the header picks
// float or double, the planes are owned by the decoded input.
inline int run_polyhedron_target(const std::uint8_t* data, std::size_t size) {
    try {
        if (is_double(data, size)) {
            const auto in = decode_polyhedron<double>(data, size);
            check_case(in.ray, in.shape());
        } else {
            const auto in = decode_polyhedron<float>(data, size);
            check_case(in.ray, in.shape());
        }
    } catch (const Filtered&) {
    }
    return 0;
}

}  // namespace rayproof::fuzz
