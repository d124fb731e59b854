// seeds.cpp — writes the seed corpora of the ray/shape fuzz targets and of bvh_fuzz and
// checks the byte formats' round trip (fuzz_decode.hpp, bvh_decode.hpp). bvh_fuzz takes
// the scene generators' scenes (rayproof/generators/scene_gen.hpp) that fit its format:
// the first N of the first 4N seeds of each scene generator.
//
//   rayproof_fuzz_seeds write DIR [N]   DIR/<target>/<float|double>-<generator>-<k>: the
//                                       cases of every shared property generator
//                                       (rayproof::gen, seeds 1..N, default 6), encoded
//   rayproof_fuzz_seeds check [N]       encode → decode is the identity, bit for bit, on
//                                       N cases of every generator, float and double
//                                       (default 200); exit 1 otherwise
#include "bvh_decode.hpp"
#include "fuzz_decode.hpp"

#include <rayproof/generators.hpp>
#include <rayproof/generators/scene_gen.hpp>
#include <rayproof/io.hpp>

#include <rayproof/cli.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>

namespace {

using namespace rayproof;
namespace fs = std::filesystem;

template <class T, class Shape> bool round_trips(const Ray<T>& ray, const Shape& shape, const std::vector<std::uint8_t>& bytes) {
    fuzz::Input<T, Shape> a{ray, shape};
    auto in = fuzz::decode<T, Shape>(bytes.data(), bytes.size());
    const auto fa = fuzz::fields(a);
    const auto fb = fuzz::fields(in);
    for (std::size_t i = 0; i < fa.size(); ++i)
        if (fuzz::to_bits(*fa[i]) != fuzz::to_bits(*fb[i])) return false;
    return fuzz::is_double(bytes.data(), bytes.size()) == std::is_same_v<T, double>;
}

// One generator's cases 1..n: each encoded, checked to round trip (round_trip(c, bytes)),
// and written to DIR/<target>/<float|double>-<generator>-<k> when dir is given. Returns
// the number of failures.
template <class T, class Generators, class Encode, class RoundTrip>
int run_cases(const std::string& target, const fs::path* dir, int n, const Generators& generators, Encode encode,
              RoundTrip round_trip) {
    int failures = 0;
    for (const auto& g : generators) {
        for (int k = 1; k <= n; ++k) {
            gen::Rng rng{std::uint64_t(k)};
            const auto c = g.make(rng);
            const std::vector<std::uint8_t> bytes = encode(c);
            if (!round_trip(c, bytes)) {
                std::cerr << target << ": encode/decode round trip fails on " << c << '\n';
                ++failures;
                continue;
            }
            if (!dir) continue;
            const fs::path d = *dir / target;
            fs::create_directories(d);
            const fs::path file = d / (std::string(gen::scalar_name<T>()) + "-" + std::string(g.name) + "-" + std::to_string(k));
            std::ofstream out(file, std::ios::binary);
            out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
            if (!out) {
                std::cerr << "cannot write " << file << '\n';
                ++failures;
            }
        }
    }
    return failures;
}

template <class T, class Shape> int run(const std::string& target, const fs::path* dir, int n) {
    return run_cases<T>(
        target, dir, n, gen::generators<T, Shape>(), [](const auto& c) { return fuzz::encode(c.ray, c.shape); },
        [](const auto& c, const std::vector<std::uint8_t>& bytes) { return round_trips(c.ray, c.shape, bytes); });
}

// The polyhedron target's cases: its own byte format (PolyDecoder), the planes compared
// bit for bit.
template <class T> bool poly_round_trips(const gen::PolyCase<T>& c, const std::vector<std::uint8_t>& bytes) {
    fuzz::PolyInput<T> a{c.ray, c.shape.planes};
    auto in = fuzz::decode_polyhedron<T>(bytes.data(), bytes.size());
    if (in.planes.size() != a.planes.size()) return false;
    const auto fa = fuzz::poly_fields(a);
    const auto fb = fuzz::poly_fields(in);
    for (std::size_t i = 0; i < fa.size(); ++i)
        if (fuzz::to_bits(*fa[i]) != fuzz::to_bits(*fb[i])) return false;
    return fuzz::is_double(bytes.data(), bytes.size()) == std::is_same_v<T, double>;
}

template <class T> int run_polyhedron(const std::string& target, const fs::path* dir, int n) {
    return run_cases<T>(
        target, dir, n, gen::polyhedron_generators<T>(),
        [](const auto& c) { return fuzz::encode_polyhedron(c.ray, std::span<const Plane<T>>(c.shape.planes)); },
        [](const auto& c, const std::vector<std::uint8_t>& bytes) { return poly_round_trips(c, bytes); });
}

// The BVH target's cases (bvh_decode.hpp): the scene generators' scenes that fit the
// format (at most 64 primitives, polyhedra of at most 16 planes), with a leaf size and a
// bin count drawn from k; the primitives compared bit for bit after decoding.
template <class T> std::string scene_bits(std::span<const Primitive<T>> prims, const Ray<T>& ray) {
    std::ostringstream os;
    os << ray;
    for (const Primitive<T>& p : prims) gen::print_primitive(os << ' ' << p.index() << ':', p);  // hexfloat: exact
    return os.str();
}
template <class T> int run_bvh(const std::string& target, const fs::path* dir, int n) {
    int failures = 0;
    for (const auto& g : gen::scene_generators<T>()) {
        int written = 0;
        for (int k = 1; k <= 4 * n && written < n; ++k) {
            gen::Rng rng{std::uint64_t(k)};
            const gen::Scene<T> s = g.make(rng);
            if (!fuzz::scene_fits<T>(s.view())) continue;
            const int leaf = 1 + k % 8, bins = 2 + (k * 7) % 32;
            const std::vector<std::uint8_t> bytes = fuzz::encode_scene<T>(s.ray, s.view(), leaf, bins);
            const auto in = fuzz::decode_scene<T>(bytes.data(), bytes.size());
            ++written;
            if (scene_bits<T>(in.view(), in.ray) != scene_bits<T>(s.view(), s.ray) || in.leaf_size != leaf ||
                in.bins != bins || fuzz::is_double(bytes.data(), bytes.size()) != std::is_same_v<T, double>) {
                std::cerr << target << ": encode/decode round trip fails on " << s << '\n';
                ++failures;
                continue;
            }
            if (!dir) continue;
            const fs::path d = *dir / target;
            fs::create_directories(d);
            const fs::path file = d / (std::string(gen::scalar_name<T>()) + "-" + std::string(g.name) + "-" + std::to_string(k));
            std::ofstream out(file, std::ios::binary);
            out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
            if (!out) {
                std::cerr << "cannot write " << file << '\n';
                ++failures;
            }
        }
    }
    return failures;
}

template <template <class> class Shape> int both(const std::string& target, const fs::path* dir, int n) {
    return run<float, Shape<float>>(target, dir, n) + run<double, Shape<double>>(target, dir, n);
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"Writes the fuzz targets' seed corpora; checks the byte format's round trip.", "rayproof_fuzz_seeds"};
    app.require_subcommand(1);
    std::string dir;
    int n = 0;
    CLI::App& write = *app.add_subcommand("write", "write DIR/<target>/<float|double>-<generator>-<k>, k = 1..N (6)");
    write.add_option("DIR", dir, "the corpus directory")->required();
    CLI::App& check = *app.add_subcommand("check", "encode then decode is the identity, bit for bit, on N cases (200)");
    for (CLI::App* c : {&write, &check})
        c->add_option("N", n, "cases per generator and scalar type")->check(CLI::Range(1, 1 << 20));
    if (const auto stop = rayproof::cli::parse(app, argc, argv)) return *stop;
    const fs::path d = dir, *out = write.parsed() ? &d : nullptr;
    if (n == 0) n = out ? 6 : 200;
    const int f = both<Aabb>("ray_aabb_fuzz", out, n) + both<Obb>("ray_obb_fuzz", out, n) +
                  both<Plane>("ray_plane_fuzz", out, n) + both<Sphere>("ray_sphere_fuzz", out, n) +
                  run_polyhedron<float>("ray_polyhedron_fuzz", out, n) + run_polyhedron<double>("ray_polyhedron_fuzz", out, n) +
                  // The box packets decode the Aabb format: the same seeds (written only).
                  (out ? both<Aabb>("ray_aabb_packet_fuzz", out, n) : 0) +
                  run_bvh<float>("bvh_fuzz", out, n) + run_bvh<double>("bvh_fuzz", out, n);
    if (out)
        std::cout << "seed corpora written to " << d.string() << (f ? " with failures" : "") << '\n';
    else
        std::cout << (f ? "round trip FAILED" : "encode/decode round trip: ok") << '\n';
    return f ? 1 : 0;
}
