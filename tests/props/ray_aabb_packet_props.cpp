// ray_aabb_packet_props.cpp — RapidCheck properties of the box packets
// (ray_aabb_packet.hpp), float and double, W = 4 and 8, judged lane by lane by the exact
// oracle.
//
// Cases: the shared generators' cases (props_support.hpp, stratified and seeded as in
// ray_aabb_props.cpp). Case i gives the ray and a hard box for it; its packet holds that
// box in some lanes and, in the others, hard variants of it chosen by the case's own
// seed (Plan::choice): one bound moved by one or two ulps either way, the box made flat
// on one axis, the boxes of neighbouring cases of other generators, the box grown or
// shrunk by one ulp on every side, and empty slots (lo > hi, a NaN bound). Every lane is
// judged by the oracle against its own box:
//   - certified: the exact verdict and face, each t faithfully rounded, and the lane
//     equal bit for bit to the scalar certified query; portable and native backends
//     identical; verdict == intersect().mask;
//   - conservative: never a false miss, the interval encloses the exact one; verdict ==
//     intersect().mask;
//   - fast: verdict == intersect().mask, empty slots and invalid rays give bit 0; its
//     wrong verdicts are counted and printed, not asserted (fast promises nothing more).
// Conservative and certified are judged again on each case moved elsewhere in the
// exponent range by an exact power-of-two scaling.
// An empty slot (the oracle: invalid box) and every lane of an invalid ray must be bit 0
// with the fields of a miss, in every mode. A failure prints the suite seed, the case,
// the lane, its box in hexfloat and the command that reruns the case (the binary is
// ray_aabb_packet_props).
#include "props_support.hpp"

#include <rayproof/ray_aabb_packet.hpp>

namespace {

using namespace rayproof;
using Failure = std::optional<std::string>;

inline constexpr std::uint64_t kPacketSalt = 11;

template <class T> T ulps(T x, int k) {
    for (; k > 0; --k) x = std::nextafter(x, std::numeric_limits<T>::infinity());
    for (; k < 0; ++k) x = std::nextafter(x, -std::numeric_limits<T>::infinity());
    return x;
}

// The packet of case d: its box and hard variants of it, lane by lane.
template <class T, int W, class D> AabbPacket<T, W> packet_of(const D& d) {
    std::uint64_t s = d.choice(kPacketSalt);
    const auto next = [&s] {
        s = props::splitmix(s + 0x9e3779b97f4a7c15ull);
        return s;
    };
    const Aabb<T>& b = d.c.shape;
    AabbPacket<T, W> p;
    for (int k = 0; k < W; ++k) {
        Aabb<T> x = b;
        const int a = int(next() % 3);
        switch (next() % 8) {
            case 0:
            case 1: break;
            case 2: {
                const int n = int(next() % 4) - 2;
                if (next() & 1) x.lo[a] = ulps(x.lo[a], n == 0 ? 1 : n);
                else x.hi[a] = ulps(x.hi[a], n == 0 ? -1 : n);
                break;
            }
            case 3: x.lo[a] = x.hi[a] = (next() & 1) ? b.lo[a] : b.hi[a]; break;
            case 4: x = d.plan->make(d.index + 1 + std::uint64_t(k)).shape; break;
            case 5:
                if (next() & 1) std::swap(x.lo[a], x.hi[a]);
                else x.hi[a] = std::numeric_limits<T>::quiet_NaN();
                break;
            case 6:
                for (int i = 0; i < 3; ++i) x.lo[i] = ulps(x.lo[i], -1), x.hi[i] = ulps(x.hi[i], 1);
                break;
            default:
                for (int i = 0; i < 3; ++i) x.lo[i] = ulps(x.lo[i], 1), x.hi[i] = ulps(x.hi[i], -1);
                break;
        }
        p.set(k, x);
    }
    return p;
}

template <class T, int W> std::string lane_text(const Ray<T>& r, const AabbPacket<T, W>& p, int i) {
    std::ostringstream os;
    os << std::hexfloat << "lane " << i << " of W = " << W << ": ray " << r << " box " << p.box(i)
       << " (binary: ray_aabb_packet_props)";
    return os.str();
}

// Every lane of mode m against the oracle; extra(i, lane hit, exact) adds the mode's own
// checks.
template <class T, int W, class Mode, class D, class Extra>
Failure judge_lanes(const D& d, Mode m, Extra extra, std::uint64_t* wrong = nullptr) {
    const Ray<T>& r = d.c.ray;
    const AabbPacket<T, W> p = packet_of<T, W>(d);
    const PreparedRay<T> pr(r);
    const PacketHit<T, W> h = intersect(pr, p, m);
    const std::uint32_t v = verdict(pr, p, m);
    std::ostringstream os;
    if (v != h.mask) {
        os << mode_name(m) << ": verdict " << v << " != intersect().mask " << h.mask;
        return os.str();
    }
    for (int i = 0; i < W; ++i) {
        const Aabb<T> box = p.box(i);
        const auto e = oracle::exact(r, box);
        const Hit<T> x = h.lane(i);
        if (e.verdict == Verdict::invalid) {
            if (x.verdict != Verdict::miss || x.t_enter != 0 || x.t_exit != 0 || x.face != -1) {
                os << mode_name(m) << ": empty slot or invalid ray answered " << x << "; " << lane_text(r, p, i);
                return os.str();
            }
            continue;
        }
        const auto c = oracle::check_contract(r, box, x, e, m);
        if (wrong) *wrong += c.judgement.outcome == oracle::Outcome::false_hit ||
                             c.judgement.outcome == oracle::Outcome::false_miss;
        if (c.promise_broken()) {
            os << mode_name(m) << " lane " << x << "\n  " << e << "\n  " << c.mode_judgement() << "\n  "
               << lane_text(r, p, i);
            return os.str();
        }
        if (Failure f = extra(i, x, box)) return *f + "; " + lane_text(r, p, i);
    }
    return std::nullopt;
}

template <class P> class PacketProps : public ::testing::Test {};
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
TYPED_TEST_SUITE(PacketProps, Params, ParamNames);

}  // namespace

// certified: every lane exact (oracle) and equal to the scalar certified query bit for
// bit; the portable backend equals the native one.
TYPED_TEST(PacketProps, CertifiedLanesExactAndEqualScalar) {
    using T = typename TypeParam::type;
    constexpr int W = TypeParam::width;
    props::run_cases<T, Aabb<T>>([](const auto& d, auto) -> Failure {
        const Ray<T>& r = d.c.ray;
        const Failure f = judge_lanes<T, W>(d, certified, [&](int, const Hit<T>& x, const Aabb<T>& box) -> Failure {
            const Hit<T> s = intersect(r, box, certified);
            if (props::identical(x, s)) return std::nullopt;
            std::ostringstream os;
            os << "certified lane " << x << " != scalar certified " << s;
            return os.str();
        });
        if (f) return f;
        const AabbPacket<T, W> p = packet_of<T, W>(d);
        const PreparedRay<T> pr(r);
        const PacketHit<T, W> a = detail::packet_intersect<detail::simd::portable>(pr, p, certified),
                              b = detail::packet_intersect<detail::simd::native>(pr, p, certified);
        for (int i = 0; i < W; ++i)
            if (!props::identical(a.lane(i), b.lane(i))) {
                std::ostringstream os;
                os << "portable " << a.lane(i) << " != native (" << detail::simd::native_name() << ") "
                   << b.lane(i) << "; " << lane_text(r, p, i);
                return os.str();
            }
        if (detail::packet_verdict<detail::simd::portable>(pr, p, certified) != b.mask)
            return std::string("portable certified verdict != native mask");
        return std::nullopt;
    });
}

// conservative: never a false miss, the interval encloses the exact one.
TYPED_TEST(PacketProps, ConservativeLanesNeverMissAndEnclose) {
    using T = typename TypeParam::type;
    props::run_cases<T, Aabb<T>>([](const auto& d, auto) -> Failure {
        return judge_lanes<T, TypeParam::width>(d, conservative, [](int, const Hit<T>&, const Aabb<T>&) -> Failure { return std::nullopt; });
    });
}

// conservative and certified again, every lane judged by the oracle, on the case moved
// elsewhere in the exponent range by an exact power-of-two scaling (choose_scaling, the
// scalar suites' ScaledCaseMeetsContract draw): the lanes' bounds at every magnitude.
// Lanes that hold neighbouring cases' boxes keep their own magnitudes.
TYPED_TEST(PacketProps, ScaledLanesKeepPromises) {
    using T = typename TypeParam::type;
    props::run_cases<T, Aabb<T>>([](const auto& d, auto pick) -> Failure {
        const auto s = props::scaled_case(d.c, d.choice(props::kScaledOracleSalt), pick);
        if (!s) return std::nullopt;
        auto scaled = d;
        scaled.c = s->c;
        const auto none = [](int, const Hit<T>&, const Aabb<T>&) -> Failure { return std::nullopt; };
        Failure f = judge_lanes<T, TypeParam::width>(scaled, conservative, none);
        if (!f) f = judge_lanes<T, TypeParam::width>(scaled, certified, none);
        if (!f) return std::nullopt;
        std::ostringstream os;
        os << "after scaling by 2^" << s->k << ": " << *f;
        return os.str();
    });
}

// fast: only what it promises (verdict == mask, empty slots and invalid rays bit 0); its
// wrong verdicts against the oracle are counted and printed.
TYPED_TEST(PacketProps, FastLanesKeepEmptySlots) {
    using T = typename TypeParam::type;
    constexpr int W = TypeParam::width;
    std::uint64_t wrong = 0, lanes = 0;
    props::run_cases<T, Aabb<T>>([&](const auto& d, auto) -> Failure {
        lanes += W;
        return judge_lanes<T, W>(
            d, fast, [](int, const Hit<T>&, const Aabb<T>&) -> Failure { return std::nullopt; }, &wrong);
    });
    std::cout << "fast packet lanes: " << lanes << ", wrong verdicts " << wrong << '\n';
}
