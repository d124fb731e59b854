// ray_polyhedron_props.cpp — RapidCheck properties of ray vs convex polyhedron: rays
// through vertices and along edges, in face planes with ±0 components, duplicate and
// coincident planes, flat slabs, unbounded and infeasible sets, up to 64 planes, extreme
// magnitudes.
//
// Covered, for float and double, over every polyhedron generator (the cases own their
// planes, gen::OwnedPolyhedron; the shape asked is its view()), stratified and seeded as
// the other shapes' suites (strata.hpp, props_support.hpp: a failure prints the suite
// seed, the case, the command that reruns it alone, the call that rebuilds the input and
// the input in hexfloat): every mode answers invalid exactly for invalid inputs and
// keeps the form of its answers; conservative never misses an exact hit and encloses
// the exact interval; certified equals the exact oracle (verdict, face, faithfully
// rounded t); verdict() equals the full answer's verdict, scalar and batch; the batch
// form equals the scalar one (certified and conservative bit for bit); a PreparedRay
// answers as the Ray (certified bit for bit, conservative within its contract);
// conservative and certified against the oracle after an exact power-of-two scaling
// (the same geometry elsewhere in the exponent range); oracle-free invariants of
// certified under exact power-of-two scaling and ray reversal; and the fast mode's wrong
// answers counted per generator (printed); for float, every conservative hit a hit of
// the pass in double (the float stage adds no false hit).
#include "props_support.hpp"

#include <rayproof/prepared_ray.hpp>

namespace rayproof::props {

// The polyhedron cases are not the shape itself: the call that rebuilds one names the
// owning type.
template <> std::string reproducer<float, gen::OwnedPolyhedron<float>>(std::string_view generator, std::uint64_t seed) {
    std::ostringstream os;
    os << "rayproof::gen::make_case<float, rayproof::gen::OwnedPolyhedron<float>>(\"" << generator << "\", 0x"
       << std::hex << seed << ")";
    return os.str();
}
template <> std::string reproducer<double, gen::OwnedPolyhedron<double>>(std::string_view generator, std::uint64_t seed) {
    std::ostringstream os;
    os << "rayproof::gen::make_case<double, rayproof::gen::OwnedPolyhedron<double>>(\"" << generator << "\", 0x"
       << std::hex << seed << ")";
    return os.str();
}

}  // namespace rayproof::props

namespace {

using namespace rayproof;
using namespace rayproof::props;

template <class T> using Owned = gen::OwnedPolyhedron<T>;
using Failure = std::optional<std::string>;

template <class T, class F> void each_mode(F&& f) {
    f(fast);
    f(conservative);
    f(certified);
}
template <class Mode> constexpr bool is_fast = std::is_same_v<Mode, fast_t>;

template <class T> class PolyhedronProps : public ::testing::Test {};
TYPED_TEST_SUITE(PolyhedronProps, Scalars, ScalarNames);

// Every mode: invalid exactly when the oracle says invalid; the first breach of the mode's
// contract otherwise (fast: only validity and the form of a hit — no NaN t; conservative
// and certified their promises, the interval ordered in [t_min, t_max], the face a plane
// index or -1).
template <class T> Failure contract_failure(const Ray<T>& ray, const ConvexPolyhedron<T>& poly, bool only_invalid) {
    const auto e = oracle::exact(ray, poly);
    Failure failure;
    each_mode<T>([&](auto mode) {
        if (failure) return;
        const Hit<T> h = intersect(ray, poly, mode);
        const auto c = oracle::check_contract(ray, poly, h, e, mode);
        if (only_invalid ? !c.invalid_mismatch() : c.ok()) return;
        std::ostringstream os;
        os << mode_name(mode) << ": " << (c.ok() ? "invalid mismatch" : oracle::describe(c.first())) << "\n  answer "
           << h << "\n  " << e << "\n  " << c.mode_judgement();
        failure = os.str();
    });
    return failure;
}

TYPED_TEST(PolyhedronProps, InvalidVerdictAgreesWithOracle) {
    using T = TypeParam;
    run_cases<T, Owned<T>>([](const auto& d, auto) { return contract_failure(d.c.ray, d.c.shape.view(), true); });
}

TYPED_TEST(PolyhedronProps, EveryModeKeepsItsContract) {
    using T = TypeParam;
    run_cases<T, Owned<T>>([](const auto& d, auto) { return contract_failure(d.c.ray, d.c.shape.view(), false); });
}

// One mode's contract alone, so that a failure names the property of that mode.
template <class T, class Mode> void mode_contract(Mode mode) {
    run_cases<T, Owned<T>>([mode](const auto& d, auto) -> Failure {
        const ConvexPolyhedron<T> poly = d.c.shape.view();
        const auto e = oracle::exact(d.c.ray, poly);
        const Hit<T> h = intersect(d.c.ray, poly, mode);
        const auto c = oracle::check_contract(d.c.ray, poly, h, e, mode);
        if (c.ok()) return std::nullopt;
        std::ostringstream os;
        os << mode_name(mode) << ": " << oracle::describe(c.first()) << "\n  answer " << h << "\n  " << e << "\n  "
           << c.mode_judgement();
        return os.str();
    });
}

TYPED_TEST(PolyhedronProps, ConservativeNeverMissesAndEncloses) { mode_contract<TypeParam>(conservative); }
TYPED_TEST(PolyhedronProps, CertifiedEqualsOracle) { mode_contract<TypeParam>(certified); }

// Float input only: conservative mode's first stage runs the pass in float and answers a
// miss where its entry bound exceeds its exit bound, a hit where they lie 5·E_max apart
// or more (an exact hit then); the rest goes to the pass in double. So every conservative
// hit is a hit of the double pass: a float stage that answered near a graze would add
// false hits. (For double input the double pass is the first stage.)
TEST(PolyhedronFloatConservative, EveryHitIsAHitOfTheDoublePass) {
    using T = float;
    run_cases<T, Owned<T>>([](const auto& d, auto) -> Failure {
        const ConvexPolyhedron<T> poly = d.c.shape.view();
        const Hit<T> h = intersect(d.c.ray, poly, conservative);
        if (h.verdict != Verdict::hit) return std::nullopt;
        const Hit<T> g = detail::poly_conservative_double(d.c.ray, poly.planes);
        if (g.verdict == Verdict::hit) return std::nullopt;
        std::ostringstream os;
        os << "conservative " << h << ", the double pass " << g;
        return os.str();
    });
}

// verdict(), scalar and batch (the ray and its reverse), equals the full answer's verdict
// (in fast mode, its validity), and the certified one is the exact verdict.
TYPED_TEST(PolyhedronProps, VerdictQueryEqualsFullQuery) {
    using T = TypeParam;
    run_cases<T, Owned<T>>([](const auto& d, auto) -> Failure {
        const ConvexPolyhedron<T> poly = d.c.shape.view();
        const Verdict exact = oracle::exact(d.c.ray, poly).verdict;
        const std::vector<Ray<T>> rays{d.c.ray, reversed(d.c.ray)};
        Failure failure;
        each_mode<T>([&](auto mode) {
            if (failure) return;
            std::vector<Verdict> batch(rays.size());
            verdict(std::span<const Ray<T>>(rays), poly, mode, std::span<Verdict>(batch));
            for (std::size_t i = 0; i < rays.size() && !failure; ++i) {
                const Hit<T> full = intersect(rays[i], poly, mode);
                const Verdict alone = verdict(rays[i], poly, mode);
                const Verdict prepared = verdict(PreparedRay<T>(rays[i]), poly, mode);
                const bool certified_wrong = std::is_same_v<decltype(mode), certified_t> && i == 0 && alone != exact;
                // fast promises nothing: its verdict path and full query may round
                // differently where the compiler contracts them differently
                // (-ffp-contract=fast), so there they agree in validity only.
                const auto agree = [&](Verdict v) {
                    if constexpr (std::is_same_v<decltype(mode), fast_t>)
                        return (v == Verdict::invalid) == (full.verdict == Verdict::invalid);
                    return v == full.verdict;
                };
                if (!agree(alone) || !agree(batch[i]) || !agree(prepared) || certified_wrong) {
                    std::ostringstream os;
                    os << mode_name(mode) << (i ? " (reversed ray)" : "") << ": verdict() " << alone << ", batch "
                       << batch[i] << ", prepared " << prepared << ", full answer " << full << ", exact " << exact;
                    failure = os.str();
                }
            }
        });
        return failure;
    });
}

// The batch form equals the scalar one element by element: certified and conservative bit
// for bit, fast in validity (a vectorized path may round differently). The batch is case
// i's ray then n - 1 more rays of its generator (n in [1, 16], shrunk towards 1), against
// case i's polyhedron.
TYPED_TEST(PolyhedronProps, BatchEqualsScalar) {
    using T = TypeParam;
    run_cases<T, Owned<T>>([](const auto& d, auto pick) -> Failure {
        const auto& g = gen::generators<T, Owned<T>>()[d.plan->generator_of(d.index)];
        const auto n = std::size_t(pick(1 + int(d.choice(kBatchSalt) % 16), 1));
        gen::Rng rng(d.seed());
        const auto first = g.make(rng);  // == d.c
        std::vector<Ray<T>> rays{first.ray};
        while (rays.size() < n) rays.push_back(g.make(rng).ray);
        const ConvexPolyhedron<T> poly = first.shape.view();
        Failure failure;
        each_mode<T>([&](auto mode) {
            std::vector<Hit<T>> out(rays.size());
            intersect(std::span<const Ray<T>>(rays), poly, mode, std::span<Hit<T>>(out));
            for (std::size_t i = 0; i < rays.size() && !failure; ++i) {
                const Hit<T> s = intersect(rays[i], poly, mode);
                if (is_fast<decltype(mode)> ? (s.verdict == Verdict::invalid) != (out[i].verdict == Verdict::invalid)
                                            : !identical(s, out[i])) {
                    std::ostringstream os;
                    os << mode_name(mode) << " ray " << i << " of " << n << " " << rays[i] << ": batch " << out[i]
                       << ", scalar " << s;
                    failure = os.str();
                }
            }
        });
        return failure;
    });
}

// A PreparedRay answers as the Ray: certified bit for bit, conservative within its
// contract (and invalid exactly when the Ray form is), fast in validity.
TYPED_TEST(PolyhedronProps, PreparedRayEqualsRay) {
    using T = TypeParam;
    run_cases<T, Owned<T>>([](const auto& d, auto) -> Failure {
        const ConvexPolyhedron<T> poly = d.c.shape.view();
        const PreparedRay<T> prepared(d.c.ray);
        const auto e = oracle::exact(d.c.ray, poly);
        Failure failure;
        each_mode<T>([&](auto mode) {
            if (failure) return;
            const Hit<T> a = intersect(d.c.ray, poly, mode), b = intersect(prepared, poly, mode);
            bool ok = (a.verdict == Verdict::invalid) == (b.verdict == Verdict::invalid);
            if constexpr (std::is_same_v<decltype(mode), certified_t>) ok = identical(a, b);
            if constexpr (std::is_same_v<decltype(mode), conservative_t>)
                ok = ok && oracle::check_contract(d.c.ray, poly, b, e, mode).ok();
            if (!ok) {
                std::ostringstream os;
                os << mode_name(mode) << ": PreparedRay " << b << ", Ray " << a << "\n  " << e;
                failure = os.str();
            }
        });
        return failure;
    });
}

// The exact power-of-two scaling of a case that `choice` picks: positions and direction
// by 2^k and the normals by 2^j (offsets by 2^(k+j)), which leaves the exact answer (t
// too) unchanged; k != 0 drawn from the case (as choose_scaling does for the other
// shapes), halved with j until it scales exactly. Nothing when no tried k does. Under
// RapidCheck, k shrinks towards ±1 and j towards 0 (a shrunk pair that is not exact is
// discarded).
template <class T> struct ScaledPolyhedron {
    int k, j;
    gen::PolyCase<T> c;  // the scaled case
};
template <class T, class D, class Pick>
std::optional<ScaledPolyhedron<T>> scale_polyhedron(const D& d, std::uint64_t choice, Pick pick) {
    constexpr int E = std::numeric_limits<T>::max_exponent - std::numeric_limits<T>::min_exponent;
    const int sign = (choice & 1) ? -1 : 1;
    int k = sign * (1 + int((choice >> 1) % std::uint64_t(E))), j = int((choice >> 32) % std::uint64_t(E + 1)) - E / 2;
    auto c = d.c;
    const auto scale = [&](int kk, int jj) {
        c = d.c;
        const T t_min = c.ray.t_min, t_max = c.ray.t_max;  // kp == kd: t unchanged, ±inf kept
        c.ray.t_min = std::isinf(t_min) ? T(0) : t_min;
        c.ray.t_max = std::isinf(t_max) ? T(0) : t_max;
        const bool ok = gen::detail::scale_polyhedron_case(c, kk, kk, jj);
        c.ray.t_min = t_min;
        c.ray.t_max = t_max;
        return ok;
    };
    while (!scale(k, j) && (k / 2 != 0)) k /= 2, j /= 2;
    if (!scale(k, j)) return std::nullopt;  // nothing scales it exactly
    k = pick(k, k < 0 ? -1 : 1);
    j = pick(j, 0);
    if (!scale(k, j)) {
        RC_DISCARD("a shrunk exponent that does not scale exactly");
    }
    return ScaledPolyhedron<T>{k, j, c};
}

// Oracle-free: after an exact scaling (scale_polyhedron) certified gives the same
// verdict and face and each t the same or the adjacent float.
TYPED_TEST(PolyhedronProps, CertifiedPowerOfTwoScalingKeepsT) {
    using T = TypeParam;
    run_cases<T, Owned<T>>([](const auto& d, auto pick) -> Failure {
        const auto s = scale_polyhedron<T>(d, d.choice(kScaleSalt), pick);
        if (!s) return std::nullopt;
        const Hit<T> a = intersect(d.c.ray, d.c.shape.view(), certified);
        const Hit<T> b = intersect(s->c.ray, s->c.shape.view(), certified);
        if (a.verdict == b.verdict && a.face == b.face &&
            (a.verdict != Verdict::hit ||
             (same_or_adjacent(a.t_enter, b.t_enter) && same_or_adjacent(a.t_exit, b.t_exit))))
            return std::nullopt;
        std::ostringstream os;
        os << "certified " << a << " but after scaling by 2^" << s->k << " (normals 2^" << s->j << ") " << b
           << "\n  scaled " << s->c;
        return os.str();
    });
}

// Judged by the oracle: a case moved by its own exact scaling (another draw of k and j)
// to another part of the exponent range still gets conservative and certified answers
// that keep their promises against the exact answer of the scaled input: a bound that
// holds at one magnitude and not at another fails here.
TYPED_TEST(PolyhedronProps, ScaledCaseMeetsContract) {
    using T = TypeParam;
    run_cases<T, Owned<T>>([](const auto& d, auto pick) -> Failure {
        const auto s = scale_polyhedron<T>(d, d.choice(kScaledOracleSalt), pick);
        if (!s) return std::nullopt;
        const Ray<T>& ray = s->c.ray;
        const ConvexPolyhedron<T> poly = s->c.shape.view();
        const auto e = oracle::exact(ray, poly);
        Failure failure;
        const auto check = [&](auto mode) {
            if (failure) return;
            const Hit<T> h = intersect(ray, poly, mode);
            const auto c = oracle::check_contract(ray, poly, h, e, mode);
            if (c.ok()) return;
            std::ostringstream os;
            os << mode_name(mode) << " after scaling by 2^" << s->k << " (normals 2^" << s->j
               << "): " << oracle::describe(c.first()) << "\n  answer " << h << "\n  " << e << "\n  "
               << c.mode_judgement() << "\n  scaled " << s->c;
            failure = os.str();
        };
        check(conservative);
        check(certified);
        return failure;
    });
}

// Oracle-free: the reversed ray covers the same points, so its interval is the mirror
// [-t_exit, -t_enter] (each end the same or the other faithful rounding).
TYPED_TEST(PolyhedronProps, CertifiedReversalMirrorsInterval) {
    using T = TypeParam;
    run_cases<T, Owned<T>>([](const auto& d, auto) -> Failure {
        const ConvexPolyhedron<T> poly = d.c.shape.view();
        const Ray<T> r = reversed(d.c.ray);
        const Hit<T> a = intersect(d.c.ray, poly, certified);
        const Hit<T> b = intersect(r, poly, certified);
        if (a.verdict == b.verdict &&
            (a.verdict != Verdict::hit ||
             (same_or_adjacent(b.t_enter, T(-a.t_exit)) && same_or_adjacent(b.t_exit, T(-a.t_enter)))))
            return std::nullopt;
        std::ostringstream os;
        os << "certified " << a << " but reversed " << b << "\n  reversed ray " << r;
        return os.str();
    });
}

// The fast mode promises no accuracy: its wrong answers per generator are printed (and
// recorded as test properties). Asserted: each generator delivers what its name says (the
// invalid one only invalid inputs, the others only valid ones; the infeasible one only
// exact misses).
TYPED_TEST(PolyhedronProps, FastModeErrorsPerGenerator) {
    using T = TypeParam;
    constexpr int kCases = 2000;
    std::ostringstream table;
    table << "fast mode vs exact, polyhedron<" << gen::scalar_name<T>() << ">, " << kCases << " cases per generator:\n";
    for (const auto& g : gen::generators<T, Owned<T>>()) {
        gen::Rng rng(0xfa57 ^ gen::name_hash(g.name));
        oracle::Tally t;
        int invalid = 0, hits = 0;
        for (int i = 0; i < kCases; ++i) {
            const auto c = g.make(rng);
            const ConvexPolyhedron<T> poly = c.shape.view();
            const auto e = oracle::exact(c.ray, poly);
            const Hit<T> h = intersect(c.ray, poly, fast);
            const auto check = oracle::check_contract(c.ray, poly, h, e, fast);
            invalid += e.verdict == Verdict::invalid;
            hits += e.verdict == Verdict::hit;
            ++t.cases;
            t.count_outcome(check.judgement);
            if (h.verdict == Verdict::hit && e.verdict == Verdict::hit) t.count_interval(check.judgement);
            t.count_coherence(h);
        }
        EXPECT_EQ(invalid, g.name == "invalid" ? kCases : 0) << g.name;
        if (g.name == "infeasible") {
            EXPECT_EQ(hits, 0) << "the infeasible generator made a solid that is hit";
        }
        table << "  " << g.name << ": exact hits " << hits << ", wrong verdicts " << t.wrong() << " (false hits "
              << t.false_hit << ", false misses " << t.false_miss << "), face mismatches " << t.face_mismatch
              << ", t not faithful " << t.t_off << ", hits with t_enter > t_exit or NaN " << t.incoherent << '\n';
        ::testing::Test::RecordProperty(std::string(g.name) + "_wrong_verdicts", int(t.wrong()));
    }
    std::cout << table.str();
}

}  // namespace
