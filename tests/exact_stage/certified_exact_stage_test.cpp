// The certified mode's exact stage in isolation: every query is answered with the
// floating-point filter switched off (each enclosure is the whole line, so every
// comparison, every sign and every rounding of t goes to exact arithmetic), on the
// cases built to defeat a filter — exact ties at corners and edges, exact tangents,
// rays lying exactly in a plane, origins on boundaries, parallel rays, one-ulp
// neighbours of all of these, and extreme exponents — and judged by the CGAL oracle:
// verdict, face and faithful t must match exactly. Covers all four shapes over float
// and double. Also checks that the filtered certified answer is identical to the
// exact-stage answer, bit for bit, on the same cases (the filter may only decide what
// the exact stage would decide the same way), and that the certified box's, oriented
// box's, plane's and sphere's straight-line common paths agree bit for bit with the general paths
// wherever they answer, on every generator, and answer nearly every general-position case;
// the same for the certified verdict filters (Aabb, plane, sphere), and that the paths
// which check validity themselves decline every invalid variant of valid cases. The
// exact stage's faster routes are checked against its generic one: the box's slab
// values compared without the Expansion type, the oriented box's, the plane's and the
// polyhedron's comparisons from double-word pairs and fixed-size sums (the box's and the
// plane's also from exact rows and from a balanced copy of input too wide to rescale,
// with their roundings), the sphere's
// fixed-size sums (the
// discriminant's sign and the vertex) against the expansions, its tangent shortcut
// against the general path, and a touching point answered at both ends by the float
// at or below t*, as the search answers it.
#include <rayproof/generators.hpp>
#include <rayproof/oracle/oracle.hpp>
#include <rayproof/rayproof.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

namespace rayproof::detail {

inline constexpr Interval<double> kWholeLine{-std::numeric_limits<double>::infinity(),
                                             std::numeric_limits<double>::infinity()};

// A slab frame with the filter off: the sign of den and the parallel case decided in
// exact arithmetic from the frame's own num and den (the origin lies in the closed slab
// i when num(i, 0) = lo - o' <= 0 <= num(i, 1) = hi - o').
template <class T, class F> struct SlabExactOnly {
    const F& f;
    int den_sign(int i) const {
        return *with_exact(f.safe(), [&](auto tag) -> std::optional<int> {
            const auto d = f.template den<typename decltype(tag)::type>(i);
            if (d.overflowed()) return std::nullopt;
            return d.sign();
        });
    }
    bool inside_parallel(int i) const {
        return *with_exact(f.safe(), [&](auto tag) -> std::optional<bool> {
            using E = typename decltype(tag)::type;
            const E below = f.template num<E>(i, 0), above = f.template num<E>(i, 1);
            if (any_overflowed(below, above)) return std::nullopt;
            return below.sign() <= 0 && above.sign() >= 0;
        });
    }
    Interval<double> enclose(int, int) const { return kWholeLine; }
    template <class E> E num(int i, int side) const { return f.template num<E>(i, side); }
    template <class E> E den(int i) const { return f.template den<E>(i); }
    bool safe() const { return f.safe(); }
    auto scaled() const
        requires requires { f.scaled(); }
    {
        return f.scaled();
    }
    T faithful(int i, int side, const Interval<double>&, bool&) const { return exact_faithful<T>(*this, i, side); }
};

// A source's quotients without its scaled() (exact_compare then takes them as they are).
template <class F> struct Unscaled {
    const F& f;
    template <class E> E num(int i, int side) const { return f.template num<E>(i, side); }
    template <class E> E den(int i) const { return f.template den<E>(i); }
    bool safe() const { return f.safe(); }
};
static_assert(SlabFrame<SlabExactOnly<double, AabbFrame<double>>, double>);

template <class T> struct PlaneExactOnly : PlaneCrossing<T> {
    using PlaneCrossing<T>::PlaneCrossing;
    int den_sign() const { return this->den_sign_exact(); }
    bool in_plane() const { return this->in_plane_exact(); }
    Interval<double> enclose() const { return kWholeLine; }
    T faithful(const Interval<double>&, bool&) const { return exact_faithful<T>(*this, 0, 0); }
};

template <class T> struct SphereExactOnly : SphereQuadratic<T> {
    using SphereQuadratic<T>::SphereQuadratic;
    Interval<double> at(double) const { return kWholeLine; }
    Interval<double> slope(double) const { return kWholeLine; }
    Interval<double> discriminant() const { return kWholeLine; }
    // A residual that never decides.
    struct NoResidual {
        int sign_at(double) const { return 2; }
    };
    NoResidual residual() const { return {}; }
    std::pair<Interval<double>, Interval<double>> roots(const Interval<double>&) const { return {kWholeLine, kWholeLine}; }
};

template <class T> Hit<T> exact_stage(const Ray<T>& r, const Aabb<T>& b) {
    if (!valid(b) || !valid(r)) return invalid_hit<T>();
    const AabbFrame<T> f(r, b);
    return slab_certified(SlabExactOnly<T, AabbFrame<T>>{f}, r.t_min, r.t_max);
}
template <class T> Hit<T> exact_stage(const Ray<T>& r, const Obb<T>& b) {
    if (!valid(b) || !valid(r)) return invalid_hit<T>();
    const ObbFrame<T> f(r, b);
    return slab_certified(SlabExactOnly<T, ObbFrame<T>>{f}, r.t_min, r.t_max);
}
template <class T> Hit<T> exact_stage(const Ray<T>& r, const Plane<T>& p) {
    if (!valid(p) || !valid(r)) return invalid_hit<T>();
    return plane_certified(r, PlaneExactOnly<T>(r, p));
}
template <class T> Hit<T> exact_stage(const Ray<T>& r, const Sphere<T>& s) {
    if (!valid(s) || !valid(r)) return invalid_hit<T>();
    return sphere_certified(r, SphereExactOnly<T>(r, s));
}

}  // namespace rayproof::detail

namespace {

using namespace rayproof;

std::uint64_t seed() {
    const char* s = std::getenv("RAYPROOF_SEED");
    return s ? std::strtoull(s, nullptr, 0) : 20261121u;
}
int cases() {
    const char* s = std::getenv("RAYPROOF_EXACT_STAGE_CASES");
    return s ? std::atoi(s) : 1000;
}

template <class T> bool same_bits(T a, T b) { return std::memcmp(&a, &b, sizeof(T)) == 0 || (a == 0 && b == 0); }

template <class T, class Shape> void run_shape() {
    const std::uint64_t base = seed();
    int checked = 0;
    for (const auto& g : gen::generators<T, Shape>()) {
        const std::string_view name = g.name;
        if (name == "general" || name == "log_uniform" || name == "invalid") continue;  // not aimed at the filter
        gen::Rng rng(base);
        for (int k = 0; k < cases(); ++k) {
            const auto c = g.make(rng);
            const Hit<T> h = detail::exact_stage(c.ray, c.shape);
            const auto ex = oracle::exact(c.ray, c.shape);
            const auto j = oracle::judge(h, ex);
            std::ostringstream repro;
            repro << "generator " << name << " case " << k << " (RAYPROOF_SEED=" << base << "): " << c.ray << " vs "
                  << c.shape << "\n  exact stage: " << h << "\n  oracle: " << ex;
            ASSERT_TRUE(j.exact_match()) << repro.str() << "\n  " << j;
            const Hit<T> filtered = intersect(c.ray, c.shape, certified);
            ASSERT_EQ(filtered.verdict, h.verdict) << repro.str();
            if (h.verdict == Verdict::hit) {
                EXPECT_EQ(filtered.face, h.face) << repro.str();
                // Both are faithful; when the exact value is representable both are it.
                EXPECT_TRUE(oracle::judge(filtered, ex).exact_match()) << repro.str() << "\n  filtered: " << filtered;
            }
            ++checked;
        }
    }
    EXPECT_GT(checked, 0);
}

// Runs check(case, where, answered) on 4·cases() valid cases of every generator (where
// names the case and its seed); check sets answered when the path under test answered,
// and may ASSERT (the run stops at a fatal failure). On general-position input the path
// must answer nearly always: a path that declined everything would leave every other
// test green and the certified mode slow.
template <class T, class Shape, class Check> void on_valid_cases(const char* path, Check&& check) {
    const std::uint64_t base = seed();
    for (const auto& g : gen::generators<T, Shape>()) {
        const std::string_view name = g.name;
        gen::Rng rng(base);
        int answered = 0;
        const int n = 4 * cases();
        for (int k = 0; k < n; ++k) {
            const auto c = g.make(rng);
            if (!detail::valid(c.ray) || !detail::valid(c.shape)) continue;
            const std::string where = "generator " + std::string(name) + " case " + std::to_string(k) +
                                      " (RAYPROOF_SEED=" + std::to_string(base) + ")";
            bool a = false;
            check(c, where, a);
            if (::testing::Test::HasFatalFailure()) return;
            answered += a;
        }
        if (name == "general") {
            EXPECT_GE(answered, n - n / 100) << path << " answered " << answered << " of " << n;
        }
    }
}

// A straight-line path (aabb_, obb_, plane_, sphere_certified_common) against the general
// path: wherever the straight-line path answers, the two answers are identical bit for
// bit (verdict, face, t_enter, t_exit).
template <class T, class Shape, class Common, class General>
void common_agrees_with_general(Common&& common_path, General&& general_path) {
    on_valid_cases<T, Shape>("the straight-line path", [&](const auto& c, const std::string& where, bool& answered) {
        const std::optional<Hit<T>> common = common_path(c.ray, c.shape);
        if (!common) return;
        answered = true;
        const Hit<T> general = general_path(c.ray, c.shape);
        ASSERT_TRUE(common->verdict == general.verdict && common->face == general.face &&
                    same_bits(common->t_enter, general.t_enter) && same_bits(common->t_exit, general.t_exit))
            << where << ": " << c.ray << " vs " << c.shape << "\n  straight-line path: " << *common
            << "\n  general path: " << general;
    });
}

}  // namespace

// Whether t is a faithful rounding of the quotient v by the bare comparisons: v is t, or
// lies strictly between t and its neighbour on v's side (t = ±max encloses a quotient
// beyond it).
template <class Bare, class T> ::testing::AssertionResult faithful_by(const Bare& bare, const detail::SlabRef& v, T t) {
    const int s = detail::exact_compare(bare, v, {-1, 0, double(t)});  // sign(v - t)
    if (s == 0) return ::testing::AssertionSuccess();
    const T next = s > 0 ? std::nextafter(t, std::numeric_limits<T>::infinity())
                         : std::nextafter(t, -std::numeric_limits<T>::infinity());
    if (!std::isfinite(next) || detail::exact_compare(bare, v, {-1, 0, double(next)}) == -s)
        return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << "rounded to " << t << ": not faithful";
}

template <class T> class CertifiedExactStage : public ::testing::Test {};
using Scalars = ::testing::Types<float, double>;
TYPED_TEST_SUITE(CertifiedExactStage, Scalars);

TYPED_TEST(CertifiedExactStage, Aabb) { run_shape<TypeParam, Aabb<TypeParam>>(); }
TYPED_TEST(CertifiedExactStage, Obb) { run_shape<TypeParam, Obb<TypeParam>>(); }
TYPED_TEST(CertifiedExactStage, Plane) { run_shape<TypeParam, Plane<TypeParam>>(); }
TYPED_TEST(CertifiedExactStage, Sphere) { run_shape<TypeParam, Sphere<TypeParam>>(); }
// The Aabb's exact comparisons through its frame, which compares without an expansion
// type at any scale where its differences p - o are exact or its products are
// (compare_at_any_scale: compare_slab_values, exact.hpp) and otherwise at a safer scale
// where the input is not safe (AabbScaledQuotients), decide as its bare quotients in
// expansions or BigDyadic:
// on every valid case of every generator, every pair among the slab values of the
// non-parallel axes and the constants t_min, t_max, 0, the slab values' rounded
// estimates and their neighbours (near ties) has the same exact_compare sign both ways,
// and so has the rescaled source on its own wherever it exists (every pair whose
// constants it scales exactly); and for double the rescaled source exists on many of
// the cases (extreme exponents, scaled integer configurations) and is the route taken
// on some pairs (a difference with an error term and a product beyond the exact range).
TYPED_TEST(CertifiedExactStage, AabbFrameComparisonsDecideAsTheBareQuotients) {
    using T = TypeParam;
    int scaled_cases = 0, scaled_route = 0;
    on_valid_cases<T, Aabb<T>>("the comparisons", [&](const auto& c, const std::string& where, bool& answered) {
        answered = true;
        const detail::AabbFrame<T> f(c.ray, c.shape);
        const detail::Unscaled<detail::AabbFrame<T>> bare{f};
        const bool scaled = !f.safe() && f.scaled().has_value();
        scaled_cases += scaled;
        std::vector<detail::SlabRef> refs{{-1, 0, c.ray.t_min}, {-1, 0, c.ray.t_max}, {-1, 0, 0.0}};
        for (int i = 0; i < 3; ++i) {
            if (c.ray.direction[i] == 0) continue;
            for (int side = 0; side < 2; ++side) {
                refs.push_back({i, side, 0});
                const double est = (double(side ? c.shape.hi[i] : c.shape.lo[i]) - double(c.ray.origin[i])) /
                                   double(c.ray.direction[i]);
                if (std::isfinite(est))
                    for (const double v : {est, std::nextafter(est, -HUGE_VAL), std::nextafter(est, HUGE_VAL)})
                        refs.push_back({-1, 0, v});
            }
        }
        for (const auto& a : refs)
            for (const auto& b : refs) {
                if (a.axis < 0 && b.axis < 0) continue;
                const int expected = detail::exact_compare(bare, a, b);
                ASSERT_EQ(detail::exact_compare(f, a, b), expected)
                    << where << ": " << c.ray << " vs " << c.shape << "\n  refs (" << a.axis << ", " << a.side << ", "
                    << a.c << ") and (" << b.axis << ", " << b.side << ", " << b.c << ")";
                if (!scaled) continue;
                scaled_route += !f.compare_at_any_scale(a, b).has_value();
                const auto& sc = *f.scaled();
                detail::SlabRef sa = a, sb = b;
                if ((a.axis >= 0 || detail::scale_exactly(a.c, sc.shift(), sa.c)) &&
                    (b.axis >= 0 || detail::scale_exactly(b.c, sc.shift(), sb.c))) {
                    ASSERT_EQ(detail::exact_compare(sc, sa, sb), expected)
                        << where << ", rescaled: " << c.ray << " vs " << c.shape << "\n  refs (" << a.axis << ", "
                        << a.side << ", " << a.c << ") and (" << b.axis << ", " << b.side << ", " << b.c << ")";
                }
            }
    });
    if constexpr (std::is_same_v<T, double>) {  // every float is safe
        EXPECT_GT(scaled_cases, 100) << "the scaled comparisons should be exercised";
        EXPECT_GT(scaled_route, 100) << "inexact differences beyond the exact range should take the rescaled values";
    }
}

// The routes an affine frame's exact side (AffineSource: the Obb's frame, the plane's
// crossing) took over a test's cases: its sums on the given input, safe for expansions
// (quick); the rescaled input (scaled, which must itself be safe); a quick comparison
// deciding on input not safe (checked: every product checked, the sums scaled apart);
// the balanced copy of input too wide to rescale (AffineQuotients::balanced), whose
// own comparisons and roundings are checked here against the bare quotients
// (balanced_agrees), since the frame's answers may also come from the given input; and
// the roundings word_faithful answered (from the pairs, or from an exact row); and the
// comparisons the exact rows decided (compare_at_any_scale).
struct AffineRoutes {
    int quick = 0, scaled = 0, checked = 0, balanced = 0, balanced_decided = 0, balanced_rounded = 0, word_rounded = 0,
        exact_rows = 0;
    template <class F> ::testing::AssertionResult count(const F& f) {
        quick += f.safe();
        if (f.safe() || !f.scaled()) return ::testing::AssertionSuccess();
        ++scaled;
        if (f.scaled()->safe()) return ::testing::AssertionSuccess();
        return ::testing::AssertionFailure() << "the rescaled input is not safe for expansions";
    }
    // Where f's input is not safe and has no rescaled copy: the balanced copy of its
    // values v, where it exists, compares every pair of refs (constants scaled by its
    // shift, where exactly) as the bare quotients do wherever it answers, and rounds each
    // of the values (axis, side) faithfully (quick_faithful, scaled back by
    // unscaled_faithful) wherever it answers.
    template <int R, class F, class Bare>
    ::testing::AssertionResult balanced_agrees(const F& f, const Bare& bare, const detail::AffineValues<R>& v,
                                               const std::vector<detail::SlabRef>& refs,
                                               const std::vector<std::pair<int, int>>& values) {
        if (f.safe() || f.scaled()) return ::testing::AssertionSuccess();
        const std::optional<detail::AffineQuotients<R>> w = detail::AffineQuotients<R>::balanced(v);
        if (!w) return ::testing::AssertionSuccess();
        ++balanced;
        for (const auto& a : refs)
            for (const auto& b : refs) {
                if (a.axis < 0 && (b.axis < 0 || std::isinf(a.c))) continue;
                if (b.axis < 0 && std::isinf(b.c)) continue;
                detail::SlabRef wa = a, wb = b;
                if ((a.axis < 0 && !detail::scale_exactly(a.c, w->shift(), wa.c)) ||
                    (b.axis < 0 && !detail::scale_exactly(b.c, w->shift(), wb.c)))
                    continue;
                const std::optional<int> q = w->quick_compare(wa, wb);
                if (!q) continue;
                ++balanced_decided;
                const int s = detail::exact_compare(bare, a, b);
                if (*q != s)
                    return ::testing::AssertionFailure() << "the balanced copy (shift " << w->shift() << ") compares refs ("
                                                         << a.axis << ", " << a.side << ", " << a.c << ") and (" << b.axis
                                                         << ", " << b.side << ", " << b.c << ") as " << *q << ", not " << s;
            }
        for (const auto& [i, side] : values) {
            const std::optional<double> g = w->template quick_faithful<double>(i, side);
            const std::optional<double> t = g ? detail::unscaled_faithful(*g, w->shift()) : std::nullopt;
            if (!t) continue;
            ++balanced_rounded;
            if (::testing::AssertionResult r = faithful_by(bare, {i, side, 0}, *t); !r)
                return r << " (the balanced copy's rounding of value (" << i << ", " << side << "), shift " << w->shift()
                         << ")";
        }
        return ::testing::AssertionSuccess();
    }
    // Each route taken often enough to be tested (for double: every float is safe).
    template <class T> void expect_exercised(int checked_at_least, int balanced_at_least, int rounded_at_least) const {
        EXPECT_GT(quick, 1000) << "the quick decisions should be exercised";
        EXPECT_GT(word_rounded, 1000) << "the roundings from the pairs and the exact rows should answer";
        EXPECT_GT(exact_rows, 1000) << "the comparisons from the exact rows should decide";
        if constexpr (std::is_same_v<T, double>) {
            EXPECT_GT(scaled, 100) << "the scaled decisions should be exercised";
            EXPECT_GT(checked, checked_at_least) << "the checked quick comparisons (input not safe) should decide";
            EXPECT_GT(balanced_decided, balanced_at_least) << "the balanced copy's comparisons should decide";
            EXPECT_GT(balanced_rounded, rounded_at_least) << "the balanced copy's roundings should answer";
        }
    }
};

// The oriented box's exact decisions through its frame, which takes them without an
// expansion type (ObbQuotients: quick_compare, quick_faithful and the signs of num and
// den, from sums of error-free products) and, where the input is not safe, at a safer
// scale (ObbQuotients::rescaled, which also rounds there for double), decide as its
// bare quotients in expansions or BigDyadic, on every valid case of every generator:
// the sign of each d'_i and whether the origin lies in each slab; every pair among the
// slab values of the non-parallel axes and the constants t_min, t_max, 0, the slab
// values' rounded estimates and their neighbours has the same exact_compare sign both
// ways (and quick_compare's where it answers, on input not safe too, its checked
// route); and each slab value's exact_faithful t is a faithful rounding by the bare
// comparisons (the exact value, or strictly between t and its neighbour on the side
// the sign gives), and so is word_faithful's wherever it answers (from the pairs, or
// from an exact row: affine_exact_row, which also decides the comparisons and signs it
// can, first). The rescaled input must lie in the safe range, and both routes must
// be exercised.
TYPED_TEST(CertifiedExactStage, ObbFrameComparisonsDecideAsTheBareQuotients) {
    using T = TypeParam;
    AffineRoutes routes;
    on_valid_cases<T, Obb<T>>("the comparisons", [&](const auto& c, const std::string& where, bool& answered) {
        answered = true;
        const detail::ObbFrame<T> f(c.ray, c.shape);
        const detail::Unscaled<detail::ObbFrame<T>> bare{f};
        const std::string what = where + ": " + ::testing::PrintToString(c.ray) + " vs " + ::testing::PrintToString(c.shape);
        ASSERT_TRUE(routes.count(f)) << what;
        for (int i = 0; i < 3; ++i) {  // the exact signs of den and num, as the bare quotients give them
            const auto bare_sign = [&](auto value) {
                return detail::exact_sign(f.safe(), [&](auto tag) { return value(tag); });
            };
            const int den = bare_sign([&](auto tag) { return f.template den<typename decltype(tag)::type>(i); });
            ASSERT_EQ(f.exact_den_sign(i), den) << what << ": the sign of d'_" << i;
            const int above = bare_sign([&](auto tag) { return f.template num<typename decltype(tag)::type>(i, 1); }),
                      below = bare_sign([&](auto tag) { return f.template num<typename decltype(tag)::type>(i, 0); });
            ASSERT_EQ(f.inside_parallel_exact(i), above >= 0 && below <= 0) << what << ": the origin in slab " << i;
        }
        std::vector<detail::SlabRef> refs{{-1, 0, c.ray.t_min}, {-1, 0, c.ray.t_max}, {-1, 0, 0.0}};
        std::vector<std::pair<int, int>> values;
        for (int i = 0; i < 3; ++i) {
            if (f.den_sign(i) == 0) continue;
            const Vec3<double> a = c.shape.axes.col(i).template cast<double>();
            const double op = a.dot(c.ray.origin.template cast<double>() - c.shape.center.template cast<double>()),
                         dp = a.dot(c.ray.direction.template cast<double>());
            for (int side = 0; side < 2; ++side) {
                refs.push_back({i, side, 0});
                values.emplace_back(i, side);
                const double h = c.shape.half_extent[i], est = ((side ? h : -h) - op) / dp;
                if (std::isfinite(est))
                    for (const double v : {est, std::nextafter(est, -HUGE_VAL), std::nextafter(est, HUGE_VAL)})
                        refs.push_back({-1, 0, v});
            }
        }
        bool checked = false;
        for (const auto& a : refs)
            for (const auto& b : refs) {
                if (a.axis < 0 && b.axis < 0) continue;
                ASSERT_EQ(detail::exact_compare(f, a, b), detail::exact_compare(bare, a, b))
                    << what << "\n  refs (" << a.axis << ", " << a.side << ", " << a.c << ") and (" << b.axis << ", "
                    << b.side << ", " << b.c << ")";
                if (std::isinf(a.c) || std::isinf(b.c)) continue;  // exact_compare's own, before quick_compare
                if (const std::optional<int> q = f.quick_compare(a, b)) {
                    ASSERT_EQ(*q, detail::exact_compare(bare, a, b)) << what << ": quick_compare";
                    checked = checked || !f.safe();
                }
                if (const std::optional<int> q = f.compare_at_any_scale(a, b)) {
                    ASSERT_EQ(*q, detail::exact_compare(bare, a, b)) << what << ": from the exact rows";
                    ++routes.exact_rows;
                }
            }
        routes.checked += checked;
        for (const auto& [i, side] : values) {
            ASSERT_TRUE(faithful_by(bare, {i, side, 0}, detail::exact_faithful<T>(f, i, side)))
                << what << "\n  slab value (" << i << ", " << side << ")";
            if (const std::optional<T> w = f.template word_faithful<T>(i, side)) {
                ASSERT_TRUE(faithful_by(bare, {i, side, 0}, *w)) << what << "\n  slab value (" << i << ", " << side
                                                                 << ") from the pairs";
                ++routes.word_rounded;
            }
        }
        ASSERT_TRUE(routes.balanced_agrees(f, bare, detail::obb_values(c.ray, c.shape), refs, values)) << what;
    });
    routes.expect_exercised<T>(100, 100000, 2000);
}

// The plane's exact decisions through its crossing, which takes them from fixed-size
// sums (AffineQuotients: quick_compare, the signs of num and den) and, where the input
// is not safe, at a safer scale (AffineQuotients::rescaled, which also rounds t there
// for double), decide as its bare quotient in expansions or BigDyadic: on every valid
// case of every generator, the crossing against t_min, t_max, 0, its rounded estimate
// and their neighbours has the same exact_compare sign both ways (and quick_compare's
// where it answers); the signs of den and num (the ray in the plane) are the bare ones;
// and exact_faithful's t, and word_faithful's where it answers, are faithful roundings
// by the bare comparisons. Both the rescaled and the checked routes must be exercised.
TYPED_TEST(CertifiedExactStage, PlaneCrossingDecidesAsTheBareQuotient) {
    using T = TypeParam;
    AffineRoutes routes;
    on_valid_cases<T, Plane<T>>("the crossing", [&](const auto& c, const std::string& where, bool& answered) {
        answered = true;
        const detail::PlaneCrossing<T> x(c.ray, c.shape);
        const detail::Unscaled<detail::PlaneCrossing<T>> bare{x};
        const std::string what = where + ": " + ::testing::PrintToString(c.ray) + " vs " + ::testing::PrintToString(c.shape);
        ASSERT_TRUE(routes.count(x)) << what;
        const auto bare_sign = [&](auto value) {
            return detail::exact_sign(x.safe(), [&](auto tag) { return value(tag); });
        };
        const int den = bare_sign([&](auto tag) { return x.template den<typename decltype(tag)::type>(0); });
        ASSERT_EQ(x.den_sign_exact(), den) << what << ": the sign of n·d";
        if (den == 0) {
            const int num = bare_sign([&](auto tag) { return x.template num<typename decltype(tag)::type>(0, 0); });
            ASSERT_EQ(x.in_plane_exact(), num == 0) << what << ": the ray in the plane";
            return;
        }
        const detail::SlabRef t{0, 0, 0};
        std::vector<detail::SlabRef> refs{{-1, 0, c.ray.t_min}, {-1, 0, c.ray.t_max}, {-1, 0, 0.0}};
        const double n = c.shape.normal.template cast<double>().dot(c.ray.origin.template cast<double>()),
                     d = c.shape.normal.template cast<double>().dot(c.ray.direction.template cast<double>()),
                     est = (double(c.shape.offset) - n) / d;
        if (std::isfinite(est))
            for (const double v : {est, std::nextafter(est, -HUGE_VAL), std::nextafter(est, HUGE_VAL)}) refs.push_back({-1, 0, v});
        bool checked = false;
        for (const auto& r : refs) {
            const int s = detail::exact_compare(bare, t, r);
            ASSERT_EQ(detail::exact_compare(x, t, r), s) << what << "\n  against " << r.c;
            ASSERT_EQ(detail::exact_compare(x, r, t), -s) << what << "\n  against " << r.c;
            if (std::isinf(r.c)) continue;  // exact_compare's own, before quick_compare
            if (const std::optional<int> q = x.quick_compare(t, r)) {
                ASSERT_EQ(*q, s) << what << ": quick_compare against " << r.c;
                checked = checked || !x.safe();
            }
            if (const std::optional<int> q = x.compare_at_any_scale(t, r)) {
                ASSERT_EQ(*q, s) << what << ": from the exact row, against " << r.c;
                ++routes.exact_rows;
            }
        }
        routes.checked += checked;
        ASSERT_TRUE(faithful_by(bare, t, detail::exact_faithful<T>(x, 0, 0))) << what;
        if (const std::optional<T> w = x.template word_faithful<T>(0, 0)) {
            ASSERT_TRUE(faithful_by(bare, t, *w)) << what << ": from the pairs";
            ++routes.word_rounded;
        }
        refs.push_back(t);
        ASSERT_TRUE(routes.balanced_agrees(x, bare, detail::plane_values(c.ray, c.shape), refs, {{0, 0}})) << what;
    });
    routes.expect_exercised<T>(20, 3000, 200);
}

// The polyhedron's exact decisions through its source (PolySource), which takes them
// first from the double-word pairs and the fixed-size sums (quick_compare, the signs of
// num and den) on the input as given where it is safe, else scaled into the safe range
// (affine_shifts), else from sums with checked products, decide as its bare quotients
// in expansions or BigDyadic: on valid cases of every polyhedron generator, the sign of
// each plane's den and num, and every pair among the crossings of the planes not
// parallel to the ray and the constants t_min, t_max, 0, the crossings' rounded
// estimates and their neighbours (quick_compare's sign where it answers, and
// exact_compare's). Inputs the safe range does not hold must be reached, and decided
// there.
TYPED_TEST(CertifiedExactStage, PolySourceComparisonsDecideAsTheBareQuotients) {
    using T = TypeParam;
    const std::uint64_t base = seed();
    long quick = 0, quick_unsafe = 0;
    for (const auto& g : gen::generators<T, gen::OwnedPolyhedron<T>>()) {
        gen::Rng rng(base);
        for (int k = 0; k < cases(); ++k) {
            const auto c = g.make(rng);
            const ConvexPolyhedron<T> p = c.shape.view();
            if (!detail::valid(c.ray) || !detail::valid(p)) continue;
            const detail::PolySource<T> src(c.ray, p.planes);
            const detail::Unscaled<detail::PolySource<T>> bare{src};
            const std::string what = "generator " + std::string(g.name) + " case " + std::to_string(k) +
                                     " (RAYPROOF_SEED=" + std::to_string(base) + "): " + ::testing::PrintToString(c.ray) +
                                     " vs " + ::testing::PrintToString(c.shape);
            const auto bare_sign = [&](auto value) {
                return detail::exact_sign(src.safe(), [&](auto tag) { return value(tag); });
            };
            std::vector<detail::SlabRef> refs{{-1, 0, c.ray.t_min}, {-1, 0, c.ray.t_max}, {-1, 0, 0.0}};
            for (int j = 0; j < int(p.planes.size()); ++j) {
                const int den = bare_sign([&](auto tag) { return src.template den<typename decltype(tag)::type>(j); }),
                          num = bare_sign([&](auto tag) { return src.template num<typename decltype(tag)::type>(j); });
                ASSERT_EQ(src.den_sign(j), den) << what << ": the sign of den_" << j;
                ASSERT_EQ(src.num_sign(j), num) << what << ": the sign of num_" << j;
                if (den == 0) continue;
                refs.push_back({j, 0, 0});
                const Plane<T>& q = p.planes[std::size_t(j)];
                const double n = q.normal.template cast<double>().dot(c.ray.origin.template cast<double>()),
                             d = q.normal.template cast<double>().dot(c.ray.direction.template cast<double>()),
                             est = (double(q.offset) - n) / d;
                if (std::isfinite(est))
                    for (const double v : {est, std::nextafter(est, -HUGE_VAL), std::nextafter(est, HUGE_VAL)})
                        refs.push_back({-1, 0, v});
            }
            for (const auto& a : refs)
                for (const auto& b : refs) {
                    if ((a.axis < 0 && b.axis < 0) || std::isinf(a.c) || std::isinf(b.c)) continue;
                    const int s = detail::exact_compare(bare, a, b);
                    ASSERT_EQ(detail::exact_compare(src, a, b), s)
                        << what << "\n  refs (" << a.axis << ", " << a.c << ") and (" << b.axis << ", " << b.c << ")";
                    if (const std::optional<int> q = src.quick_compare(a, b)) {
                        ASSERT_EQ(*q, s) << what << ": quick_compare, refs (" << a.axis << ", " << a.c << ") and ("
                                         << b.axis << ", " << b.c << ")";
                        ++quick;
                        quick_unsafe += !src.safe();
                    }
                }
        }
    }
    EXPECT_GT(quick, 10000);
    if constexpr (std::is_same_v<T, double>) {  // every float is safe
        EXPECT_GT(quick_unsafe, 1000);
    }
}

// The sphere's exact signs on the rescaled input (SphereQuadratic, where the given one
// is not safe for expansions) are those on the given input: on every valid case of
// every generator, sign q(t) and sign(a t + b) at t_min, 0, t_max, the estimated roots
// and their neighbours, the vertex and its neighbours, and the discriminant's sign; the
// residual (rescaled alike) decides only those signs; the slope's sign from the
// vertex is the exact one at every such t, and on a tangent line (discriminant 0) so
// is q's sign from the vertex alone; and the rescaling applies to many of the cases
// (extreme exponents, scaled integer configurations).
TEST(CertifiedExactStageDouble, SphereRescaledSignsAreTheGivenOnes) {
    using T = double;
    int rescalable = 0, residual_decided = 0, tangents = 0;
    on_valid_cases<T, Sphere<T>>("the signs", [&](const auto& c, const std::string& where, bool& answered) {
        answered = true;
        const detail::SphereQuadratic<T> q(c.ray, c.shape);
        detail::ExponentSpan positions, directions;
        bool safe = detail::expansion_safe(c.shape.radius);
        positions.add(c.shape.radius);
        for (int j = 0; j < 3; ++j) {
            positions.add(c.ray.origin[j]);
            positions.add(c.shape.center[j]);
            directions.add(c.ray.direction[j]);
            safe = safe && detail::expansion_safe(c.ray.origin[j]) && detail::expansion_safe(c.shape.center[j]) &&
                   detail::expansion_safe(c.ray.direction[j]);
        }
        rescalable += !safe && positions.safe_shift() && directions.safe_shift();
        const std::string what = where + ": " + ::testing::PrintToString(c.ray) + " vs " + ::testing::PrintToString(c.shape);
        ASSERT_EQ(q.sign_discriminant(), q.sign_discriminant(false)) << what;
        std::vector<double> ts{0.0};
        for (const T t : {c.ray.t_min, c.ray.t_max})
            if (std::isfinite(t)) ts.push_back(t);
        const auto [r0, r1] = q.roots(q.discriminant());
        for (const double m : {r0.mid(), r1.mid()})
            if (std::isfinite(m))
                for (const double t : {m, std::nextafter(m, -HUGE_VAL), std::nextafter(m, HUGE_VAL)}) ts.push_back(t);
        const auto residual = q.residual();
        const auto vertex = q.vertex();
        const bool tangent = q.sign_discriminant(false) == 0;
        tangents += tangent;
        for (const double m : {vertex.f, std::nextafter(vertex.f, -HUGE_VAL), std::nextafter(vertex.f, HUGE_VAL)})
            if (std::isfinite(m)) ts.push_back(m);
        for (const double t : ts) {
            const int s = q.sign_at(t, false);
            ASSERT_EQ(q.sign_at(t), s) << what << ", t = " << t;
            const int slope = q.sign_slope(t, false);
            ASSERT_EQ(q.sign_slope(t), slope) << what << ", t = " << t;
            ASSERT_EQ(vertex.slope_sign(t), slope) << what << ", t = " << t << ": the vertex's slope sign";
            if (tangent) {  // q(t) = a (t - t*)²
                ASSERT_EQ(vertex.side == 0 && t == vertex.f ? 0 : 1, s) << what << ", t = " << t << ": a tangent";
            }
            const int r = residual.sign_at(t);
            if (r != 2) {
                ASSERT_EQ(r, s) << what << ", t = " << t << ": the residual's sign";
                ++residual_decided;
            }
        }
    });
    EXPECT_GT(rescalable, 100) << "the rescaled signs should be exercised";
    EXPECT_GT(residual_decided, 100) << "the residual should decide some of them";
    EXPECT_GT(tangents, 100) << "exact tangents should be among the cases";
}

TYPED_TEST(CertifiedExactStage, AabbStraightLinePathAgreesWithGeneralPath) {
    using T = TypeParam;
    common_agrees_with_general<T, Aabb<T>>([](const Ray<T>& r, const Aabb<T>& b) { return detail::aabb_certified_common(r, b); },
                                           [](const Ray<T>& r, const Aabb<T>& b) { return detail::aabb_certified_general(r, b); });
}
// The box's second stage (aabb_certified_stage, over the straight-line path's values and
// bounds) answers as the general path, bit for bit, on every valid case the
// straight-line path declines with usable lanes (rays through edges and corners, near
// ties, winners outside the correction's range), and so does the whole declined path
// (the stage where the lanes are usable, the general path otherwise) on every valid case.
TYPED_TEST(CertifiedExactStage, AabbSecondStageAgreesWithGeneralPath) {
    using T = TypeParam;
    int staged = 0;
    on_valid_cases<T, Aabb<T>>("the second stage", [&](const auto& c, const std::string& where, bool& answered) {
        answered = true;
        const Hit<T> general = detail::aabb_certified_general(c.ray, c.shape);
        const auto same = [&](const Hit<T>& h) {
            return h.verdict == general.verdict && h.face == general.face && same_bits(h.t_enter, general.t_enter) &&
                   same_bits(h.t_exit, general.t_exit);
        };
        const Hit<T> declined = detail::aabb_certified_declined(c.ray, c.shape);
        ASSERT_TRUE(same(declined)) << where << ": " << c.ray << " vs " << c.shape << "\n  declined path: " << declined
                                    << "\n  general path: " << general;
        const detail::AabbLanes L = detail::aabb_lanes(c.ray, c.shape);
        if (detail::aabb_certified_common(c.ray, c.shape) || detail::lanes::bits(L.usable) != 3) return;
        ++staged;
        const Hit<T> stage = detail::aabb_certified_stage(c.ray, c.shape, L.V);
        ASSERT_TRUE(same(stage)) << where << ": " << c.ray << " vs " << c.shape << "\n  second stage: " << stage
                                 << "\n  general path: " << general;
    });
    EXPECT_GT(staged, 1000) << "the second stage should be exercised";
}

// A verdict filter (the certified verdict query's straight-line path): wherever it
// answers, the general path's verdict; it answers nearly every general-position case;
// and whatever full_answers says the full query's straight-line path answers, it
// answers too (for the Aabb, whose filter needs a subset of the full path's conditions).
template <class T, class Shape, class Filter, class General, class FullAnswers>
void verdict_filter_agrees(Filter&& filter, General&& general_path, FullAnswers&& full_answers) {
    on_valid_cases<T, Shape>("the verdict path", [&](const auto& c, const std::string& where, bool& answered) {
        const int v = filter(c.ray, c.shape);
        if (full_answers(c.ray, c.shape)) {
            ASSERT_NE(v, detail::verdict_declined) << where << ": the full path answered, the verdict path declined";
        }
        if (v == detail::verdict_declined) return;
        answered = true;
        ASSERT_EQ(Verdict(v), general_path(c.ray, c.shape).verdict) << where << ": " << c.ray << " vs " << c.shape;
    });
}

// Invalid variants of a valid case: each number of the ray and of the shape replaced by
// NaN, +inf and -inf in turn, the limits made invalid, the direction zero, and the
// shape's own rules broken (an Aabb's lo and hi swapped, a plane's normal zero, a
// negative radius).
// The numbers of each value that must be finite (the ray's limits have rules of their own).
template <class T> std::vector<T*> finite_numbers(Ray<T>& r) {
    return {&r.origin[0], &r.origin[1], &r.origin[2], &r.direction[0], &r.direction[1], &r.direction[2]};
}
template <class T> std::vector<T*> finite_numbers(Aabb<T>& b) {
    return {&b.lo[0], &b.lo[1], &b.lo[2], &b.hi[0], &b.hi[1], &b.hi[2]};
}
template <class T> std::vector<T*> finite_numbers(Plane<T>& p) { return {&p.normal[0], &p.normal[1], &p.normal[2], &p.offset}; }
template <class T> std::vector<T*> finite_numbers(Sphere<T>& s) { return {&s.center[0], &s.center[1], &s.center[2], &s.radius}; }
// x with each of its finite_numbers replaced by NaN, +inf and -inf in turn.
template <class T, class X> void non_finite_variants(const X& x, std::vector<X>& out) {
    X probe = x;
    const std::size_t n = finite_numbers(probe).size();
    for (const T v : {std::numeric_limits<T>::quiet_NaN(), std::numeric_limits<T>::infinity(), -std::numeric_limits<T>::infinity()})
        for (std::size_t k = 0; k < n; ++k) {
            X y = x;
            *finite_numbers(y)[k] = v;
            out.push_back(y);
        }
}
template <class T> void shape_variants(const Aabb<T>& s, std::vector<Aabb<T>>& out) {
    non_finite_variants<T>(s, out);
    for (int i = 0; i < 3; ++i) {
        if (s.lo[i] < s.hi[i]) {
            Aabb<T> b = s;
            std::swap(b.lo[i], b.hi[i]);
            out.push_back(b);
        }
    }
}
template <class T> void shape_variants(const Plane<T>& s, std::vector<Plane<T>>& out) {
    non_finite_variants<T>(s, out);
    Plane<T> q = s;
    q.normal = Vec3<T>(T(0), -T(0), T(0));
    out.push_back(q);
}
template <class T> void shape_variants(const Sphere<T>& s, std::vector<Sphere<T>>& out) {
    non_finite_variants<T>(s, out);
    Sphere<T> q = s;
    q.radius = -std::max(s.radius, std::numeric_limits<T>::denorm_min());
    out.push_back(q);
}
template <class T, class Shape> std::vector<std::pair<Ray<T>, Shape>> invalid_variants(const Ray<T>& ray, const Shape& shape) {
    const T inf = std::numeric_limits<T>::infinity(), nan = std::numeric_limits<T>::quiet_NaN();
    std::vector<std::pair<Ray<T>, Shape>> out;
    std::vector<Ray<T>> rays;
    non_finite_variants<T>(ray, rays);
    for (const Ray<T>& r : rays) out.push_back({r, shape});
    for (const auto& [t_min, t_max] : {std::pair{nan, ray.t_max}, std::pair{ray.t_min, nan}, std::pair{inf, inf},
                                       std::pair{-inf, -inf}, std::pair{T(2), T(1)}}) {
        Ray<T> r = ray;
        r.t_min = t_min;
        r.t_max = t_max;
        out.push_back({r, shape});
    }
    Ray<T> zero = ray;
    zero.direction = Vec3<T>(T(0), -T(0), T(0));
    out.push_back({zero, shape});
    std::vector<Shape> shapes;
    shape_variants(shape, shapes);
    for (const Shape& s : shapes) out.push_back({ray, s});
    return out;
}

// Straight-line paths that check validity themselves (no flag from outside) decline
// every invalid variant of valid cases (declines: nullptr where validity is checked
// before the path runs), and the public answers, full and verdict alone, are invalid.
template <class T, class Shape, class Declines> void declines_invalid_input(Declines&& declines) {
    const std::uint64_t base = seed();
    int variants = 0;
    for (const auto& g : gen::generators<T, Shape>()) {
        gen::Rng rng(base);
        for (int k = 0; k < cases() / 8; ++k) {
            const auto c = g.make(rng);
            if (!detail::valid(c.ray) || !detail::valid(c.shape)) continue;
            for (const auto& [r, s] : invalid_variants(c.ray, c.shape)) {
                if (detail::valid(r) && detail::valid(s)) continue;  // a NaN-free replacement that is still valid
                ++variants;
                const std::string where = std::string(g.name) + " case " + std::to_string(k) + " (RAYPROOF_SEED=" +
                                          std::to_string(base) + ")";
                if constexpr (!std::is_same_v<std::decay_t<Declines>, std::nullptr_t>) {
                    ASSERT_TRUE(declines(r, s)) << where << ": " << r << " vs " << s;
                }
                ASSERT_EQ(intersect(r, s, certified).verdict, Verdict::invalid) << where;
                ASSERT_EQ(verdict(r, s, certified), Verdict::invalid) << where;
            }
        }
    }
    EXPECT_GT(variants, 1000);
}

TYPED_TEST(CertifiedExactStage, AabbVerdictPathAgreesWithGeneralPath) {
    using T = TypeParam;
    verdict_filter_agrees<T, Aabb<T>>(
        [](const Ray<T>& r, const Aabb<T>& b) { return detail::aabb_verdict_common(r, b); },
        [](const Ray<T>& r, const Aabb<T>& b) { return detail::aabb_certified_general(r, b); },
        [](const Ray<T>& r, const Aabb<T>& b) { return detail::aabb_certified_common(r, b).has_value(); });
}
TYPED_TEST(CertifiedExactStage, PlaneVerdictFilterAgreesWithGeneralPath) {
    using T = TypeParam;
    verdict_filter_agrees<T, Plane<T>>(
        [](const Ray<T>& r, const Plane<T>& p) { return detail::plane_verdict_common(r, p); },
        [](const Ray<T>& r, const Plane<T>& p) { return detail::plane_certified_general(r, p); },
        [](const Ray<T>&, const Plane<T>&) { return false; });
}
TYPED_TEST(CertifiedExactStage, SphereVerdictFilterAgreesWithGeneralPath) {
    using T = TypeParam;
    verdict_filter_agrees<T, Sphere<T>>(
        [](const Ray<T>& r, const Sphere<T>& s) { return detail::sphere_verdict_common(r, s); },
        [](const Ray<T>& r, const Sphere<T>& s) { return detail::sphere_certified_general(r, s); },
        [](const Ray<T>&, const Sphere<T>&) { return false; });
}
TYPED_TEST(CertifiedExactStage, SphereVerdictOfInvalidInputIsInvalid) {
    using T = TypeParam;
    declines_invalid_input<T, Sphere<T>>(nullptr);
}
TYPED_TEST(CertifiedExactStage, AabbStraightLinePathsDeclineInvalidInput) {
    using T = TypeParam;
    declines_invalid_input<T, Aabb<T>>([](const Ray<T>& r, const Aabb<T>& b) {
        return !detail::aabb_certified_common(r, b).has_value() && detail::aabb_verdict_common(r, b) == detail::verdict_declined;
    });
}
TYPED_TEST(CertifiedExactStage, PlaneVerdictFilterDeclinesInvalidInput) {
    using T = TypeParam;
    declines_invalid_input<T, Plane<T>>(
        [](const Ray<T>& r, const Plane<T>& p) { return detail::plane_verdict_common(r, p) == detail::verdict_declined; });
}

TYPED_TEST(CertifiedExactStage, ObbStraightLinePathAgreesWithGeneralPath) {
    using T = TypeParam;
    common_agrees_with_general<T, Obb<T>>([](const Ray<T>& r, const Obb<T>& b) { return detail::obb_certified_common(r, b); },
                                          [](const Ray<T>& r, const Obb<T>& b) { return detail::obb_certified_general(r, b); });
}
TYPED_TEST(CertifiedExactStage, PlaneStraightLinePathAgreesWithGeneralPath) {
    using T = TypeParam;
    common_agrees_with_general<T, Plane<T>>(
        [](const Ray<T>& r, const Plane<T>& p) { return detail::plane_certified_common(r, p); },
        [](const Ray<T>& r, const Plane<T>& p) { return detail::plane_certified_general(r, p); });
}
TYPED_TEST(CertifiedExactStage, SphereStraightLinePathAgreesWithGeneralPath) {
    using T = TypeParam;
    common_agrees_with_general<T, Sphere<T>>(
        [](const Ray<T>& r, const Sphere<T>& s) { return detail::sphere_certified_common(r, s); },
        [](const Ray<T>& r, const Sphere<T>& s) { return detail::sphere_certified_general(r, s); });
}
// A ray that touches the sphere at one point t* only (an exact tangent, or a range that
// meets the ball at one point): both ends answered with the greatest float at or below
// t*, by the certified query and by its exact stage alone. Faithful rounding would allow
// the float above as well; the general path's search clamps t_enter to t_exit, and its
// tangent shortcut (sphere_tangent_floats, read off the exact vertex) must answer the
// same float. On every valid case of the tangent generators.
TYPED_TEST(CertifiedExactStage, SphereTouchingPointAnswersTheFloatBelowIt) {
    using T = TypeParam;
    const std::uint64_t base = seed();
    int touching = 0;
    for (const char* name : {"grazing", "near_grazing", "on_boundary"}) {
        const auto* g = gen::find_generator<T, Sphere<T>>(name);
        ASSERT_NE(g, nullptr) << name;
        gen::Rng rng(base);
        for (int k = 0; k < 4 * cases(); ++k) {
            const auto c = g->make(rng);
            if (!detail::valid(c.ray) || !detail::valid(c.shape)) continue;
            const auto ex = oracle::exact(c.ray, c.shape);
            if (ex.verdict != Verdict::hit || compare(ex.t_enter, ex.t_exit) != 0) continue;
            ++touching;
            const T below = ex.exit_bracket().lo;
            const Hit<T> filtered = intersect(c.ray, c.shape, certified), exact = detail::exact_stage(c.ray, c.shape);
            for (const Hit<T>& h : {filtered, exact}) {
                ASSERT_TRUE(h.verdict == Verdict::hit && same_bits(h.t_enter, below) && same_bits(h.t_exit, below))
                    << "generator " << name << " case " << k << " (RAYPROOF_SEED=" << base << "): " << c.ray << " vs "
                    << c.shape << "\n  certified: " << filtered << "\n  exact stage: " << exact << "\n  oracle: " << ex
                    << "\n  the float at or below t*: " << below;
            }
        }
    }
    EXPECT_GT(touching, cases());  // the grazing generator touches in every case
}
// The sphere's fixed-size exact sums (SphereFixedExact: float input, and double input
// safe for expansions, as given or rescaled into that range) against the expansion types
// on the given input, on every valid case of every generator: the discriminant's sign
// is the same wherever the sums decide it, and the vertex (scaled back to the given t)
// has the exact slope signs (sign_slope) at its f, at the expansions' f and at their
// neighbours, at the ends of the range and at 0, so that it is a faithful rounding of
// t* with the right side; likewise SphereQuadratic's own answers, which take the sums
// first. The sums must decide nearly every case they are offered (they decline only
// when a fixed capacity does not suffice), must answer nothing on input outside their
// range, and the rescaled input must be among them.
TYPED_TEST(CertifiedExactStage, SphereFixedSumsAreTheExpansionsSigns) {
    using T = TypeParam;
    int offered = 0, declined = 0, tangents = 0, rescaled = 0;
    on_valid_cases<T, Sphere<T>>("the fixed sums", [&](const auto& c, const std::string& where, bool& answered) {
        const detail::SphereFixedExact given(detail::sphere_given_values(c.ray, c.shape), std::is_same_v<T, float>);
        if (!given.usable()) {
            ASSERT_FALSE(given.sign_discriminant() || given.vertex()) << where << ": an answer on input the sums do not take";
        }
        const std::optional<detail::SphereValues> w = detail::sphere_rescaled_values(c.ray, c.shape);
        const std::optional<detail::SphereFixedInput> e = detail::sphere_fixed_input(c.ray, c.shape, [&] { return w; });
        ASSERT_EQ(e.has_value(), given.usable() || w.has_value()) << where << ": the input the sums take";
        if (!e) return;
        ASSERT_TRUE(e->sums.usable()) << where << ": a rescaled input the sums do not take";
        rescaled += !given.usable();
        answered = true;
        ++offered;
        const detail::SphereQuadratic<T> q(c.ray, c.shape);
        const std::string what = where + ": " + ::testing::PrintToString(c.ray) + " vs " + ::testing::PrintToString(c.shape);
        const int exact = q.sign_discriminant(false);
        tangents += exact == 0;
        ASSERT_EQ(q.sign_discriminant(), exact) << what << ": the discriminant's sign";
        const std::optional<int> sd = e->sign_discriminant();
        if (sd) {
            ASSERT_EQ(*sd, exact) << what << ": the fixed sums' discriminant sign";
        }
        const std::optional<std::pair<double, int>> v_fixed = e->vertex();
        const bool have = v_fixed.has_value();
        const double f_fixed = have ? v_fixed->first : 0.0;
        declined += !sd + !have;
        using Vertex = typename detail::SphereQuadratic<T>::Vertex;
        const Vertex expansions = q.vertex(false), taken = q.vertex();
        std::vector<Vertex> vertices{taken};
        if (have) vertices.push_back(Vertex{f_fixed, v_fixed->second});
        std::vector<double> ts{0.0};
        for (const T t : {c.ray.t_min, c.ray.t_max})
            if (std::isfinite(t)) ts.push_back(t);
        for (const double f : {f_fixed, taken.f, expansions.f})
            for (const double t : {f, std::nextafter(f, -HUGE_VAL), std::nextafter(f, HUGE_VAL)})
                if (std::isfinite(t)) ts.push_back(t);
        for (const Vertex& vx : vertices)
            for (const double t : ts) {
                ASSERT_EQ(vx.slope_sign(t), q.sign_slope(t, false)) << what << ", t = " << t << ": the vertex's slope sign";
            }
    });
    EXPECT_GT(tangents, 100) << "exact tangents should be among the cases";
    EXPECT_LT(declined, offered / 20) << "the fixed sums should decide nearly every case offered";
    if constexpr (std::is_same_v<T, double>) {
        EXPECT_GT(rescaled, 100) << "rescaled input should be among the cases";
    }
}

// The tangent shortcut (sphere_tangent_shortcut, ray_sphere.hpp: an exact tangent
// answered from the fixed sums' vertex before the straight-line and general paths)
// answers the general path's answer bit for bit wherever it answers, and the
// discriminant's sign it hands to the general path where it decided one is the exact
// one; it answers nearly every case of the grazing generator (exact tangents).
TYPED_TEST(CertifiedExactStage, SphereTangentShortcutAgreesWithGeneralPath) {
    using T = TypeParam;
    int grazing = 0, answered_grazing = 0;
    on_valid_cases<T, Sphere<T>>("the tangent shortcut", [&](const auto& c, const std::string& where, bool& answered) {
        answered = true;  // every case is checked; the shortcut answers tangents only
        const detail::SphereTangentTry<T> tangent = detail::sphere_tangent_shortcut(c.ray, c.shape);
        if (c.generator == "grazing") {
            ++grazing;
            answered_grazing += tangent.answer.has_value();
        }
        const std::string what = where + ": " + ::testing::PrintToString(c.ray) + " vs " + ::testing::PrintToString(c.shape);
        if (tangent.disc_sign != 2) {
            ASSERT_EQ(tangent.disc_sign, detail::SphereQuadratic<T>(c.ray, c.shape).sign_discriminant(false))
                << what << ": the discriminant's sign handed on";
        }
        if (!tangent.answer) return;
        ASSERT_EQ(tangent.disc_sign, 0) << what;
        const Hit<T> general = detail::sphere_certified_general(c.ray, c.shape);
        ASSERT_TRUE(tangent.answer->verdict == general.verdict && tangent.answer->face == general.face &&
                    same_bits(tangent.answer->t_enter, general.t_enter) &&
                    same_bits(tangent.answer->t_exit, general.t_exit))
            << what << "\n  tangent shortcut: " << *tangent.answer << "\n  general path: " << general;
    });
    EXPECT_GT(grazing, 100);
    EXPECT_GE(answered_grazing, grazing - grazing / 20) << "the shortcut should answer the grazing tangents";
}

// The float straight-line path (sphere_certified_float: plain double with gamma bounds, no
// double-word arithmetic), in front of sphere_certified_common for float input: wherever
// it answers, the general path's answer bit for bit, on every generator (tangents, a
// hair off them, origins on the sphere, extreme magnitudes), and nearly always on
// general-position input.
TEST(CertifiedExactStageFloat, SphereFloatStraightLinePathAgreesWithGeneralPath) {
    using T = float;
    common_agrees_with_general<T, Sphere<T>>(
        [](const Ray<T>& r, const Sphere<T>& s) { return detail::sphere_certified_float(r, s); },
        [](const Ray<T>& r, const Sphere<T>& s) { return detail::sphere_certified_general(r, s); });
}
// The float path's root pins (sphere_float_pin_enter / _exit) from deliberately wrong
// candidates: the general path's t_enter (t_exit) moved by -3 to +3 floats. Whatever the
// candidate, a pin answers the general path's float or nothing; from the right float
// (offset 0) it answers every root of general-position input. A pin that trusted the
// candidate without proving both signs would answer a neighbour here.
TEST(CertifiedExactStageFloat, SphereFloatPinsProveTheirCandidates) {
    using T = float;
    int tried = 0, answered_exact = 0;
    on_valid_cases<T, Sphere<T>>("the float pins", [&](const auto& c, const std::string& where, bool& answered) {
        const Hit<T> general = detail::sphere_certified_general(c.ray, c.shape);
        answered = true;  // the pins are checked on every hit below; none is required to answer
        if (general.verdict != Verdict::hit || general.t_enter == general.t_exit) return;
        const detail::SphereFloatLine line = detail::sphere_float_line(c.ray, c.shape);
        for (int k = -3; k <= 3; ++k) {
            auto moved = [k](T x) {
                for (int i = 0; i < k; ++i) x = detail::step_up(x);
                for (int i = 0; i > k; --i) x = detail::step_down(x);
                return x == 0 ? T(0) : x;
            };
            // t_enter above t_min: q(t_min) > 0 (else the general path answers t_min).
            if (general.t_enter != c.ray.t_min && std::isfinite(general.t_enter)) {
                const detail::Pinned<T> e = detail::sphere_float_pin_enter(c.ray, line, moved(general.t_enter));
                ASSERT_TRUE(!e.ok || same_bits(e.t, general.t_enter))
                    << where << ", t_enter candidate moved by " << k << ": pin " << e.t << ", general " << general;
                tried += k == 0 && c.generator == "general";
                answered_exact += k == 0 && c.generator == "general" && e.ok;
            }
            if (general.t_exit != c.ray.t_max && std::isfinite(general.t_exit)) {
                const detail::Pinned<T> e = detail::sphere_float_pin_exit(c.ray, line, moved(general.t_exit));
                ASSERT_TRUE(!e.ok || same_bits(e.t, general.t_exit))
                    << where << ", t_exit candidate moved by " << k << ": pin " << e.t << ", general " << general;
                tried += k == 0 && c.generator == "general";
                answered_exact += k == 0 && c.generator == "general" && e.ok;
            }
        }
    });
    ASSERT_GT(tried, 0);
    EXPECT_GE(answered_exact, tried - tried / 100) << "the pins proved " << answered_exact << " of " << tried;
}
