// Ray vs AabbPacket (ray_aabb_packet.hpp), float and double, W = 4 and 8, every mode,
// both SIMD backends (detail/simd.hpp: portable arrays and the native registers of this
// build; the same file is built a second time with -mavx2, ray_aabb_packet_avx2_test,
// where native means AVX2). Every packet below goes through check_packet, which holds:
//   - verdict(...) == intersect(...).mask in every mode and backend;
//   - certified: each lane equals the scalar certified answer (rayproof::intersect on
//     the lane's box) bit for bit (verdict, t_enter, t_exit, face; a miss and an empty
//     slot as 0, 0, -1), and the portable and native backends give identical answers;
//   - conservative: never a miss where the certified lane hits, and its interval holds
//     the exact one (which lies within one ulp of the certified ends, outward);
//   - every mode: an empty slot (lo > hi, NaN or infinite bound) has bit 0, an invalid
//     ray gives mask 0;
//   - fast: the mask equals the certified one on the packets marked clear (small
//     integers and powers of two, no rounding anywhere).
// The packets: unit cubes shifted lane by lane; empty slots of every kind; invalid rays;
// ±0 direction components with the origin exactly on a slab plane, one ulp inside and
// one ulp outside (decided exactly, in every mode); grazing an edge and a corner, with
// the box moved one ulp either way; boxes at extreme exponents and of denormal size; a
// double direction with |d_i| >= 2^1022 (the scalar path for every lane); and seeded
// random packets of hard boxes built around points of the ray. The filter is also
// checked to decide the clear lanes itself (no scalar fallback for them), in float lanes
// or, when the float reciprocals are not normal, in double lanes; and the guarded modes
// are checked to answer alike under every directed rounding mode. The forms that take an
// FpEnvScope equal the forms without it on every packet above (check_packet), in and
// under a foreign rounding mode the scope restores, and a scoped query stops the program
// when the environment was changed inside the scope (the check this file turns on). Vec::store_widened
// (the BVH's node entries) is checked lane by lane in both backends.
// The FpEnvScope forms check their precondition here at every call (fp_env_scope.hpp).
#define RAYPROOF_CHECK_FP_ENV_SCOPE 1
#include "same_hit.hpp"
#include <rayproof/rayproof.hpp>

#include <gtest/gtest.h>

#include <bit>
#include <cfenv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <sstream>
#include <string>

using namespace rayproof;
namespace simd = rayproof::detail::simd;

namespace {

using rayproof::testing::same_bits;

template <class T> T up(T x) { return std::nextafter(x, std::numeric_limits<T>::infinity()); }
template <class T> T down(T x) { return std::nextafter(x, -std::numeric_limits<T>::infinity()); }

template <class T, int W> std::string describe(const Ray<T>& r, const AabbPacket<T, W>& p, int lane) {
    std::ostringstream os;
    os << std::hexfloat << "ray " << r << " lane " << lane << " box " << p.box(lane);
    return os.str();
}

template <class T, int W> bool same_packet(const PacketHit<T, W>& a, const PacketHit<T, W>& b) {
    return a.mask == b.mask && std::memcmp(a.t_enter, b.t_enter, sizeof a.t_enter) == 0 &&
           std::memcmp(a.t_exit, b.t_exit, sizeof a.t_exit) == 0 && std::memcmp(a.face, b.face, sizeof a.face) == 0;
}

template <class T, int W, class B, class Mode> void check_backend(const Ray<T>& r, const AabbPacket<T, W>& p, Mode m,
                                                                  bool clear) {
    const PreparedRay<T> pr(r);
    const std::uint32_t v = detail::packet_verdict<B>(pr, p, m);
    const PacketHit<T, W> h = detail::packet_intersect<B>(pr, p, m);
    SCOPED_TRACE(std::string(mode_name(m)) + (std::is_same_v<B, simd::portable> ? " portable" : " native"));
    EXPECT_EQ(v, h.mask) << "verdict != intersect().mask";
    if (!detail::valid(r)) {
        EXPECT_EQ(v, 0u) << "invalid ray";
    }
    for (int i = 0; i < W; ++i) {
        const Aabb<T> box = p.box(i);
        const Hit<T> c = intersect(r, box, certified);
        const bool bit = (v >> i) & 1;
        const Hit<T> x = h.lane(i);  // the lane as a Hit: the packet's own fields
        EXPECT_EQ(x.verdict, ((h.mask >> i) & 1) ? Verdict::hit : Verdict::miss);
        EXPECT_TRUE(same_bits(x.t_enter, h.t_enter[i]) && same_bits(x.t_exit, h.t_exit[i]) && x.face == h.face[i]);
        if (c.verdict == Verdict::invalid) {
            EXPECT_FALSE(bit) << "empty slot or invalid ray: " << describe(r, p, i);
            continue;
        }
        if constexpr (std::is_same_v<Mode, certified_t>) {
            EXPECT_EQ(bit, c.verdict == Verdict::hit) << describe(r, p, i);
            EXPECT_TRUE(same_bits(h.t_enter[i], c.t_enter)) << h.t_enter[i] << " vs " << c << ' ' << describe(r, p, i);
            EXPECT_TRUE(same_bits(h.t_exit[i], c.t_exit)) << h.t_exit[i] << " vs " << c << ' ' << describe(r, p, i);
            EXPECT_EQ(h.face[i], c.face) << describe(r, p, i);
        } else if constexpr (std::is_same_v<Mode, conservative_t>) {
            if (c.verdict == Verdict::hit) {
                EXPECT_TRUE(bit) << "conservative false miss: " << describe(r, p, i);
                if (bit) {
                    EXPECT_LE(h.t_enter[i], up(c.t_enter)) << describe(r, p, i);
                    EXPECT_GE(h.t_exit[i], down(c.t_exit)) << describe(r, p, i);
                    EXPECT_LE(r.t_min, h.t_enter[i]);
                    EXPECT_LE(h.t_enter[i], h.t_exit[i]);
                    EXPECT_LE(h.t_exit[i], r.t_max);
                }
            }
        } else if (clear) {
            EXPECT_EQ(bit, c.verdict == Verdict::hit) << "fast on a clear case: " << describe(r, p, i);
        }
        if (!bit) {
            EXPECT_EQ(h.t_enter[i], T(0));
            EXPECT_EQ(h.t_exit[i], T(0));
            EXPECT_EQ(h.face[i], -1);
        }
    }
}

template <class T, int W> void check_packet(const Ray<T>& r, const AabbPacket<T, W>& p, bool clear = false) {
    const auto each = [&](auto m) {
        check_backend<T, W, simd::portable>(r, p, m, clear);
        check_backend<T, W, simd::native>(r, p, m, clear);
    };
    each(fast);
    each(conservative);
    each(certified);
    // The two backends, certified: identical.
    const PreparedRay<T> pr(r);
    const PacketHit<T, W> a = detail::packet_intersect<simd::portable>(pr, p, certified);
    const PacketHit<T, W> b = detail::packet_intersect<simd::native>(pr, p, certified);
    EXPECT_EQ(a.mask, b.mask);
    EXPECT_EQ(detail::packet_verdict<simd::portable>(pr, p, certified),
              detail::packet_verdict<simd::native>(pr, p, certified));
    EXPECT_EQ(std::memcmp(a.t_enter, b.t_enter, sizeof a.t_enter), 0);
    EXPECT_EQ(std::memcmp(a.t_exit, b.t_exit, sizeof a.t_exit), 0);
    EXPECT_EQ(std::memcmp(a.face, b.face, sizeof a.face), 0);
    // The public forms are the native backend.
    EXPECT_EQ(verdict(pr, p, certified), b.mask);
    // In an FpEnvScope (checked: RAYPROOF_CHECK_FP_ENV_SCOPE above), every mode: the
    // answers of the forms without it, bit for bit.
    const FpEnvScope env;
    const auto scoped = [&](auto m) {
        EXPECT_TRUE(same_packet(intersect(pr, p, m, env), intersect(pr, p, m))) << mode_name(m) << " in an FpEnvScope";
        EXPECT_EQ(verdict(pr, p, m, env), verdict(pr, p, m)) << mode_name(m) << " in an FpEnvScope";
    };
    scoped(fast);
    scoped(conservative);
    scoped(certified);
}

template <class T> Aabb<T> box(T x0, T y0, T z0, T x1, T y1, T z1) { return {Vec3<T>(x0, y0, z0), Vec3<T>(x1, y1, z1)}; }

// Lane i: the unit cube [-1, 1]^3 moved by i·step along x.
template <class T, int W> AabbPacket<T, W> shifted_cubes(T step) {
    AabbPacket<T, W> p;
    for (int i = 0; i < W; ++i) p.set(i, box<T>(-1 + T(i) * step, -1, -1, 1 + T(i) * step, 1, 1));
    return p;
}

template <class P> class Packet : public ::testing::Test {};
template <class T, int W> struct Param {
    using type = T;
    static constexpr int width = W;
};
using Params = ::testing::Types<Param<float, 4>, Param<float, 8>, Param<double, 4>, Param<double, 8>>;
struct ParamNames {
    template <class P> static std::string GetName(int) {
        return std::string(std::is_same_v<typename P::type, float> ? "float" : "double") + "_W" +
               std::to_string(P::width);
    }
};
TYPED_TEST_SUITE(Packet, Params, ParamNames);

}  // namespace

TEST(PacketBackend, NativeIsTheCompiledTarget) {
#if defined(__AVX2__)
    EXPECT_STREQ(simd::native_name(), "avx2");
#elif defined(__SSE2__) && defined(__x86_64__)
    EXPECT_STREQ(simd::native_name(), "sse2");
#endif
    std::cout << "native backend: " << simd::native_name() << '\n';
}

// store_widened (the BVH's node entries): each lane widened to double exactly, in both
// backends and at both widths, for the values a node test can produce (signed zeros,
// subnormals, the extremes, infinities, NaN) in every lane position.
template <int W, class B> void check_widened() {
    const float special[] = {0.0f, -0.0f, 1.0f, -1.5f, 0x1p-149f, -0x1p-149f, 0x1p-126f, 0x1.fffffep127f,
                             -0x1.fffffep127f, std::numeric_limits<float>::infinity(),
                             -std::numeric_limits<float>::infinity(), std::numeric_limits<float>::quiet_NaN(),
                             0x1.2345p-3f};
    constexpr std::size_t n = sizeof special / sizeof special[0];
    for (std::size_t shift = 0; shift < n; ++shift) {
        float in[W];
        for (int i = 0; i < W; ++i) in[i] = special[(shift + std::size_t(i)) % n];
        double out[W];
        simd::Vec<float, W, B>::load(in).store_widened(out);
        for (int i = 0; i < W; ++i) {
            const double want = double(in[i]);
            EXPECT_EQ(std::bit_cast<std::uint64_t>(out[i]), std::bit_cast<std::uint64_t>(want))
                << "W " << W << (std::is_same_v<B, simd::portable> ? " portable" : " native") << ", lane " << i
                << ": " << in[i];
        }
    }
}
TEST(PacketBackend, WidenedStoreIsExactInEveryLane) {
    check_widened<4, simd::portable>();
    check_widened<8, simd::portable>();
    check_widened<4, simd::native>();
    check_widened<8, simd::native>();
}

TYPED_TEST(Packet, ShiftedCubesAlongEachAxis) {
    using T = typename TypeParam::type;
    constexpr int W = TypeParam::width;
    const AabbPacket<T, W> p = shifted_cubes<T, W>(T(1));
    for (int a = 0; a < 3; ++a)
        for (T s : {T(1), T(-1)})
            for (T y : {T(0), T(0.5), T(2)}) {
                Vec3<T> o(0, y, 0), d(0, 0, 0);
                o[a] = -8 * s;
                if (a == 1) o[0] = y;
                d[a] = s;
                check_packet(Ray<T>{o, d}, p, true);
                check_packet(Ray<T>{o, d, T(9), T(9.5)}, p, true);  // starts inside a few lanes
            }
    // Along x through every lane, clipped so that some lanes are out of range.
    check_packet(Ray<T>{Vec3<T>(-4, 0, 0), Vec3<T>(1, 0, 0), T(0), T(5)}, p, true);
    check_packet(Ray<T>{Vec3<T>(-4, 0, 0), Vec3<T>(2, 0, 0), T(1), T(2)}, p, true);
    // Oblique, non-representable slab values.
    check_packet(Ray<T>{Vec3<T>(T(-3.1), T(-0.7), T(-2.3)), Vec3<T>(T(0.9), T(0.3), T(0.7))}, p);
    check_packet(Ray<T>{Vec3<T>(T(9.3), T(2.7), T(2.3)), Vec3<T>(T(-0.9), T(-0.35), T(-0.4))}, p);
}

TYPED_TEST(Packet, EmptySlotsAndInvalidRays) {
    using T = typename TypeParam::type;
    constexpr int W = TypeParam::width;
    constexpr T nan = std::numeric_limits<T>::quiet_NaN(), inf = std::numeric_limits<T>::infinity();
    AabbPacket<T, W> p = shifted_cubes<T, W>(T(0.25));
    p.lo[0][0] = 2;          // lo > hi
    p.hi[1][1] = nan;        // NaN bound
    p.lo[2][2] = -inf;       // infinite bound
    p.hi[2][3] = inf;
    if constexpr (W == 8) {
        p.lo[1][5] = up(p.hi[1][5]);  // lo > hi by one ulp
        p.hi[0][7] = std::numeric_limits<T>::max();  // valid, huge
    }
    const Ray<T> r{Vec3<T>(-5, 0, 0), Vec3<T>(1, 0, 0)};
    check_packet(r, p, true);
    const std::uint32_t empty = 0xfu | (W == 8 ? 1u << 5 : 0u);
    for (std::uint32_t m : {verdict(PreparedRay<T>(r), p, fast), verdict(PreparedRay<T>(r), p, conservative),
                            verdict(PreparedRay<T>(r), p, certified)})
        EXPECT_EQ(m & empty, 0u);
    EXPECT_EQ(verdict(PreparedRay<T>(r), p, certified), ((1u << W) - 1) & ~empty);
    // Invalid rays: mask 0 in every mode.
    const AabbPacket<T, W> q = shifted_cubes<T, W>(T(0.25));
    const Ray<T> bad[] = {
        {Vec3<T>(-5, 0, 0), Vec3<T>(0, 0, 0)},                 // zero direction
        {Vec3<T>(nan, 0, 0), Vec3<T>(1, 0, 0)},                // NaN origin
        {Vec3<T>(-5, 0, 0), Vec3<T>(inf, 0, 0)},               // infinite direction
        {Vec3<T>(-5, 0, 0), Vec3<T>(1, 0, 0), T(2), T(1)},     // t_min > t_max
        {Vec3<T>(-5, 0, 0), Vec3<T>(1, 0, 0), nan, T(1)},      // NaN t_min
        {Vec3<T>(-5, 0, 0), Vec3<T>(1, 0, 0), T(0), -inf},     // t_max = -inf
    };
    for (const Ray<T>& b : bad) {
        const PreparedRay<T> pr(b);
        EXPECT_EQ(verdict(pr, q, fast), 0u);
        EXPECT_EQ(verdict(pr, q, conservative), 0u);
        EXPECT_EQ(verdict(pr, q, certified), 0u);
        EXPECT_EQ(intersect(pr, q, certified).mask, 0u);
        check_packet(b, q);
    }
}

// ±0 direction components: the axis is decided exactly on the origin, never through
// 0·inf, with the origin on lo, on hi, one ulp inside and one ulp outside, per lane.
TYPED_TEST(Packet, SignedZeroDirectionsWithOriginOnSlabPlanes) {
    using T = typename TypeParam::type;
    constexpr int W = TypeParam::width;
    for (int a = 0; a < 3; ++a)
        for (T zero : {T(0), T(-0.0)})
            for (T plane : {T(1), T(-1), T(0.1), T(0x1p-100)}) {
                AabbPacket<T, W> p;
                // Lane i: the box [plane + k·ulp-ish, ...] around the origin's coordinate,
                // with the origin on lo, on hi, inside, outside.
                for (int i = 0; i < W; ++i) {
                    Aabb<T> b = box<T>(-2, -2, -2, 2, 2, 2);
                    switch (i % 4) {
                        case 0: b.lo[a] = plane, b.hi[a] = plane + 1; break;        // on lo
                        case 1: b.lo[a] = plane - 1, b.hi[a] = plane; break;        // on hi
                        case 2: b.lo[a] = up(plane), b.hi[a] = plane + 1; break;    // just outside (below lo)
                        case 3: b.lo[a] = plane - 1, b.hi[a] = down(plane); break;  // just outside (above hi)
                    }
                    if (i >= 4) b.lo[a] = b.hi[a] = (i % 4 < 2) ? plane : up(plane);  // flat boxes
                    p.set(i, b);
                }
                Vec3<T> o(T(-7), T(-7), T(-7)), d(T(1), T(0.75), T(0.5));
                const int b = (a + 1) % 3;
                o[a] = plane;
                d[a] = zero;
                o[b] = 0;  // the moving axes pass through the boxes
                d[b] = 0;
                o[3 - a - b] = -9;
                d[3 - a - b] = 1;
                const Ray<T> r{o, d};
                check_packet(r, p, true);
                const std::uint32_t want = W == 4 ? 0x3u : 0x33u;
                EXPECT_EQ(verdict(PreparedRay<T>(r), p, fast), want);
                EXPECT_EQ(verdict(PreparedRay<T>(r), p, conservative), want);
                EXPECT_EQ(verdict(PreparedRay<T>(r), p, certified), want);
            }
}

// A ray touching an edge and a corner of the box exactly, and the box moved by one ulp
// away from (a miss) or into the ray (a hit), lane by lane.
TYPED_TEST(Packet, GrazingEdgesAndCorners) {
    using T = typename TypeParam::type;
    constexpr int W = TypeParam::width;
    for (T s : {T(1), T(3), T(0x1p-60), T(0x1p60), T(0x1p-120)}) {
        // Edge: o = (0, 2s, 0), d = (1, -1, 0) touches the edge x = y = s of [-s, s]^3 at
        // t = s. Corner: o = (3s, 3s, -s), d = (-1, -1, 1) touches the corner (s, s, s) of
        // [-s, s] x [-s, s] x [-3s, s] at t = 2s. Every coordinate is exact.
        const Ray<T> edge{Vec3<T>(0, 2 * s, 0), Vec3<T>(1, -1, 0)};
        const Ray<T> corner{Vec3<T>(3 * s, 3 * s, -s), Vec3<T>(-1, -1, 1)};
        for (const Ray<T>& r : {edge, corner}) {
            AabbPacket<T, W> p;
            for (int i = 0; i < W; ++i) {
                Aabb<T> b = box<T>(-s, -s, -s, s, s, s);
                if (&r == &corner) b = box<T>(-s, -s, -3 * s, s, s, s);
                switch (i % 4) {
                    case 0: break;                                  // exact touch: hit
                    case 1: b.hi[0] = down(b.hi[0]); break;         // one ulp away: miss
                    case 2: b.hi[1] = up(b.hi[1]); break;           // one ulp into the ray: hit
                    case 3: b.hi[0] = down(b.hi[0]), b.hi[1] = up(b.hi[1]); break;
                }
                if (i >= 4) b.lo[2] = b.hi[2] = (&r == &corner) ? s : T(0);  // flat
                p.set(i, b);
            }
            check_packet(r, p);
            const std::uint32_t m = verdict(PreparedRay<T>(r), p, certified);
            EXPECT_EQ(m & 1u, 1u) << "exact touch";
            EXPECT_EQ(m & 2u, 0u) << "one ulp away";
        }
    }
}

TYPED_TEST(Packet, ExtremeExponentsAndDenormals) {
    using T = typename TypeParam::type;
    constexpr int W = TypeParam::width;
    constexpr T tiny = std::numeric_limits<T>::denorm_min(), mn = std::numeric_limits<T>::min(),
                mx = std::numeric_limits<T>::max();
    const int emax = std::numeric_limits<T>::max_exponent - 2, emin = std::numeric_limits<T>::min_exponent;
    for (int e : {emin, emin / 2, -20, 0, 20, emax / 2, emax - 4}) {
        const T s = std::ldexp(T(1), e);
        AabbPacket<T, W> p;
        for (int i = 0; i < W; ++i) p.set(i, box<T>(s * T(i), -s, -s, s * T(i + 1), s, s));
        for (const Vec3<T>& d : {Vec3<T>(1, 0, 0), Vec3<T>(1, T(0.3), T(-0.2)), Vec3<T>(s, s, s), Vec3<T>(-1, 1, 1)})
            check_packet(Ray<T>{Vec3<T>(-s, T(0.5) * s, 0), d}, p);
    }
    // Denormal-sized boxes and a denormal origin.
    AabbPacket<T, W> p;
    for (int i = 0; i < W; ++i) p.set(i, box<T>(tiny * T(i), -tiny, -tiny, tiny * T(i + 1), tiny * T(2), mn));
    for (const Vec3<T>& d : {Vec3<T>(1, 0, 0), Vec3<T>(1, tiny, 0), Vec3<T>(mn, tiny, tiny), Vec3<T>(1, -1, 1),
                             Vec3<T>(tiny, 0, -0.0)})
        for (const Vec3<T>& o : {Vec3<T>(-tiny, 0, 0), Vec3<T>(-1, 0, 0), Vec3<T>(0, tiny, 0)}) check_packet(Ray<T>{o, d}, p);
    // Huge boxes, values near the top of the range (slab values overflow: the scalar path).
    AabbPacket<T, W> q;
    for (int i = 0; i < W; ++i) q.set(i, box<T>(-mx, -mx, T(i) - mx / 2, mx, mx, mx / 4));
    for (const Vec3<T>& d : {Vec3<T>(1, 0, 0), Vec3<T>(tiny, 1, 0), Vec3<T>(mn, mn, mn), Vec3<T>(mx, -mx, 1)})
        for (const Vec3<T>& o : {Vec3<T>(-mx, 0, 0), Vec3<T>(mx, mx, mx), Vec3<T>(0, 0, 0)}) check_packet(Ray<T>{o, d}, q);
    if constexpr (std::is_same_v<T, double>) {
        // |d_0| >= 2^1022: 1/d_0 is subnormal, every lane goes to the scalar query.
        check_packet(Ray<T>{Vec3<T>(-2, 0, 0), Vec3<T>(0x1p1023, 1, 0)}, shifted_cubes<T, W>(T(0.5)));
        check_packet(Ray<T>{Vec3<T>(-2, 0, 0), Vec3<T>(0x1p1023, 0x1p1022, 0x1p1023)}, shifted_cubes<T, W>(T(0.5)));
    }
}

// The filter decides the clear lanes itself: none of them is left to the scalar query.
TYPED_TEST(Packet, FilterDecidesClearLanes) {
    using T = typename TypeParam::type;
    constexpr int W = TypeParam::width;
    const AabbPacket<T, W> p = shifted_cubes<T, W>(T(3));
    const PreparedRay<T> pr(Ray<T>{Vec3<T>(T(-5), T(0.3), T(-0.2)), Vec3<T>(T(1), T(0.01), T(0.02))});
    for (const auto& d : {detail::packet::certified_filter<simd::portable>(pr, p),
                          detail::packet::certified_filter<simd::native>(pr, p)}) {
        EXPECT_EQ(d.undecided, 0u);
        EXPECT_EQ(d.hit, (1u << W) - 1);
    }
    const PreparedRay<T> away(Ray<T>{Vec3<T>(-5, 3, 0), Vec3<T>(1, 0, 0)});
    for (const auto& d : {detail::packet::certified_filter<simd::portable>(away, p),
                          detail::packet::certified_filter<simd::native>(away, p)}) {
        EXPECT_EQ(d.undecided, 0u);
        EXPECT_EQ(d.hit, 0u);
    }
}

// A float ray whose float reciprocal overflows (|d_0| < 2^-128) runs the double filter,
// which still decides the clear lanes; so does a double ray with |d_0| >= 2^1022 not:
// every lane goes to the scalar query there.
TYPED_TEST(Packet, FilterArithmeticFollowsTheReciprocals) {
    using T = typename TypeParam::type;
    constexpr int W = TypeParam::width;
    const AabbPacket<T, W> p = shifted_cubes<T, W>(T(3));
    if constexpr (std::is_same_v<T, float>) {
        const PreparedRay<T> pr(Ray<T>{Vec3<T>(T(-5), T(0.3), T(-0.2)), Vec3<T>(T(1), T(0x1p-140), T(0.02))});
        EXPECT_FALSE((pr.template reciprocals_usable_in<float>()));
        EXPECT_TRUE((pr.template reciprocals_usable_in<double>()));
        for (const auto& d : {detail::packet::certified_filter<simd::portable>(pr, p),
                              detail::packet::certified_filter<simd::native>(pr, p)}) {
            EXPECT_EQ(d.undecided, 0u);
            EXPECT_EQ(d.hit, (1u << W) - 1);
        }
        check_packet(pr.ray(), p);
    } else {
        const PreparedRay<T> pr(Ray<T>{Vec3<T>(T(-5), T(0.3), T(-0.2)), Vec3<T>(T(0x1p1023), T(0.01), T(0.02))});
        EXPECT_FALSE((pr.template reciprocals_usable_in<double>()));
        EXPECT_EQ(detail::packet::certified_filter<simd::native>(pr, p).undecided, (1u << W) - 1);
        check_packet(pr.ray(), p);
    }
}

// The certified and conservative lanes answer in the default floating-point environment
// whatever the caller's: under each directed rounding mode the packets equal the ones
// computed under round-to-nearest.
TYPED_TEST(Packet, ForeignRoundingModeIsGuarded) {
    using T = typename TypeParam::type;
    constexpr int W = TypeParam::width;
    const AabbPacket<T, W> p = shifted_cubes<T, W>(T(0.75));
    const Ray<T> rays[] = {{Vec3<T>(T(-3.1), T(-0.7), T(-2.3)), Vec3<T>(T(0.9), T(0.3), T(0.7))},
                           {Vec3<T>(0, 2, 0), Vec3<T>(1, -1, 0)},
                           {Vec3<T>(T(9.3), T(2.7), T(2.3)), Vec3<T>(T(-0.9), T(-0.35), T(-0.4))}};
    for (const Ray<T>& r : rays) {
        const PreparedRay<T> pr(r);
        const PacketHit<T, W> c = intersect(pr, p, certified), k = intersect(pr, p, conservative);
        for (int mode : {FE_UPWARD, FE_DOWNWARD, FE_TOWARDZERO}) {
            ASSERT_EQ(std::fesetround(mode), 0);
            const PacketHit<T, W> c2 = intersect(pr, p, certified), k2 = intersect(pr, p, conservative);
            const std::uint32_t v2 = verdict(pr, p, certified);
            // The same in an FpEnvScope made under the foreign mode, which must be back
            // when the scope ends.
            PacketHit<T, W> c3, k3;
            std::uint32_t v3 = 0;
            bool switched = false;
            {
                const FpEnvScope env;
                switched = env.switched();
                c3 = intersect(pr, p, certified, env);
                k3 = intersect(pr, p, conservative, env);
                v3 = verdict(pr, p, certified, env);
            }
            const int after = std::fegetround();
            std::fesetround(FE_TONEAREST);
            EXPECT_TRUE(same_packet(c, c2)) << "certified, rounding mode " << mode;
            EXPECT_TRUE(same_packet(k, k2)) << "conservative, rounding mode " << mode;
            EXPECT_EQ(v2, c.mask);
            EXPECT_TRUE(switched) << "the scope did not see the foreign rounding mode " << mode;
            EXPECT_TRUE(same_packet(c, c3)) << "certified in an FpEnvScope, rounding mode " << mode;
            EXPECT_TRUE(same_packet(k, k3)) << "conservative in an FpEnvScope, rounding mode " << mode;
            EXPECT_EQ(v3, c.mask);
            EXPECT_EQ(after, mode) << "the FpEnvScope did not restore the caller's rounding mode";
        }
    }
}

// An FpEnvScope's precondition, checked (RAYPROOF_CHECK_FP_ENV_SCOPE): a scoped query
// after the environment was changed inside the scope stops the program with a message,
// and the forms without a scope still answer there.
TEST(FpEnvScopeDeathTest, EnvironmentChangedInsideTheScopeStopsTheProgram) {
    const AabbPacket<double, 4> p = shifted_cubes<double, 4>(0.75);
    const PreparedRay<double> pr(Ray<double>{Vec3<double>(-3, 0.25, 0.5), Vec3<double>(1, 0.125, 0.0625)});
    const Ray<double> r = pr.ray();
    const Aabb<double> b = p.box(0);
    const auto broken = [](auto query) {
        const FpEnvScope env;
        std::fesetround(FE_UPWARD);
        const auto answer = query(env);
        std::fesetround(FE_TONEAREST);
        return answer;
    };
    EXPECT_DEATH(broken([&](const FpEnvScope& e) { return verdict(pr, p, certified, e); }), "not the default");
    EXPECT_DEATH(broken([&](const FpEnvScope& e) { return intersect(pr, p, conservative, e).mask; }), "not the default");
    EXPECT_DEATH(broken([&](const FpEnvScope& e) { return intersect(r, b, certified, e).verdict; }), "not the default");
    EXPECT_DEATH(broken([&](const FpEnvScope& e) { return verdict(pr, b, conservative, e); }), "not the default");
    // Fast mode reads no environment, with or without a scope; the forms without a scope
    // establish their own.
    EXPECT_EQ(broken([&](const FpEnvScope& e) { return verdict(pr, p, fast, e); }), verdict(pr, p, fast));
    EXPECT_EQ(broken([&](const FpEnvScope&) { return verdict(pr, p, certified); }), verdict(pr, p, certified));
}

// Seeded random packets of hard boxes: a box with a corner, an edge or a face placed on a
// point of the ray (computed in T, so a few ulps off the exact touch), moved by a few
// ulps, empty slots and flat boxes among them, ±0 direction components.
TYPED_TEST(Packet, RandomHardBoxes) {
    using T = typename TypeParam::type;
    constexpr int W = TypeParam::width;
    constexpr std::uint64_t seed = 20261203;
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-1, 1);
    std::uniform_int_distribution<int> pick(0, 7), ulps(-3, 3), expo(-30, 30);
    const auto nudge = [&](T x) {
        for (int k = ulps(rng); k != 0; k += k > 0 ? -1 : 1) x = k > 0 ? up(x) : down(x);
        return x;
    };
    for (int n = 0; n < 3000; ++n) {
        const T scale = std::ldexp(T(1), expo(rng));
        Vec3<T> o(T(u(rng)) * scale, T(u(rng)) * scale, T(u(rng)) * scale), d(T(u(rng)), T(u(rng)), T(u(rng)));
        if (pick(rng) == 0) d[pick(rng) % 3] = pick(rng) % 2 ? T(0) : T(-0.0);
        if (d.isZero()) d[0] = 1;
        Ray<T> r{o, d};
        if (pick(rng) == 1) r.t_min = T(u(rng)) * scale, r.t_max = r.t_min + std::abs(T(u(rng))) * scale;
        AabbPacket<T, W> p;
        for (int i = 0; i < W; ++i) {
            const T t = T(std::abs(u(rng)) * 2) * scale;
            const Vec3<T> q = o + t * d;  // near a point of the ray
            Aabb<T> b;
            for (int a = 0; a < 3; ++a) {
                const T ext = T(std::abs(u(rng))) * scale;
                switch (pick(rng) % 4) {
                    case 0: b.lo[a] = nudge(q[a]), b.hi[a] = q[a] + ext; break;
                    case 1: b.lo[a] = q[a] - ext, b.hi[a] = nudge(q[a]); break;
                    case 2: b.lo[a] = b.hi[a] = nudge(q[a]); break;
                    default: b.lo[a] = q[a] - ext, b.hi[a] = q[a] + ext; break;
                }
                if (b.lo[a] > b.hi[a] && pick(rng) < 6) std::swap(b.lo[a], b.hi[a]);  // some empty slots stay
            }
            p.set(i, b);
        }
        SCOPED_TRACE("RandomHardBoxes seed " + std::to_string(seed) + " case " + std::to_string(n));
        check_packet(r, p);
        if (::testing::Test::HasFailure()) break;
    }
}
