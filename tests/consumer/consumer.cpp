// A program outside the project, written as an embedder would write it. Each consumer
// test (find_package after the kernel-only install, add_subdirectory, FetchContent,
// pkg-config with a plain compiler command line) builds this one file with the kernel's
// include directory given by plain -I and -Wall -Wextra -Wpedantic -Wconversion
// -Wsign-conversion -Wshadow -Werror, one of them with -fno-exceptions too.
//
// It instantiates every public query — every shape (the convex polyhedron included),
// every mode, float and double, the scalar and the span forms of intersect and verdict,
// on a Ray and on a PreparedRay, the packets of boxes and a Bvh over every kind of
// primitive — with normal(), reversed(), surface_point(), the io helpers and the version
// macros, and checks the answers it can know exactly: all inputs
// below are small integers and halves, so every exact t is representable and a certified
// answer must equal it. It prints "rayproof <version> consumer: <n> checks passed" and
// exits 0 only when every check holds.
//
// find_package and no_exceptions build all of it. The ways whose subject is how the
// kernel reaches the compiler (add_subdirectory, FetchContent, pkg-config) define
// CONSUMER_PLUMBING: float only, every shape in every mode, no packets and no BVH. The
// instantiations are the same whatever the way, and all of them cost about 38 s of
// compile at -O0 (the plumbing set about 10 s), once per way and compiler.
#include <rayproof/rayproof.hpp>

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <limits>
#include <optional>
#include <span>
#include <sstream>
#include <string>
#include <type_traits>

#if !defined(RAYPROOF_VERSION_MAJOR) || !defined(RAYPROOF_VERSION_MINOR) || !defined(RAYPROOF_VERSION_PATCH)
#error "rayproof/rayproof.hpp does not define the version macros"
#endif
static_assert(RAYPROOF_VERSION ==
              RAYPROOF_VERSION_MAJOR * 10000 + RAYPROOF_VERSION_MINOR * 100 + RAYPROOF_VERSION_PATCH);

namespace {

int checks = 0;
int failures = 0;

void check(bool ok, const std::string& what) {
    ++checks;
    if (!ok) {
        ++failures;
        std::fprintf(stderr, "FAILED: %s\n", what.c_str());
    }
}

template <class T> std::string name_of() { return sizeof(T) == sizeof(float) ? "float" : "double"; }

// One shape with a ray whose exact answer is known, and a ray that misses it.
template <class T, class Shape> struct Case {
    const char* name;
    Shape shape;
    rayproof::Ray<T> hitting;
    T t_enter, t_exit;  // the exact interval of `hitting`
    int face;           // its exact entry face
    int exit_face;      // the exact entry face of reversed(hitting)
    rayproof::Vec3<T> outward;  // normal(shape, certified hit, hitting)
    rayproof::Ray<T> missing;
};

template <class T> rayproof::Vec3<T> v3(double x, double y, double z) {
    return rayproof::Vec3<T>(static_cast<T>(x), static_cast<T>(y), static_cast<T>(z));
}

template <class T> bool near(T got, T want) {
    // Fast mode promises nothing; on these inputs, far from every hard case, plain
    // floating point lands within a few ulps.
    return std::abs(got - want) <= T(64) * std::numeric_limits<T>::epsilon() * std::abs(want);
}

// Each query is called from one place per instantiation: the kernel inlines its paths
// into the caller, and one copy per combination keeps this file quick to compile.
template <class T, class Shape, class Mode>
[[gnu::noinline]] rayproof::Hit<T> ask(const rayproof::Ray<T>& r, const Shape& s, Mode mode) {
    return rayproof::intersect(r, s, mode);
}
template <class T, class Shape, class Mode>
[[gnu::noinline]] rayproof::Verdict ask_verdict(const rayproof::Ray<T>& r, const Shape& s, Mode mode) {
    return rayproof::verdict(r, s, mode);
}

// What each mode promises about the hitting ray (docs/semantics.md).
template <class T, class Shape, class Mode>
void check_hit(const Case<T, Shape>& c, const rayproof::Hit<T>& h, Mode mode, const std::string& where) {
    const std::string what = where + " " + c.name + "<" + name_of<T>() + "> " + rayproof::mode_name(mode);
    check(h.verdict == rayproof::Verdict::hit && static_cast<bool>(h), what + ": verdict hit");
    if constexpr (std::is_same_v<Mode, rayproof::certified_t>) {
        check(h.t_enter == c.t_enter && h.t_exit == c.t_exit, what + ": t exact");
        check(h.face == c.face, what + ": face exact");
    } else if constexpr (std::is_same_v<Mode, rayproof::conservative_t>) {
        check(h.t_enter <= c.t_enter && c.t_exit <= h.t_exit, what + ": interval encloses the exact one");
    } else {
        check(near(h.t_enter, c.t_enter) && near(h.t_exit, c.t_exit), what + ": t near the exact one");
    }
}

template <class T, class Shape, class Mode> void check_mode(const Case<T, Shape>& c, Mode mode) {
    using rayproof::Hit;
    using rayproof::Ray;
    using rayproof::Verdict;
    const std::string what = std::string(c.name) + "<" + name_of<T>() + "> " + rayproof::mode_name(mode);

    // Scalar forms.
    const Hit<T> h = ask(c.hitting, c.shape, mode);
    check_hit(c, h, mode, "scalar");
    check(ask_verdict(c.hitting, c.shape, mode) == h.verdict, what + ": verdict() equals intersect().verdict");

    Ray<T> zero = c.hitting;
    zero.direction.setZero();
    check(ask(zero, c.shape, mode).verdict == Verdict::invalid, what + ": zero direction invalid");
    check(ask_verdict(zero, c.shape, mode) == Verdict::invalid, what + ": verdict() of zero direction invalid");

    // Span forms, over the hitting, the missing and the invalid ray.
    const std::array<Ray<T>, 3> rays{c.hitting, c.missing, zero};
    std::array<Hit<T>, 3> hits{};
    std::array<Verdict, 3> verdicts{};
    rayproof::intersect(std::span<const Ray<T>>(rays), c.shape, mode, std::span<Hit<T>>(hits));
    rayproof::verdict(std::span<const Ray<T>>(rays), c.shape, mode, std::span<Verdict>(verdicts));
    check_hit(c, hits[0], mode, "batch");
    check(hits[2].verdict == Verdict::invalid && verdicts[2] == Verdict::invalid, what + ": batch invalid");

    // Prepared rays, scalar and span forms: within the mode's promise, and in certified
    // mode equal to the Ray's answers bit for bit (checked below).
    const std::array<rayproof::PreparedRay<T>, 3> prepared{rayproof::PreparedRay<T>(c.hitting),
                                                           rayproof::PreparedRay<T>(c.missing),
                                                           rayproof::PreparedRay<T>(zero)};
    std::array<Hit<T>, 3> prepared_hits{};
    std::array<Verdict, 3> prepared_verdicts{};
    rayproof::intersect(std::span<const rayproof::PreparedRay<T>>(prepared), c.shape, mode,
                        std::span<Hit<T>>(prepared_hits));
    rayproof::verdict(std::span<const rayproof::PreparedRay<T>>(prepared), c.shape, mode,
                      std::span<Verdict>(prepared_verdicts));
    check_hit(c, rayproof::intersect(prepared[0], c.shape, mode), mode, "prepared");
    check(rayproof::verdict(prepared[0], c.shape, mode) == Verdict::hit, what + ": prepared verdict()");
    check_hit(c, prepared_hits[0], mode, "prepared batch");
    check(prepared_hits[2].verdict == Verdict::invalid && prepared_verdicts[2] == Verdict::invalid,
          what + ": prepared batch invalid");

    if constexpr (std::is_same_v<Mode, rayproof::certified_t>) {
        for (std::size_t i = 0; i < rays.size(); ++i) {
            const Hit<T> one = ask(rays[i], c.shape, mode);
            check(std::memcmp(&one.t_enter, &hits[i].t_enter, sizeof(T)) == 0 &&
                      std::memcmp(&one.t_exit, &hits[i].t_exit, sizeof(T)) == 0 && one.verdict == hits[i].verdict &&
                      one.face == hits[i].face,
                  what + ": batch equals scalar bit for bit, element " + std::to_string(i));
            check(verdicts[i] == one.verdict, what + ": batch verdict equals scalar, element " + std::to_string(i));
            check(std::memcmp(&one.t_enter, &prepared_hits[i].t_enter, sizeof(T)) == 0 &&
                      std::memcmp(&one.t_exit, &prepared_hits[i].t_exit, sizeof(T)) == 0 &&
                      one.verdict == prepared_hits[i].verdict && one.face == prepared_hits[i].face &&
                      prepared_verdicts[i] == one.verdict,
                  what + ": prepared batch equals the Ray's bit for bit, element " + std::to_string(i));
        }
        check(hits[1].verdict == Verdict::miss, what + ": miss");

        // The same ray backwards: [-t_exit, -t_enter], entered through the exit face.
        const Hit<T> back = ask(rayproof::reversed(c.hitting), c.shape, mode);
        check(back.verdict == Verdict::hit && back.t_enter == -c.t_exit && back.t_exit == -c.t_enter &&
                  back.face == c.exit_face,
              what + ": reversed ray");

        check(rayproof::normal(c.shape, h, c.hitting) == c.outward, what + ": normal()");

        // The hit point with its error bound, and secondary rays spawned off both sides.
        const rayproof::SurfacePoint<T> sp = rayproof::surface_point(c.hitting, c.shape, h);
        check(sp.n == c.outward && (sp.error.array() >= T(0)).all(), what + ": surface_point");
        for (const int side : {+1, -1}) {
            const rayproof::Vec3<T> o = rayproof::spawn_origin(sp, side);
            check(T(side) * (o - sp.p).dot(sp.n) > T(0), what + ": spawn_origin leaves on side " + std::to_string(side));
        }
        check(rayproof::normal(c.shape, hits[1], c.missing) == rayproof::Vec3<T>::Zero(), what + ": normal() of a miss");
    }
}

template <class T, class Shape> void check_case(const Case<T, Shape>& c) {
    check_mode(c, rayproof::fast);
    check_mode(c, rayproof::conservative);
    check_mode(c, rayproof::certified);

    // The run-time mode answers as its tag, bit for bit in certified mode.
    for (const char* name : {"fast", "conservative", "certified"}) {
        const std::optional<rayproof::RuntimeMode> m = rayproof::parse_mode(name);
        check(m.has_value() && std::string(rayproof::to_string(*m)) == name, std::string("parse_mode ") + name);
        check(m.has_value() && rayproof::verdict(c.hitting, c.shape, *m) == rayproof::Verdict::hit,
              std::string(c.name) + ": RuntimeMode verdict in " + name);
    }
    const rayproof::Hit<T> by_tag = ask(c.hitting, c.shape, rayproof::certified);
    const rayproof::Hit<T> by_enum = rayproof::intersect(c.hitting, c.shape, rayproof::RuntimeMode::certified);
    check(std::memcmp(&by_tag.t_enter, &by_enum.t_enter, sizeof(T)) == 0 && by_tag.face == by_enum.face,
          std::string(c.name) + ": RuntimeMode intersect equals the tag's");
    check(!rayproof::parse_mode("exact").has_value(), "parse_mode refuses an unknown name");

    // io: every public type prints, numbers in hexadecimal floating point.
    std::ostringstream os;
    os << c.shape << ' ' << c.hitting << ' ' << ask(c.hitting, c.shape, rayproof::certified);
    check(os.str().rfind(std::string(c.name) + "{", 0) == 0, std::string(c.name) + ": operator<< of the shape");
    check(os.str().find(" Ray{o=") != std::string::npos, std::string(c.name) + ": operator<< of the ray");
    check(os.str().find(" Hit{hit t=[") != std::string::npos, std::string(c.name) + ": operator<< of the hit");
}

// A packet of W boxes, lane i the cube [-1, 1]^3 moved by 4i along y: the ray along x
// at y = 0.5 hits lane 0 alone, at t in [3, 5] through face 0; a lane with lo > hi is
// an empty slot.
template <class T, int W> void check_packets() {
    using namespace rayproof;
    AabbPacket<T, W> p{};
    for (int i = 0; i < W; ++i) {
        const T y = T(4 * i);
        p.set(i, Aabb<T>{v3<T>(-1, double(y) - 1, -1), v3<T>(1, double(y) + 1, 1)});
    }
    p.lo[0][W - 1] = T(2);  // lo > hi on x: an empty slot
    const PreparedRay<T> r(Ray<T>{v3<T>(-4, 0.5, 0), v3<T>(1, 0, 0)});
    const std::string what = "AabbPacket<" + name_of<T>() + ", " + std::to_string(W) + ">";
    const auto each = [&](auto mode) {
        const PacketHit<T, W> h = intersect(r, p, mode);
        check(h.mask == 1u && verdict(r, p, mode) == h.mask, what + " " + mode_name(mode) + ": mask");
        if constexpr (std::is_same_v<decltype(mode), certified_t>) {
            const Hit<T> lane = h.lane(0), scalar = intersect(r, p.box(0), certified);
            check(lane.t_enter == T(3) && lane.t_exit == T(5) && lane.face == 0 && scalar.face == lane.face,
                  what + " certified: lane 0 exact");
        } else if constexpr (std::is_same_v<decltype(mode), conservative_t>) {
            check(h.t_enter[0] <= T(3) && T(5) <= h.t_exit[0], what + " conservative: encloses");
        }
    };
    each(fast);
    each(conservative);
    each(certified);
}

// A small Bvh over every kind of primitive: the cube [-1, 1]^3 as six planes (index
// 0), the sphere of radius 1 at (5, 0, 0), the box [9, 11] x [-1, 1]^2 and the plane x =
// 20 (kept beside the tree). The ray along x at y = 0.5 enters the cube first, at t = 3
// through its plane 0; every mode finds it, the tree equals the brute force, and
// for_each_candidate offers each of the four primitives exactly once.
template <class T, int W> void check_bvh() {
    using namespace rayproof;
    static const Plane<T> cube[6] = {{v3<T>(-1, 0, 0), T(1)}, {v3<T>(1, 0, 0), T(1)}, {v3<T>(0, -1, 0), T(1)},
                                     {v3<T>(0, 1, 0), T(1)},  {v3<T>(0, 0, -1), T(1)}, {v3<T>(0, 0, 1), T(1)}};
    const std::array<Primitive<T>, 4> prims{Primitive<T>(ConvexPolyhedron<T>{cube}),
                                            Primitive<T>(Sphere<T>{v3<T>(5, 0, 0), T(1)}),
                                            Primitive<T>(Aabb<T>{v3<T>(9, -1, -1), v3<T>(11, 1, 1)}),
                                            Primitive<T>(Plane<T>{v3<T>(1, 0, 0), T(20)})};
    const Bvh<T, W> bvh(std::span<const Primitive<T>>(prims), BvhOptions{1, 8});
    const std::string what = "Bvh<" + name_of<T>() + ", " + std::to_string(W) + ">";
    const BvhStats st = bvh.stats();
    check(st.primitives == 4 && st.outside == 1 && st.leaves == 3 && st.nodes >= 1 && st.depth >= 1,
          what + ": stats");
    const Ray<T> ray{v3<T>(-4, 0.5, 0), v3<T>(1, 0, 0)};
    const PreparedRay<T> pr(ray);
    const auto each = [&](auto mode) {
        const ClosestHit<T> c = bvh.closest_hit(pr, mode), brute = closest_hit(pr, std::span<const Primitive<T>>(prims), mode);
        check(c.verdict == Verdict::hit && c.index == 0 && c.hit.face == 0 && brute.index == c.index,
              what + " " + mode_name(mode) + ": closest_hit");
        if constexpr (std::is_same_v<decltype(mode), certified_t>)
            check(c.hit.t_enter == T(3) && c.hit.t_exit == T(5), what + " certified: closest t exact");
        const ClosestHit<T> a = bvh.any_hit(ray, mode);
        check(a.verdict == Verdict::hit && a.index >= 0 && a.index < 4, what + " " + mode_name(mode) + ": any_hit");
        const ClosestHit<T> none = bvh.closest_hit(Ray<T>{v3<T>(-4, 5, 0), v3<T>(0, 1, 0)}, mode);
        check(none.verdict == Verdict::miss && none.index == -1, what + " " + mode_name(mode) + ": a miss");
        std::array<int, 4> seen{};
        T limit = std::numeric_limits<T>::infinity();
        bvh.for_each_candidate(pr, mode, limit, [&](std::size_t i) {
            ++seen[i];
            return true;
        });
        if constexpr (!std::is_same_v<decltype(mode), fast_t>)
            check(seen[0] == 1 && seen[1] == 1 && seen[2] == 1 && seen[3] == 1,
                  what + " " + mode_name(mode) + ": every candidate once");
    };
    each(fast);
    each(conservative);
    each(certified);
    check(bvh.closest_hit(Ray<T>{v3<T>(0, 0, 0), v3<T>(0, 0, 0)}, certified).verdict == Verdict::invalid,
          what + ": an invalid ray");
}

template <class T> void check_type() {
    using namespace rayproof;
    Mat3<T> turn;  // a quarter turn about z: columns (0, 1, 0), (-1, 0, 0), (0, 0, 1)
    turn << 0, -1, 0, 1, 0, 0, 0, 0, 1;

    check_case(Case<T, Aabb<T>>{"Aabb", Aabb<T>{v3<T>(-1, -1, -1), v3<T>(1, 1, 1)},
                                Ray<T>{v3<T>(-4, 0.5, 0), v3<T>(1, 0, 0)}, T(3), T(5), 0, 1, v3<T>(-1, 0, 0),
                                Ray<T>{v3<T>(-4, 5, 0), v3<T>(1, 0, 0)}});
    // Along x the ray crosses the second axis, (-1, 0, 0), whose slab |x - 0.5| <= 2 it
    // enters at x = -1.5 on its + side (face 2*1 + 1) and leaves at x = 2.5 (face 2).
    check_case(Case<T, Obb<T>>{"Obb", Obb<T>{v3<T>(0.5, 0, 0), turn, v3<T>(1, 2, 3)},
                               Ray<T>{v3<T>(-4.5, 0.5, 0), v3<T>(1, 0, 0)}, T(3), T(7), 3, 2, v3<T>(-1, 0, 0),
                               Ray<T>{v3<T>(-4.5, 5, 0), v3<T>(1, 0, 0)}});
    check_case(Case<T, Plane<T>>{"Plane", Plane<T>{v3<T>(0, 0, 2), T(4)}, Ray<T>{v3<T>(1, 1, -1), v3<T>(0, 0, 0.5)},
                                 T(6), T(6), -1, -1, v3<T>(0, 0, -1), Ray<T>{v3<T>(1, 1, -1), v3<T>(0, 0, -0.5)}});
    check_case(Case<T, Sphere<T>>{"Sphere", Sphere<T>{v3<T>(1, 2, 3), T(2)}, Ray<T>{v3<T>(1, 2, -7), v3<T>(0, 0, 2)},
                                  T(4), T(6), -1, -1, v3<T>(0, 0, -1), Ray<T>{v3<T>(1, 5, -7), v3<T>(0, 0, 2)}});

    // The box [-1, 1]^3 as six planes (-x, +x, -y, +y, -z, +z): entered through plane 0
    // at x = -1, left through plane 1.
    static const Plane<T> cube[6] = {{v3<T>(-1, 0, 0), T(1)}, {v3<T>(1, 0, 0), T(1)}, {v3<T>(0, -1, 0), T(1)},
                                     {v3<T>(0, 1, 0), T(1)},  {v3<T>(0, 0, -1), T(1)}, {v3<T>(0, 0, 1), T(1)}};
    check_case(Case<T, ConvexPolyhedron<T>>{"ConvexPolyhedron", ConvexPolyhedron<T>{cube},
                                            Ray<T>{v3<T>(-4, 0.5, 0), v3<T>(1, 0, 0)}, T(3), T(5), 0, 1,
                                            v3<T>(-1, 0, 0), Ray<T>{v3<T>(-4, 5, 0), v3<T>(1, 0, 0)}});

#ifndef CONSUMER_PLUMBING
    check_packets<T, 4>();
    check_packets<T, 8>();
    check_bvh<T, 4>();
    check_bvh<T, 8>();
#endif

    // The printed form reproduces bit for bit: 3 and 5 in hexadecimal floating point.
    std::ostringstream os;
    os << ask(Ray<T>{v3<T>(-4, 0.5, 0), v3<T>(1, 0, 0)}, Aabb<T>{v3<T>(-1, -1, -1), v3<T>(1, 1, 1)}, certified);
    check(os.str() == "Hit{hit t=[0x1.8p+1, 0x1.4p+2] face=0}", "operator<< of a Hit<" + name_of<T>() + ">: " + os.str());
}

}  // namespace

int main() {
    check(std::string(rayproof::to_string(rayproof::Verdict::invalid)) == "invalid", "to_string(Verdict)");
    check(std::string(RAYPROOF_VERSION_STRING) == std::to_string(RAYPROOF_VERSION_MAJOR) + "." +
                                                      std::to_string(RAYPROOF_VERSION_MINOR) + "." +
                                                      std::to_string(RAYPROOF_VERSION_PATCH),
          "RAYPROOF_VERSION_STRING is MAJOR.MINOR.PATCH");
#ifdef CONSUMER_EXPECTED_VERSION
    // The version the package reported (CMake's package version, pkg-config --modversion).
    check(std::string(RAYPROOF_VERSION_STRING) == CONSUMER_EXPECTED_VERSION,
          std::string("package version ") + CONSUMER_EXPECTED_VERSION + " equals the header's " + RAYPROOF_VERSION_STRING);
#endif
    check_type<float>();
#ifndef CONSUMER_PLUMBING
    check_type<double>();
#endif
    std::printf("rayproof %s consumer: %d checks, %d failed\n", RAYPROOF_VERSION_STRING, checks, failures);
    if (failures == 0) std::printf("rayproof consumer: all %d checks passed\n", checks);
    return failures == 0 ? 0 : 1;
}
