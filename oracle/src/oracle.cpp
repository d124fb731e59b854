// oracle.cpp — the exact answers (ray vs Aabb, Obb, Plane, Sphere, ConvexPolyhedron), exact values and the
// judge. All arithmetic on inputs is exact rational arithmetic (CGAL::Gmpq); MPFR is used
// only to guess a float near an exact value, and every guess is then settled by exact
// comparisons.
//
// This is the oracle's one CGAL translation unit. It holds what the shapes share: exact
// values (roots, comparisons, faithful brackets), the validity rules, the judge and the
// printing, and it instantiates exact() for float and double. Each shape's exact answer,
// with how it is decided (the contract's definitions, literally), is in its own file
// found by the shape's name stem: ray_aabb_oracle.hpp, ray_obb_oracle.hpp,
// ray_plane_oracle.hpp, ray_sphere_oracle.hpp, ray_polyhedron_oracle.hpp (their shared
// parts: exact_answer.hpp).
#include "exact_number.hpp"

#include <rayproof/io.hpp>

#include <gmp.h>
#include <mpfr.h>

#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <ostream>
#include <sstream>
#include <type_traits>

namespace rayproof::oracle {

// =====================================================================================
// Exact values
// =====================================================================================

namespace internal {

ExactValue make_root(const Q& p, const Q& r, int sigma) {
    if (CGAL::sign(r) == CGAL::ZERO) return make_rational(p);
    const Z num = r.numerator(), den = r.denominator();  // lowest terms, den > 0
    if (mpz_perfect_square_p(num.mpz()) && mpz_perfect_square_p(den.mpz())) {
        Z sn, sd;
        mpz_sqrt(sn.mpz(), num.mpz());
        mpz_sqrt(sd.mpz(), den.mpz());
        const Q s{sn, sd};
        const Q v = sigma > 0 ? Q{p + s} : Q{p - s};
        return make_rational(v);
    }
    auto impl = std::make_shared<ExactValue::Impl>();
    impl->kind = ExactValue::Kind::quadratic_root;
    impl->p = p;
    impl->r = r;
    impl->sigma = sigma > 0 ? 1 : -1;
    return ExactValue{std::move(impl)};
}

int sign_minus(const ExactValue::Impl& v, const Q& x) {
    const Q s = v.p - x;
    const int ss = int(CGAL::sign(s));
    if (v.kind == ExactValue::Kind::rational) return ss;
    // v - x = s + sigma·sqrt(r), r > 0 irrational root.
    if (v.sigma > 0) {
        if (ss >= 0) return 1;
        const Q s2 = s * s;
        return int(CGAL::compare(v.r, s2));  // sign(sqrt(r) - |s|)
    }
    if (ss <= 0) return -1;
    const Q s2 = s * s;
    return int(CGAL::compare(s2, v.r));  // sign(s - sqrt(r))
}

}  // namespace internal

using internal::to_q;

ExactValue::Kind ExactValue::kind() const { return impl_ ? impl_->kind : Kind::none; }

namespace {

// A monotone integer key for the floats of T: key(a) < key(b) iff a < b, -0 and +0 both
// 0, consecutive floats consecutive keys, ±inf one step beyond ±max.
template <class T> std::int64_t key(T x) {
    if constexpr (std::is_same_v<T, float>) {
        const std::uint32_t b = std::bit_cast<std::uint32_t>(x);
        const std::int64_t m = std::int64_t(b & 0x7fffffffu);
        return (b >> 31) ? -m : m;
    } else {
        const std::uint64_t b = std::bit_cast<std::uint64_t>(x);
        const std::int64_t m = std::int64_t(b & 0x7fffffffffffffffull);
        return (b >> 63) ? -m : m;
    }
}
template <class T> T from_key(std::int64_t k) {
    if constexpr (std::is_same_v<T, float>) {
        const std::uint32_t m = std::uint32_t(k < 0 ? -k : k);
        return std::bit_cast<float>(k < 0 ? (m | 0x80000000u) : m);
    } else {
        const std::uint64_t m = std::uint64_t(k < 0 ? -k : k);
        return std::bit_cast<double>(k < 0 ? (m | 0x8000000000000000ull) : m);
    }
}

// The oracle steps floats with the standard library, not with the kernel's
// detail::step_up/step_down: the ground truth shares no code with what it judges.
template <class T> T step_up(T x) { return std::nextafter(x, std::numeric_limits<T>::infinity()); }
template <class T> T step_down(T x) { return std::nextafter(x, -std::numeric_limits<T>::infinity()); }

Order order_of(double f, const ExactValue::Impl* v) {
    if (!v || std::isnan(f)) return Order::unordered;
    using K = ExactValue::Kind;
    if (v->kind == K::minus_infinity) return f == -std::numeric_limits<double>::infinity() ? Order::equal : Order::above;
    if (v->kind == K::plus_infinity) return f == std::numeric_limits<double>::infinity() ? Order::equal : Order::below;
    if (std::isinf(f)) return f < 0 ? Order::below : Order::above;
    const int s = internal::sign_minus(*v, to_q(f));  // sign(v - f)
    return s > 0 ? Order::below : s < 0 ? Order::above : Order::equal;
}

// An MPFR approximation of a finite value (relative error ~2^-150), for guesses only.
struct Mpfr {
    mpfr_t x;
    Mpfr() { mpfr_init2(x, 160); }
    ~Mpfr() { mpfr_clear(x); }
    Mpfr(const Mpfr&) = delete;
    Mpfr& operator=(const Mpfr&) = delete;
};
void approximate(const ExactValue::Impl& v, mpfr_t out) {
    if (v.kind == ExactValue::Kind::rational) {
        mpfr_set_q(out, v.p.mpq(), MPFR_RNDN);
        return;
    }
    // p + σ·sqrt(r); when p and σ·sqrt(r) have opposite signs, use the cancellation-free
    // (p² - r) / (p - σ·sqrt(r)) instead.
    Mpfr p, sr, t;
    mpfr_set_q(p.x, v.p.mpq(), MPFR_RNDN);
    mpfr_set_q(sr.x, v.r.mpq(), MPFR_RNDN);
    mpfr_sqrt(sr.x, sr.x, MPFR_RNDN);
    if (v.sigma < 0) mpfr_neg(sr.x, sr.x, MPFR_RNDN);
    if (mpfr_sgn(p.x) * mpfr_sgn(sr.x) < 0) {
        const Q num_q = v.p * v.p - v.r;
        mpfr_set_q(t.x, num_q.mpq(), MPFR_RNDN);
        mpfr_sub(p.x, p.x, sr.x, MPFR_RNDN);
        mpfr_div(out, t.x, p.x, MPFR_RNDN);
    } else {
        mpfr_add(out, p.x, sr.x, MPFR_RNDN);
    }
}

template <class T> T guess(const ExactValue::Impl& v) {
    Mpfr m;
    approximate(v, m.x);
    if constexpr (std::is_same_v<T, float>)
        return mpfr_get_flt(m.x, MPFR_RNDN);
    else
        return mpfr_get_d(m.x, MPFR_RNDN);
}

}  // namespace

Order ExactValue::compare(double f) const { return order_of(f, impl_.get()); }
Order ExactValue::compare(float f) const { return order_of(double(f), impl_.get()); }

template <class T> Bracket<T> ExactValue::faithful() const {
    constexpr T inf = std::numeric_limits<T>::infinity();
    if (!impl_) return {std::numeric_limits<T>::quiet_NaN(), std::numeric_limits<T>::quiet_NaN()};
    if (impl_->kind == Kind::minus_infinity) return {-inf, -inf};
    if (impl_->kind == Kind::plus_infinity) return {inf, inf};
    T g = guess<T>(*impl_);
    if (std::isnan(g)) g = 0;
    // Walk from the guess (normally 0 or 1 steps), then bisect on the keys if the guess
    // was far off; every decision is an exact comparison.
    for (int steps = 0; steps < 4; ++steps) {
        const Order o = compare(g);
        if (o == Order::equal) return {g, g};
        if (o == Order::below) {
            const T n = step_up(g);
            const Order on = compare(n);
            if (on == Order::equal) return {n, n};
            if (on == Order::above) return {g, n};
            g = n;
        } else {
            const T n = step_down(g);
            const Order on = compare(n);
            if (on == Order::equal) return {n, n};
            if (on == Order::below) return {n, g};
            g = n;
        }
    }
    // Bisection: lo_k below (or equal to) the value, hi_k above (or equal).
    std::int64_t lo_k = key(-inf), hi_k = key(inf);
    while (hi_k - lo_k > 1) {
        const std::int64_t mid = lo_k + (hi_k - lo_k) / 2;
        const Order o = compare(from_key<T>(mid));
        if (o == Order::equal) return {from_key<T>(mid), from_key<T>(mid)};
        if (o == Order::below)
            lo_k = mid;
        else
            hi_k = mid;
    }
    return {from_key<T>(lo_k), from_key<T>(hi_k)};
}
template Bracket<float> ExactValue::faithful<float>() const;
template Bracket<double> ExactValue::faithful<double>() const;

double ExactValue::approx() const {
    if (!impl_) return std::numeric_limits<double>::quiet_NaN();
    if (impl_->kind == Kind::minus_infinity) return -std::numeric_limits<double>::infinity();
    if (impl_->kind == Kind::plus_infinity) return std::numeric_limits<double>::infinity();
    return guess<double>(*impl_);
}

namespace {
std::string elide(std::string s, std::size_t max_digits) {
    if (max_digits >= 8 && s.size() > max_digits) {
        const std::size_t keep = max_digits / 2;
        s = s.substr(0, keep) + "..." + s.substr(s.size() - keep) + "<" + std::to_string(s.size()) + " chars>";
    }
    return s;
}
std::string q_str(const Q& q, std::size_t max_digits) {
    char* raw = mpq_get_str(nullptr, 10, q.mpq());
    std::string s(raw);
    void (*freefunc)(void*, std::size_t);
    mp_get_memory_functions(nullptr, nullptr, &freefunc);
    freefunc(raw, std::strlen(raw) + 1);
    return elide(std::move(s), max_digits);
}
}  // namespace

std::string ExactValue::str(std::size_t max_digits) const {
    switch (kind()) {
        case Kind::none: return "none";
        case Kind::minus_infinity: return "-inf";
        case Kind::plus_infinity: return "+inf";
        case Kind::rational: return q_str(impl_->p, max_digits);
        case Kind::quadratic_root:
            return q_str(impl_->p, max_digits) + (impl_->sigma > 0 ? " + " : " - ") + "sqrt(" +
                   q_str(impl_->r, max_digits) + ")";
    }
    return "?";
}

bool operator==(const ExactValue& a, const ExactValue& b) {
    if (a.kind() != b.kind()) return false;
    switch (a.kind()) {
        case ExactValue::Kind::none:
        case ExactValue::Kind::minus_infinity:
        case ExactValue::Kind::plus_infinity: return true;
        case ExactValue::Kind::rational: return a.impl()->p == b.impl()->p;
        case ExactValue::Kind::quadratic_root:
            return a.impl()->p == b.impl()->p && a.impl()->r == b.impl()->r && a.impl()->sigma == b.impl()->sigma;
    }
    return false;
}

namespace {
// sign(c + e·sqrt(r)) for rationals c, e and r >= 0.
int sign_plus_root(const Q& c, const Q& e, const Q& r) {
    const int sc = int(CGAL::sign(c));
    const int se = CGAL::sign(r) == CGAL::ZERO ? 0 : int(CGAL::sign(e));
    if (se == 0) return sc;
    if (sc == 0 || sc == se) return se;
    const Q c2 = c * c, e2r = e * e * r;
    const int m = int(CGAL::compare(c2, e2r));  // sign(|c| - |e|·sqrt(r))
    return m > 0 ? sc : m < 0 ? se : 0;
}
}  // namespace

// a = pa + sa·sqrt(ra), b = pb + sb·sqrt(rb) (s = 0 for a rational). With u = pa - pb,
// L = u + sa·sqrt(ra) and R = sb·sqrt(rb): sign(a - b) = sign(L - R). When L and R have
// different signs that decides; with the same sign s, sign(L - R) = s·sign(L² - R²),
// and L² - R² = (u² + ra - rb) + 2u·sa·sqrt(ra), again a rational plus a multiple of one
// square root.
int compare(const ExactValue& a, const ExactValue& b) {
    using K = ExactValue::Kind;
    const auto rank = [](K k) { return k == K::minus_infinity ? -1 : k == K::plus_infinity ? 1 : 0; };
    const int ra_ = rank(a.kind()), rb_ = rank(b.kind());
    if (ra_ != 0 || rb_ != 0) return ra_ < rb_ ? -1 : ra_ > rb_ ? 1 : 0;
    const ExactValue::Impl& x = *a.impl();
    const ExactValue::Impl& y = *b.impl();
    const Q zero{0};
    const int sa = x.kind == K::quadratic_root ? x.sigma : 0, sb = y.kind == K::quadratic_root ? y.sigma : 0;
    const Q& ra = sa ? x.r : zero;
    const Q& rb = sb ? y.r : zero;
    const Q u = x.p - y.p;
    const int sl = sign_plus_root(u, Q{sa}, ra), sr = sb;
    if (sl != sr) return sl > sr ? 1 : -1;
    if (sl == 0) return 0;
    const Q c = u * u + ra - rb, e = Q{2 * sa} * u;
    return sl * sign_plus_root(c, e, ra);
}

// =====================================================================================
// Validity (the contract's rules, exact)
// =====================================================================================

namespace {
template <class T> bool finite3(const Vec3<T>& v) {
    return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}
template <class T> bool nonzero3(const Vec3<T>& v) { return v[0] != 0 || v[1] != 0 || v[2] != 0; }
}  // namespace

template <class T> bool valid(const Ray<T>& r) {
    constexpr T inf = std::numeric_limits<T>::infinity();
    if (!finite3(r.origin) || !finite3(r.direction)) return false;
    if (std::isnan(r.t_min) || std::isnan(r.t_max) || r.t_min == inf || r.t_max == -inf) return false;
    return r.t_min <= r.t_max && nonzero3(r.direction);
}
template <class T> bool valid(const Aabb<T>& b) {
    return finite3(b.lo) && finite3(b.hi) && b.lo[0] <= b.hi[0] && b.lo[1] <= b.hi[1] && b.lo[2] <= b.hi[2];
}
template <class T> bool valid(const Plane<T>& p) { return finite3(p.normal) && std::isfinite(p.offset) && nonzero3(p.normal); }
template <class T> bool valid(const Sphere<T>& s) { return finite3(s.center) && std::isfinite(s.radius) && s.radius >= 0; }
template <class T> bool valid(const ConvexPolyhedron<T>& p) {
    for (const Plane<T>& plane : p.planes)
        if (!valid(plane)) return false;
    return true;  // no planes: all of space
}
template <class T> bool valid(const Obb<T>& b) {
    if (!finite3(b.center) || !finite3(b.half_extent)) return false;
    for (int i = 0; i < 9; ++i)
        if (!std::isfinite(b.axes.data()[i])) return false;
    if (!(b.half_extent[0] >= 0 && b.half_extent[1] >= 0 && b.half_extent[2] >= 0)) return false;
    // Linearly dependent columns <=> det == 0, exactly.
    std::array<std::array<Q, 3>, 3> m;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) m[r][c] = to_q(b.axes(r, c));
    const Q m0 = m[1][1] * m[2][2] - m[1][2] * m[2][1];
    const Q m1 = m[1][0] * m[2][2] - m[1][2] * m[2][0];
    const Q m2 = m[1][0] * m[2][1] - m[1][1] * m[2][0];
    const Q det = m[0][0] * m0 - m[0][1] * m1 + m[0][2] * m2;
    return CGAL::sign(det) != CGAL::ZERO;
}

}  // namespace rayproof::oracle

// =====================================================================================
// Exact answers: one file per shape, included after the validity rules they call
// =====================================================================================

#include "ray_aabb_oracle.hpp"
#include "ray_obb_oracle.hpp"
#include "ray_plane_oracle.hpp"
#include "ray_polyhedron_oracle.hpp"
#include "ray_sphere_oracle.hpp"

namespace rayproof::oracle {

#define RAYPROOF_ORACLE_INSTANTIATE(T)                                      \
    template bool valid<T>(const Ray<T>&);                                  \
    template bool valid<T>(const Aabb<T>&);                                 \
    template bool valid<T>(const Obb<T>&);                                  \
    template bool valid<T>(const Plane<T>&);                                \
    template bool valid<T>(const Sphere<T>&);                               \
    template bool valid<T>(const ConvexPolyhedron<T>&);                     \
    template Exact<T> exact<T>(const Ray<T>&, const Aabb<T>&);              \
    template Exact<T> exact<T>(const Ray<T>&, const Obb<T>&);               \
    template Exact<T> exact<T>(const Ray<T>&, const Plane<T>&);             \
    template Exact<T> exact<T>(const Ray<T>&, const Sphere<T>&);           \
    template Exact<T> exact<T>(const Ray<T>&, const ConvexPolyhedron<T>&);
RAYPROOF_ORACLE_INSTANTIATE(float)
RAYPROOF_ORACLE_INSTANTIATE(double)
#undef RAYPROOF_ORACLE_INSTANTIATE

// =====================================================================================
// The judge
// =====================================================================================

template <class T> std::uint64_t ulp_distance(T a, T b) {
    if (std::isnan(a) || std::isnan(b)) return std::numeric_limits<std::uint64_t>::max();
    const std::int64_t ka = key(a), kb = key(b);
    return ka > kb ? std::uint64_t(ka) - std::uint64_t(kb) : std::uint64_t(kb) - std::uint64_t(ka);
}

template <class T> std::uint64_t ulps_from(T f, const ExactValue& v) {
    const Order o = v.compare(f);
    if (o == Order::unordered) return std::numeric_limits<std::uint64_t>::max();
    if (o == Order::equal) return 0;
    // One more exact comparison settles the common case: f is the neighbour just below
    // (above) the value when the next float up (down) is already above (below) it.
    if (o == Order::below) {
        if (v.compare(step_up(f)) == Order::above) return 0;
        return ulp_distance(f, v.faithful<T>().lo);
    }
    if (v.compare(step_down(f)) == Order::below) return 0;
    return ulp_distance(f, v.faithful<T>().hi);
}

template <class T> Judgement judge(const Hit<T>& hit, const Exact<T>& ex, bool compare_face) {
    Judgement j;
    const bool hit_invalid = hit.verdict == Verdict::invalid, ex_invalid = ex.verdict == Verdict::invalid;
    if (hit_invalid || ex_invalid) {
        j.outcome = hit_invalid == ex_invalid ? Outcome::agree : Outcome::invalid_mismatch;
        return j;
    }
    if (hit.verdict != ex.verdict) {
        j.outcome = hit.verdict == Verdict::hit ? Outcome::false_hit : Outcome::false_miss;
        return j;
    }
    if (hit.verdict != Verdict::hit) return j;
    if (compare_face && hit.face != ex.face) j.outcome = Outcome::face_mismatch;
    j.enter_ulps = ulps_from(hit.t_enter, ex.t_enter);
    j.exit_ulps = ulps_from(hit.t_exit, ex.t_exit);
    const Order oe = ex.t_enter.compare(hit.t_enter), ox = ex.t_exit.compare(hit.t_exit);
    j.encloses = (oe == Order::below || oe == Order::equal) && (ox == Order::above || ox == Order::equal);
    return j;
}

template std::uint64_t ulp_distance<float>(float, float);
template std::uint64_t ulp_distance<double>(double, double);
template std::uint64_t ulps_from<float>(float, const ExactValue&);
template std::uint64_t ulps_from<double>(double, const ExactValue&);
template Judgement judge<float>(const Hit<float>&, const Exact<float>&, bool);
template Judgement judge<double>(const Hit<double>&, const Exact<double>&, bool);

// =====================================================================================
// Printing
// =====================================================================================

const char* to_string(Outcome o) {
    switch (o) {
        case Outcome::agree: return "agree";
        case Outcome::false_hit: return "false_hit";
        case Outcome::false_miss: return "false_miss";
        case Outcome::invalid_mismatch: return "invalid_mismatch";
        case Outcome::face_mismatch: return "face_mismatch";
    }
    return "?";
}
const char* to_string(Order o) {
    switch (o) {
        case Order::below: return "below";
        case Order::equal: return "equal";
        case Order::above: return "above";
        case Order::unordered: return "unordered";
    }
    return "?";
}
std::ostream& operator<<(std::ostream& os, Outcome o) { return os << to_string(o); }
std::ostream& operator<<(std::ostream& os, Order o) { return os << to_string(o); }

std::ostream& operator<<(std::ostream& os, const ExactValue& v) {
    os << v.str();
    if (v.kind() == ExactValue::Kind::rational || v.kind() == ExactValue::Kind::quadratic_root) {
        const auto flags = os.flags();
        os << " (~" << std::hexfloat << v.approx() << ')';
        os.flags(flags);
    }
    return os;
}

template <class T> std::ostream& operator<<(std::ostream& os, const Exact<T>& e) {
    os << "Exact{" << e.verdict;
    if (e.verdict == Verdict::hit) {
        const Bracket<T> be = e.enter_bracket(), bx = e.exit_bracket();
        const auto flags = os.flags();
        os << " t_enter=" << e.t_enter << " in [" << std::hexfloat << be.lo << ", " << be.hi << "]";
        os.flags(flags);
        os << " t_exit=" << e.t_exit << " in [" << std::hexfloat << bx.lo << ", " << bx.hi << "]";
        os.flags(flags);
        os << " face=" << e.face;
    }
    return os << '}';
}
template std::ostream& operator<< <float>(std::ostream&, const Exact<float>&);
template std::ostream& operator<< <double>(std::ostream&, const Exact<double>&);

std::ostream& operator<<(std::ostream& os, const Judgement& j) {
    return os << "Judgement{" << j.outcome << " enter_ulps=" << j.enter_ulps << " exit_ulps=" << j.exit_ulps
              << " encloses=" << (j.encloses ? "yes" : "no") << '}';
}

}  // namespace rayproof::oracle
