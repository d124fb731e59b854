// rayproof/detail/exact.hpp — exact arithmetic for the certified mode and for input
// validation: error-free transformations, Shewchuk expansions, a fixed-capacity exact
// dyadic rational, and the exact decisions built on them (faithful quotients,
// comparisons of quotients, the sign of a 3x3 determinant).
//
// Two exact number types share one interface, so an exact algorithm is written once
// as a template on E and run with either (see with_exact below):
//   Expansion<Cap>  a sum of up to Cap doubles (Shewchuk 1997). Fast: a few flops per
//                   component. Exact when no product underflows (guaranteed for
//                   polynomials of degree <= 6 in inputs that pass expansion_safe) and
//                   the result needs at most Cap components; anything else raises its
//                   overflowed() flag, so an unflagged value is always exact.
//   BigDyadic       ±M·2^E with M a fixed array of 64-bit limbs. Slower, but exact for
//                   every finite float or double, denormals included, up to the
//                   documented degree.
// Both offer: construction from double and float (exact), + - * and unary -, sign()
// (exact), approx() (value ≈ mant·2^exp, relative error < 2^-50, works outside the
// double range), and overflowed() (sticky: the value is meaningless once it is set).
//
// Rounding is IEEE binary64, round to nearest even, no excess precision (SSE2 or any
// target with IEEE double arithmetic). -ffast-math and its parts are refused at compile
// time (detail/fp_model.hpp). Contraction (fusing a*b + c into one fma, which g++ and
// clang do with an FMA target even at -std=c++20) cannot change anything here: the only
// rounded products are two_prod's, whose hi is detail::rounded (eft.hpp, class C3), so
// every two_sum, fast_two_sum and scale step sees fl(a·b) and the expansions stay
// exact; s·f[j] with s = ±1 is exact (class C2); BigDyadic is integer arithmetic; the
// quotient's candidate is only a start for the exact stepping, which decides; and
// det3_sign's filter is class C1 (its bound counts five roundings per monomial, a fused
// evaluation has fewer). The suites run under -O3 -march=native -ffp-contract=fast
// with g++ and clang (scripts/test.sh, contraction stage).
//
// Reference: J. R. Shewchuk, "Adaptive Precision Floating-Point Arithmetic and Fast
// Robust Geometric Predicates", Discrete Comput. Geom. 18 (1997) — theorem numbers
// below refer to it. Error bounds use gamma(n) = n·u/(1 − n·u), u = 2^-53
// (detail/rounding.hpp).
#pragma once

#include <rayproof/detail/eft.hpp>
#include <rayproof/detail/float_util.hpp>
#include <rayproof/detail/limbs.hpp>
#include <rayproof/detail/rounding.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <initializer_list>
#include <limits>
#include <optional>
#include <span>
#include <type_traits>
#include <utility>

// The fixed arrays below are filled only up to their length field and every read stays
// below it; after inlining, GCC's flow analysis cannot always see that and reports
// false -Wmaybe-uninitialized warnings in the caller's build (zero-filling the arrays
// instead would cost more than the arithmetic). Silenced for this header only.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif

namespace rayproof::detail {

// Error-free transformations (SumOf, Pair, two_sum, fast_two_sum, two_prod):
// detail/eft.hpp.

// value ≈ mant · 2^exp with |mant| in [0.5, 1), or mant == 0 and exp == 0 for zero.
struct Approx {
    double mant;
    long exp;
};

namespace exact_impl {

// Below this magnitude a two_prod error term may be subnormal, hence possibly
// inexact (see two_prod): such products raise the expansion's overflowed() flag.
inline constexpr double kMinExactProduct = 0x1p-916;

// ---- Expansion kernels on raw arrays. Inputs: nonoverlapping expansions, components
// sorted by increasing magnitude, no zeros (Shewchuk's strongly nonoverlapping form,
// which every routine below both requires and produces under round-to-even).

// h = e + s·f for s = ±1 (FAST-EXPANSION-SUM with zero elimination, Theorem 13): merge
// the components by magnitude, then one chain of two_sums. h has room for m + n.
inline int sum(const double* e, int m, const double* f, int n, double s, double* h) {
    if (m + n == 0) return 0;
    int i = 0, j = 0, k = 0;
    auto take = [&]() -> double {
        if (j >= n || (i < m && std::abs(e[i]) < std::abs(f[j]))) return e[i++];
        return s * f[j++];  // exact: s is ±1
    };
    double q = take();
    for (int t = 1; t < m + n; ++t) {
        const Pair r = two_sum(q, take());
        if (r.lo != 0) h[k++] = r.lo;
        q = r.hi;
    }
    if (q != 0) h[k++] = q;
    return k;
}

// h = e·b (SCALE-EXPANSION with zero elimination, Theorem 19); h has room for 2m.
// Sets `tiny` when a product fell below kMinExactProduct (possibly inexact); checking
// the first suffices: e[0] is the smallest component, so e[0]·b the smallest product.
inline int scale(const double* e, int m, double b, double* h, bool& tiny) {
    Pair p = two_prod(e[0], b);
    tiny |= !(std::abs(p.hi) >= kMinExactProduct);
    int k = 0;
    if (p.lo != 0) h[k++] = p.lo;
    double q = p.hi;
    for (int i = 1; i < m; ++i) {
        p = two_prod(e[i], b);
        const Pair s = two_sum(q, p.lo);
        if (s.lo != 0) h[k++] = s.lo;
        const Pair f = fast_two_sum(p.hi, s.hi);  // |p.hi| >= |s.hi| (Theorem 19)
        if (f.lo != 0) h[k++] = f.lo;
        q = f.hi;
    }
    if (q != 0) h[k++] = q;
    return k;
}

// COMPRESS (Theorem 23), in place: the same value in a nonadjacent expansion whose
// largest component approximates the whole with an error below one ulp of it.
inline int compress(double* e, int m) {
    if (m <= 1) return m;
    int bottom = m - 1;
    double q = e[bottom];
    for (int i = m - 2; i >= 0; --i) {
        const Pair r = fast_two_sum(q, e[i]);
        if (r.lo != 0) {
            e[bottom--] = r.hi;
            q = r.lo;
        } else {
            q = r.hi;
        }
    }
    int top = 0;
    for (int i = bottom + 1; i < m; ++i) {
        const Pair r = fast_two_sum(e[i], q);
        if (r.lo != 0) e[top++] = r.lo;
        q = r.hi;
    }
    e[top] = q;
    return top + 1;
}

inline long floor_div64(long e) { return e >= 0 ? e / 64 : -((-e + 63) / 64); }

}  // namespace exact_impl

// ===================================================================================
// 2. Expansion<Cap>
// ===================================================================================
//
// A Shewchuk expansion: the exact value is the sum of c_[0..n_), nonoverlapping,
// increasing magnitude, no zero components, at most Cap of them; no heap.
//
// Exactness. Sums and differences are always exact (barring overflow, which is
// flagged). A product is exact when every two_prod inside it is, i.e. its error term
// is representable (see two_prod); a product falling below 2^-916 raises the flag, so
// !overflowed() always means the value is exact. The flag never rises for range
// reasons when the inputs pass expansion_safe and the computed quantity is a
// polynomial of degree <= 6 in them (derivation at expansion_safe); for other inputs
// the caller reruns with BigDyadic (with_exact does it).
//
// overflowed() is sticky and propagates through every operation: it is set when a
// result (or a partial product) needs more than Cap components after compression,
// when a component becomes non-finite, when a product may be inexact, or when the
// expansion was built from a NaN or an infinity.
template <int Cap> class Expansion {
    static_assert(Cap >= 2, "an expansion needs room for at least two components");

public:
    static constexpr int capacity = Cap;
    static constexpr std::size_t kSlots = static_cast<std::size_t>(Cap);  // array bounds

    Expansion() noexcept {}
    Expansion(double x) noexcept : bad_(!std::isfinite(x)) {  // exact
        if (x != 0 && !bad_) c_[n_++] = x;
    }
    Expansion(float x) noexcept : Expansion(static_cast<double>(x)) {}  // exact
    // Copies move only the components in use.
    Expansion(const Expansion& o) noexcept : n_(o.n_), bad_(o.bad_) { copy_from(o); }
    Expansion& operator=(const Expansion& o) noexcept {
        if (this == &o) return *this;
        n_ = o.n_;
        bad_ = o.bad_;
        copy_from(o);
        return *this;
    }

    bool overflowed() const { return bad_; }
    // Exact sign of the value: that of the largest component (the others sum to less
    // than its last bit). Meaningless when overflowed().
    int sign() const { return n_ == 0 ? 0 : (c_[n_ - 1] > 0 ? 1 : -1); }
    int size() const { return n_; }
    std::span<const double> components() const { return {c_, static_cast<std::size_t>(n_)}; }

    // value ≈ mant·2^exp, relative error < 2^-51: after compression the top component
    // is within one ulp of the value (Theorem 23), adding the next one leaves a
    // remainder below that, and the addition rounds once.
    Approx approx() const {
        if (n_ == 0) return {0.0, 0};
        double top = c_[0], next = 0;
        if (n_ >= 2) {
            double h[kSlots];
            std::memcpy(h, c_, sizeof(double) * static_cast<std::size_t>(n_));
            const int k = exact_impl::compress(h, n_);
            top = h[k - 1];
            next = k >= 2 ? h[k - 2] : 0.0;
        }
        int e = 0;
        (void)std::frexp(top, &e);
        double m = std::ldexp(top, -e) + std::ldexp(next, -e);
        int e2 = 0;
        m = std::frexp(m, &e2);
        return {m, static_cast<long>(e) + e2};
    }

    // Rewrite in place as a compressed (nonadjacent) expansion of the same value.
    void compress() { n_ = exact_impl::compress(c_, n_); }

    friend Expansion operator-(const Expansion& a) {
        Expansion r(a);
        for (int i = 0; i < r.n_; ++i) r.c_[i] = -r.c_[i];
        return r;
    }
    friend Expansion operator+(const Expansion& a, const Expansion& b) { return add(a, b, 1.0); }
    friend Expansion operator-(const Expansion& a, const Expansion& b) { return add(a, b, -1.0); }
    friend Expansion operator*(const Expansion& a, const Expansion& b) {
        if (a.bad_ || b.bad_) return flagged();
        if (a.n_ == 0 || b.n_ == 0) return Expansion();
        if (a.n_ == 1 && b.n_ == 1) {  // the common case: one two_prod
            const Pair p = two_prod(a.c_[0], b.c_[0]);
            const double m = std::abs(p.hi);
            if (!(m >= exact_impl::kMinExactProduct && m <= std::numeric_limits<double>::max())) return flagged();
            Expansion r;
            if (p.lo != 0) r.c_[r.n_++] = p.lo;
            r.c_[r.n_++] = p.hi;
            return r;
        }
        const Expansion& l = a.n_ >= b.n_ ? a : b;  // the longer one is scaled
        const Expansion& s = a.n_ >= b.n_ ? b : a;
        bool tiny = false;
        double buf0[4 * kSlots], buf1[4 * kSlots], t[2 * kSlots];
        double* acc = buf0;
        double* nxt = buf1;
        int k = exact_impl::scale(l.c_, l.n_, s.c_[0], acc, tiny);
        for (int j = 1; j < s.n_; ++j) {  // acc += l·s_j, kept within 2·Cap components
            const int tl = exact_impl::scale(l.c_, l.n_, s.c_[j], t, tiny);
            k = exact_impl::sum(acc, k, t, tl, 1.0, nxt);
            std::swap(acc, nxt);
            if (k > 2 * Cap) k = exact_impl::compress(acc, k);
            if (k > 2 * Cap) return flagged();
        }
        if (k > 2) k = exact_impl::compress(acc, k);  // products shrink a lot when compressed
        return store(acc, k, tiny);
    }
    Expansion& operator+=(const Expansion& o) { return *this = *this + o; }
    Expansion& operator-=(const Expansion& o) { return *this = *this - o; }
    Expansion& operator*=(const Expansion& o) { return *this = *this * o; }

private:
    void copy_from(const Expansion& o) { std::memcpy(c_, o.c_, sizeof(double) * static_cast<std::size_t>(o.n_)); }
    static Expansion flagged() {
        Expansion r;
        r.bad_ = true;
        return r;
    }
    // The result from a scratch buffer: compressed if it is too long, flagged if it
    // still is, or if any component is non-finite, or if a product may be inexact.
    static Expansion store(double* h, int k, bool bad) {
        if (k > Cap) k = exact_impl::compress(h, k);
        if (bad || k > Cap) return flagged();
        Expansion r;
        bool finite = true;
        for (int i = 0; i < k; ++i) {
            finite &= std::abs(h[i]) <= std::numeric_limits<double>::max();  // false for inf, NaN
            r.c_[i] = h[i];
        }
        if (!finite) return flagged();
        r.n_ = k;
        return r;
    }
    static Expansion add(const Expansion& a, const Expansion& b, double s) {
        if (a.bad_ || b.bad_) return flagged();
        if (b.n_ == 0) return a;
        if (a.n_ == 0) return s > 0 ? b : -b;
        double h[2 * kSlots];
        int k = 0;
        if (a.n_ == 1 && b.n_ == 1) {  // the common case: one two_sum
            const Pair r = two_sum(a.c_[0], s * b.c_[0]);
            if (r.lo != 0) h[k++] = r.lo;
            if (r.hi != 0) h[k++] = r.hi;
        } else {
            k = exact_impl::sum(a.c_, a.n_, b.c_, b.n_, s, h);
        }
        return store(h, k, false);
    }

    double c_[kSlots];
    int n_ = 0;
    bool bad_ = false;
};

// ===================================================================================
// 3. BigDyadic
// ===================================================================================
//
// The exact dyadic rational (−1)^neg · M · 2^(64·lexp), M = Σ limb[i]·2^(64 i) over the
// limbs in use; the exponent is kept a whole number of limbs so that aligning two
// operands never shifts bits. Normalized: no zero limb at either end (zero is n = 0).
//
// Capacity: kCapacity = 232 limbs = 14848 bits. A value fits when it is an integer
// multiple of 2^-7518 below 2^7184 in magnitude: 7518 + 7184 = 14702 bits, plus at
// most 63 bits of limb alignment, 14765 <= 14848. Every double or float is a multiple
// of 2^-1074 below 2^1024, so a product of k <= 7 of them is a multiple of 2^(-1074k)
// below 2^(1024k): any polynomial of total degree <= 7 in doubles (denormals
// included) with integer coefficients whose absolute values sum to at most 2^16 (e.g.
// up to 2^16 monomials) fits, and so does every intermediate of evaluating it, as long
// as the intermediates are such polynomials too (true for sums and products of
// differences of inputs: the coefficient sums multiply). Degree 5 with 1000 terms,
// the kernel's need, is far inside. Past the capacity overflowed() is set (never a
// crash or an assertion).
//
// BasicBigDyadic<L> is the same class with L limbs (kCapacity = L); BigDyadic is
// BasicBigDyadic<232>, the capacity above, and BigDyadic8 (below) the one for degree 8.
template <int Limbs> class BasicBigDyadic {
public:
    static constexpr int kCapacity = Limbs;

    BasicBigDyadic() noexcept {}
    BasicBigDyadic(double x) noexcept {  // exact
        if (!std::isfinite(x)) {
            of_ = true;
            return;
        }
        if (x == 0) return;
        const std::uint64_t bits = std::bit_cast<std::uint64_t>(x);
        neg_ = (bits >> 63) != 0;
        const int ef = static_cast<int>((bits >> 52) & 0x7ff);
        std::uint64_t m = bits & ((std::uint64_t(1) << 52) - 1);
        long e = -1074;  // subnormal: m·2^-1074
        if (ef != 0) {
            m |= std::uint64_t(1) << 52;
            e = ef - 1075;
        }
        const long q = exact_impl::floor_div64(e);  // e = 64q + r, 0 <= r < 64
        const int r = static_cast<int>(e - 64 * q);
        limb_[0] = m << r;
        limb_[1] = r == 0 ? 0 : m >> (64 - r);
        n_ = 2;
        lexp_ = q;
        normalize();
    }
    BasicBigDyadic(float x) noexcept : BasicBigDyadic(static_cast<double>(x)) {}  // exact
    // Copies move only the limbs in use.
    BasicBigDyadic(const BasicBigDyadic& o) noexcept : n_(o.n_), neg_(o.neg_), of_(o.of_), lexp_(o.lexp_) { copy_from(o); }
    BasicBigDyadic& operator=(const BasicBigDyadic& o) noexcept {
        if (this == &o) return *this;
        n_ = o.n_;
        neg_ = o.neg_;
        of_ = o.of_;
        lexp_ = o.lexp_;
        copy_from(o);
        return *this;
    }

    bool overflowed() const { return of_; }
    int sign() const { return n_ == 0 ? 0 : (neg_ ? -1 : 1); }
    // Representation, for tests and printing: value = ±Σ limb(i)·2^(64·(i + limb_exponent())).
    int limb_count() const { return n_; }
    std::uint64_t limb(int i) const { return limb_[i]; }
    long limb_exponent() const { return lexp_; }

    // value ≈ mant·2^exp: the top 64 bits of M with a sticky bit, correctly rounded to
    // double, so the relative error is at most 2^-53.
    Approx approx() const {
        if (n_ == 0) return {0.0, 0};
        const std::uint64_t top = limb_[n_ - 1];
        const int sh = std::countl_zero(top);
        std::uint64_t m = top << sh;
        bool sticky = n_ >= 3;  // normalized: the lowest limb is nonzero
        if (n_ >= 2) {
            const std::uint64_t below = limb_[n_ - 2];
            if (sh != 0) m |= below >> (64 - sh);
            sticky |= (sh == 0 ? below : below << sh) != 0;
        }
        m |= sticky ? 1 : 0;  // bit 0 lies below the rounding position: breaks ties right
        int e = 0;
        double mant = std::frexp(static_cast<double>(m), &e);
        if (neg_) mant = -mant;
        return {mant, e + 64 * (lexp_ + n_ - 1) - sh};
    }

    friend BasicBigDyadic operator-(const BasicBigDyadic& a) {
        BasicBigDyadic r(a);
        if (r.n_ != 0) r.neg_ = !r.neg_;
        return r;
    }
    friend BasicBigDyadic operator+(const BasicBigDyadic& a, const BasicBigDyadic& b) { return add(a, b, false); }
    friend BasicBigDyadic operator-(const BasicBigDyadic& a, const BasicBigDyadic& b) { return add(a, b, true); }
    // Schoolbook product of the limbs in use, 128-bit partial products. A zero limb of a
    // adds nothing and is skipped: a sum of numbers of far apart magnitudes (a subnormal
    // direction component beside a unit one) has few nonzero limbs among many. Row i
    // writes limb i + nb, which no earlier row reached, so a skipped row leaves it 0.
    friend BasicBigDyadic operator*(const BasicBigDyadic& a, const BasicBigDyadic& b) {
        BasicBigDyadic r;
        if (a.of_ || b.of_ || a.n_ + b.n_ - 1 > kCapacity) return flagged();  // needs >= na+nb-1 limbs
        if (a.n_ == 0 || b.n_ == 0) return r;
        std::fill_n(r.limb_, a.n_ + b.n_, std::uint64_t(0));
        for (int i = 0; i < a.n_; ++i) {
            if (a.limb_[i] == 0) continue;
            std::uint64_t carry = 0;
            for (int j = 0; j < b.n_; ++j) {
                const LimbPair t = mul_add_add(a.limb_[i], b.limb_[j], r.limb_[i + j], carry);
                r.limb_[i + j] = t.lo;
                carry = t.hi;
            }
            r.limb_[i + b.n_] = carry;
        }
        r.n_ = a.n_ + b.n_;
        r.lexp_ = a.lexp_ + b.lexp_;
        r.neg_ = a.neg_ != b.neg_;
        r.normalize();
        return r;
    }
    BasicBigDyadic& operator+=(const BasicBigDyadic& o) { return *this = *this + o; }
    BasicBigDyadic& operator-=(const BasicBigDyadic& o) { return *this = *this - o; }
    BasicBigDyadic& operator*=(const BasicBigDyadic& o) { return *this = *this * o; }

private:
    void copy_from(const BasicBigDyadic& o) {
        std::memcpy(limb_, o.limb_, sizeof(std::uint64_t) * static_cast<std::size_t>(o.n_));
    }

    static BasicBigDyadic flagged() {
        BasicBigDyadic r;
        r.of_ = true;
        return r;
    }
    // Limb at absolute position k (weight 2^(64k)), 0 outside the limbs in use.
    std::uint64_t at(long k) const {
        const long i = k - lexp_;
        return i >= 0 && i < n_ ? limb_[i] : 0;
    }
    // Drop zero limbs at both ends; flag if the result is still too long.
    void normalize() {
        while (n_ > 0 && limb_[n_ - 1] == 0) --n_;
        if (n_ == 0) {
            neg_ = false;
            lexp_ = 0;
            return;
        }
        int z = 0;
        while (limb_[z] == 0) ++z;
        if (z != 0) {
            std::memmove(limb_, limb_ + z, sizeof(std::uint64_t) * static_cast<std::size_t>(n_ - z));
            n_ -= z;
            lexp_ += z;
        }
        if (n_ > kCapacity) *this = flagged();
    }
    // Compare |a| and |b| (both normalized, nonzero).
    static int cmp_mag(const BasicBigDyadic& a, const BasicBigDyadic& b) {
        const long ta = a.lexp_ + a.n_, tb = b.lexp_ + b.n_;
        if (ta != tb) return ta > tb ? 1 : -1;
        const long lo = std::min(a.lexp_, b.lexp_);
        for (long k = ta - 1; k >= lo; --k) {
            const std::uint64_t x = a.at(k), y = b.at(k);
            if (x != y) return x > y ? 1 : -1;
        }
        return 0;
    }
    static BasicBigDyadic add(const BasicBigDyadic& a, const BasicBigDyadic& b, bool negate_b) {
        if (a.of_ || b.of_) return flagged();
        if (b.n_ == 0) return a;
        if (a.n_ == 0) return negate_b ? -b : b;
        const bool nb = b.neg_ != negate_b;
        const long lo = std::min(a.lexp_, b.lexp_);
        const long span = std::max(a.lexp_ + a.n_, b.lexp_ + b.n_) - lo;
        BasicBigDyadic r;
        r.lexp_ = lo;
        if (a.neg_ == nb) {  // |a| + |b|: needs >= span limbs
            if (span > kCapacity) return flagged();
            std::uint64_t carry = 0;
            for (long i = 0; i < span; ++i) {
                const LimbPair s = add_carry(a.at(lo + i), b.at(lo + i), carry);
                r.limb_[i] = s.lo;
                carry = s.hi;
            }
            r.limb_[span] = carry;
            r.n_ = static_cast<int>(span + 1);
            r.neg_ = a.neg_;
        } else {  // ||a| − |b||: the top drops by at most one limb, so needs >= span − 1 limbs
            if (span > kCapacity + 1) return flagged();
            const int c = cmp_mag(a, b);
            if (c == 0) return BasicBigDyadic();
            const BasicBigDyadic& big = c > 0 ? a : b;
            const BasicBigDyadic& small = c > 0 ? b : a;
            std::uint64_t borrow = 0;
            for (long i = 0; i < span; ++i) {
                const std::uint64_t x = big.at(lo + i), y = small.at(lo + i);
                const std::uint64_t d = x - y - borrow;
                borrow = (x < y || (x == y && borrow)) ? 1 : 0;
                r.limb_[i] = d;
            }
            r.n_ = static_cast<int>(span);
            r.neg_ = c > 0 ? a.neg_ : nb;
        }
        r.normalize();
        return r;
    }

    std::uint64_t limb_[std::size_t(kCapacity) + 1];  // one spare limb for a carry or a product's top
    int n_ = 0;
    bool neg_ = false;
    bool of_ = false;
    long lexp_ = 0;  // exponent in limbs: the lowest limb weighs 2^(64·lexp_)
};

using BigDyadic = BasicBigDyadic<232>;

// BigDyadic8: exact for polynomials of total degree <= 8. kCapacity = 272 limbs = 17408
// bits. A product of k <= 8 doubles or floats is a multiple of 2^(-1074k) >= 2^-8592
// below 2^(1024k) <= 2^8192; with integer coefficients whose absolute values sum to at
// most 2^20 a value is below 2^8212: 8592 + 8212 = 16804 bits, plus at most 63 bits of
// limb alignment, 16867 <= 17408. Intermediates obey the same rule as BigDyadic's
// (sums and products of differences of inputs). Used by the exact order of two sphere
// entries (detail/entry_order.hpp), whose decisive polynomials have degree 8.
using BigDyadic8 = BasicBigDyadic<272>;

// Exact conversion of an expansion (the flag carries over), to BigDyadic unless Big
// names another capacity.
template <class Big = BigDyadic, int Cap> Big to_big_dyadic(const Expansion<Cap>& e) {
    if (e.overflowed()) return Big(std::numeric_limits<double>::quiet_NaN());
    Big r;
    for (double c : e.components()) r += Big(c);
    return r;
}

template <class E> struct is_expansion : std::false_type {};
template <int Cap> struct is_expansion<Expansion<Cap>> : std::true_type {};
template <class E> inline constexpr bool is_expansion_v = is_expansion<E>::value;

// True when any of the exact values has its overflowed() flag set.
template <class... E> bool any_overflowed(const E&... e) { return (e.overflowed() || ...); }

// ===================================================================================
// 4. Which exact type: expansion_safe
// ===================================================================================
//
// expansion_safe(x): x == 0, or |x| in [2^-100, 2^100] for double; every finite float.
// Derivation. Call g the grain of an expansion when all its components are integer
// multiples of 2^g. A double with |x| >= 2^-100 has grain >= −152 (its last bit).
// two_sum and fast_two_sum keep the grain (rounding a multiple of 2^g to a double
// gives a multiple of 2^g; the error is a difference of such), so sums and
// differences of inputs, at any depth, have grain >= −152. A product of grains g1, g2
// has grain g1 + g2, so a product of k such factors has grain >= −152k. For k <= 6
// that is >= −912: every nonzero component is >= 2^-912 > 2^-916, so no two_prod can
// fall below kMinExactProduct (the flag never rises for range reasons), every error
// term is a normal number, and IEEE arithmetic coincides with the unbounded-exponent
// model of Shewchuk's proofs. (k = 7 still gives grain −1064 >= −1074: still exact,
// but the flag may rise and force the BigDyadic rerun.) Upper end: |x| <= 2^100, so
// differences are < 2^102, degree-6 products < 2^612 and sums of 2^16 of them
// < 2^628, far below 2^1024: no overflow. In terms of magnitudes: nonzero components
// of differences are >= 2^(-100-52), degree-5 products >= 2^(-152·5) = 2^-760, their
// two_prod error terms at most 2^-106 below that, >= 2^-866, well above 2^-1022.
// Floats: every finite float has grain >= −149 and magnitude < 2^128, so degree-6
// products have grain >= −894 (> −916: no flag) and magnitude < 2^(6·129) = 2^774
// (sums of 2^16 of them < 2^790): every finite float is safe.
template <class T>
    requires(std::is_same_v<T, float> || std::is_same_v<T, double>)
bool expansion_safe(T x) {
    if constexpr (std::is_same_v<T, float>) {
        return std::isfinite(x);
    } else {
        const double a = std::abs(x);
        return a == 0 || (a >= 0x1p-100 && a <= 0x1p100);  // false for NaN and inf
    }
}
template <class T> bool expansion_safe(std::initializer_list<T> xs) {
    for (T x : xs)
        if (!expansion_safe(x)) return false;
    return true;
}
template <class Derived> bool expansion_safe(const Eigen::DenseBase<Derived>& m) {
    for (Eigen::Index j = 0; j < m.cols(); ++j)
        for (Eigen::Index i = 0; i < m.rows(); ++i)
            if (!expansion_safe(m(i, j))) return false;
    return true;
}

// A range of shifts (powers of two), empty when lo > hi.
struct ShiftRange {
    int lo, hi;
};

// Rescaling into the safe range. A predicate whose inputs fall in groups that scale
// alike (every position by 2^sp, every direction by 2^sd, say) has a sign that
// changes by a positive factor only, so it can be decided on the rescaled inputs. The
// binary exponents of a group's nonzero values, and the power of two that puts them all
// in [2^-100, 2^100) when they span at most 199 binades: s = 99 - the largest exponent
// (the smallest one then becomes >= -100). Each product x·2^s is then a normal double,
// exact (times_pow2, float_util.hpp: |s| <= 99 + 1074).
struct ExponentSpan {
    int hi = std::numeric_limits<int>::min(), lo = std::numeric_limits<int>::max();
    void add(double x) noexcept {
        if (x == 0) return;
        const int k = binary_exponent(x);
        hi = std::max(hi, k);
        lo = std::min(lo, k);
    }
    // The shift, or none when the group is too wide; 0 for a group of zeros only.
    std::optional<int> safe_shift() const noexcept {
        if (hi < lo) return 0;
        if (hi - lo > 199) return std::nullopt;
        return 99 - hi;
    }
    // Every shift s that puts the group in [2^-100, 2^100] (2^(k + s) >= 2^-100 and
    // 2^(k + s + 1) <= 2^100 for every exponent k): [-100 - lo, 99 - hi], empty (lo > hi)
    // when the group is too wide; for a group of zeros only, every shift that keeps a
    // value safe for times_pow2 (|s| <= 1173).
    ShiftRange shift_range() const noexcept {
        if (hi < lo) return {-1173, 1173};
        return {-100 - lo, 99 - hi};
    }
};

// c·2^k into out when that product is a finite double that loses no bit (the round
// trip checks the subnormal range); false otherwise.
inline bool scale_exactly(double c, int k, double& out) {
    out = std::ldexp(c, k);
    return std::isfinite(out) && std::ldexp(out, -k) == c;
}

// A faithful double for q from f', a faithful double for 2^shift·q, or none. f' normal
// (neither clamped to ±max nor flushed to 0) lies with 2^shift·q between two neighbours,
// so f'·2^-shift, where it is exact, lies with q between two doubles no farther apart
// than its own neighbours (the same ones, or in the subnormal range coarser): faithful
// for q. Where it overflows: 2^shift·|q| > pred(|f'|) >= 2^e·(1 - 2^-53), e the binary
// exponent of f', so e - shift >= 1024 puts |q| above (1 - 2^-53)·2^1024, the largest
// double, whose faithful rounding is then ±max with f''s sign, as faithful_quotient
// answers it.
inline std::optional<double> unscaled_faithful(double f, int shift) {
    const double a = std::abs(f);
    if (!(a >= std::numeric_limits<double>::min() && a < std::numeric_limits<double>::max())) return std::nullopt;
    if (double q; scale_exactly(f, -shift, q)) return q;
    if (binary_exponent(a) - shift >= 1024) return std::copysign(std::numeric_limits<double>::max(), f);
    return std::nullopt;
}

// ===================================================================================
// 5. The dispatcher and the exact decisions
// ===================================================================================

// Names an exact type for a generic lambda: [&](auto tag) { using E = typename decltype(tag)::type; ... }
template <class E> struct exact_tag {
    using type = E;
};

inline constexpr int kDefaultExpansionCap = 32;

template <class R> struct is_optional : std::false_type {};
template <class V> struct is_optional<std::optional<V>> : std::true_type {};

// Run an exact algorithm written once for both exact types.
//   f(exact_tag<E>{}) computes with E and returns std::optional<V>: std::nullopt when
//   a value it relied on overflowed() (any_overflowed helps), else the answer.
// When `safe` (usually expansion_safe of every input), f first runs with
// Expansion<Cap>; if it returns nullopt, or when !safe, f runs with BigDyadic. The
// result is f's: nullopt only if BigDyadic's capacity was exceeded too, which cannot
// happen within its documented degree (see BigDyadic). Big names a larger BigDyadic
// (BigDyadic8) for algorithms of higher degree.
//   auto s = with_exact(expansion_safe({a, b, c}), [&](auto tag) -> std::optional<int> {
//       using E = typename decltype(tag)::type;
//       const E v = E(a) * E(b) - E(c);
//       if (v.overflowed()) return std::nullopt;
//       return v.sign();
//   });
template <int Cap = kDefaultExpansionCap, class Big = BigDyadic, class F> auto with_exact(bool safe, F&& f) {
    using R = std::invoke_result_t<F&, exact_tag<Big>>;
    static_assert(is_optional<R>::value, "the exact algorithm returns std::optional<V>");
    static_assert(std::is_same_v<R, std::invoke_result_t<F&, exact_tag<Expansion<Cap>>>>,
                  "the exact algorithm returns the same type for both exact types");
    if (safe) {
        R r = f(exact_tag<Expansion<Cap>>{});
        if (r) return r;
    }
    return f(exact_tag<Big>{});
}

// The exact sign of value(exact_tag<E>{}), an exact value computed once for both exact
// types by with_exact: an overflowed expansion hands the value over to BigDyadic.
template <class F> int exact_sign(bool safe, F&& value) {
    return *with_exact(safe, [&](auto tag) -> std::optional<int> {
        const auto v = value(tag);
        if (v.overflowed()) return std::nullopt;
        return v.sign();
    });
}

namespace exact_impl {

// sign(num/den − x) = sign(num − x·den)·sign(den), exact; x finite. nullopt when an
// expansion overflowed on the way (x·den may fall outside the expansion's range).
template <class E, class T> std::optional<int> side(const E& num, const E& den, int sden, T x) {
    const E r = num - E(x) * den;
    if (r.overflowed()) return std::nullopt;
    return r.sign() * sden;
}

// The faithful quotient; nullopt if an expansion overflowed on the way.
template <class T, class E> std::optional<T> quotient(const E& num, const E& den) {
    constexpr T kMax = std::numeric_limits<T>::max();
    constexpr long kMaxExp = std::numeric_limits<T>::max_exponent;  // max < 2^kMaxExp
    constexpr long kMinExp = std::numeric_limits<T>::min_exponent - std::numeric_limits<T>::digits;  // denorm_min = 2^kMinExp
    const int sden = den.sign();
    const Approx an = num.approx(), ad = den.approx();
    if (an.mant == 0) return T(0);
    // Candidate: q ≈ (an.mant/ad.mant)·2^(an.exp − ad.exp), |an.mant/ad.mant| in (0.5, 2),
    // a few ulps from the quotient; exponents kept apart so it works outside T's range.
    // The exact stepping below makes the answer right whatever the candidate.
    const double m = an.mant / ad.mant;
    const long e = an.exp - ad.exp;
    T q;
    if (e > kMaxExp + 1) {
        q = std::copysign(kMax, narrow<T>(m));  // |quotient| > 2^(kMaxExp+1)·(1 − 2^-49)
    } else if (e < kMinExp - 2) {
        q = 0;  // |quotient| < 2^(kMinExp−2)·(1 + 2^-49)
    } else {
        q = std::ldexp(narrow<T>(m), static_cast<int>(e));
        if (std::isinf(q)) q = std::copysign(kMax, q);
    }
    // Step towards the quotient one T at a time until it is bracketed.
    const std::optional<int> s0 = side(num, den, sden, q);
    if (!s0) return std::nullopt;
    const int s = *s0;  // sign(quotient − q), constant while stepping
    while (s != 0) {
        const T next = s > 0 ? step_up(q) : step_down(q);
        if (std::isinf(next)) break;  // quotient beyond ±max: q = ±max encloses it
        const std::optional<int> s1 = side(num, den, sden, next);
        if (!s1) return std::nullopt;
        if (*s1 != s) {  // next == quotient, or quotient strictly between q and next
            if (*s1 == 0) q = next;
            break;
        }
        q = next;
    }
    return q == 0 ? T(0) : q;  // +0, never -0
}

}  // namespace exact_impl

// num/den faithfully rounded to T (float or double): the quotient itself when it is
// representable, otherwise one of the two adjacent T values enclosing it. Beyond the
// largest finite T the answer is ±numeric_limits<T>::max() (the enclosing finite
// neighbour; infinity is never returned); a nonzero quotient below the smallest
// subnormal gives 0 or the smallest subnormal of its sign; zero is always +0.0.
// Preconditions: den != 0, neither input overflowed() (otherwise returns 0).
// An Expansion whose check products leave the expansion range (for instance a
// subnormal quotient) is redone exactly with BigDyadic.
template <class T, class E> T faithful_quotient(const E& num, const E& den) {
    static_assert(std::is_same_v<T, float> || std::is_same_v<T, double>);
    if (any_overflowed(num, den) || den.sign() == 0) return T(0);
    if (const std::optional<T> q = exact_impl::quotient<T>(num, den)) return *q;
    if constexpr (is_expansion_v<E>) {
        return faithful_quotient<T>(to_big_dyadic(num), to_big_dyadic(den));
    } else {
        return T(0);  // unreachable within BigDyadic's documented capacity
    }
}

// sign(n1/d1 − n2/d2), exact: sign(n1·d2 − n2·d1)·sign(d1)·sign(d2). Preconditions:
// d1, d2 != 0, no input overflowed(). An Expansion overflow is redone with BigDyadic.
template <class E> int compare_quotients(const E& n1, const E& d1, const E& n2, const E& d2) {
    const E x = n1 * d2 - n2 * d1;
    if constexpr (is_expansion_v<E>) {
        if (x.overflowed() && !any_overflowed(n1, d1, n2, d2))
            return compare_quotients(to_big_dyadic(n1), to_big_dyadic(d1), to_big_dyadic(n2), to_big_dyadic(d2));
    }
    return x.sign() * d1.sign() * d2.sign();
}

// sign(num/den − t) for a finite T value t, exact. Preconditions as compare_quotients.
template <class E, class T> int compare_quotient(const E& num, const E& den, T t) {
    static_assert(std::is_same_v<T, float> || std::is_same_v<T, double>);
    if (const std::optional<int> s = exact_impl::side(num, den, den.sign(), t)) return *s;
    if constexpr (is_expansion_v<E>) {
        if (!any_overflowed(num, den)) return compare_quotient(to_big_dyadic(num), to_big_dyadic(den), t);
    }
    return 0;  // an overflowed input: meaningless
}

// Whether two_prod(x, y) is exact and x·y far below overflow, for x and y of any range:
// x·y is a multiple of 2^(kx + ky), kx and ky the exponents of their last bits, so its
// rounding error is representable when kx + ky >= -1074 (eft.hpp); and |x·y| < 2^1000
// when their binary exponents add to at most 998, which leaves room for sums of up to
// 2^23 such products.
inline bool exact_product(double x, double y) {
    if (x == 0 || y == 0) return true;
    return last_bit_exponent(x) + last_bit_exponent(y) >= -1074 && binary_exponent(x) + binary_exponent(y) <= 998;
}

// A nonoverlapping expansion of at most N doubles, components by increasing magnitude,
// grown one term at a time with zero elimination (GROW-EXPANSION, Shewchuk 1997,
// Theorem 10): exact while no partial sum overflows and N components suffice; a term
// that finds no room sets `full`, and the value is then incomplete. add_product adds
// x·y exactly when two_prod is exact for it (the caller's ranges say so). Fixed-size
// exact sums for expressions known in advance, without Expansion's general machinery.
template <int N> struct GrowingSum {
    double e[std::size_t(N)];
    int n = 0;
    bool full = false;
    void add(double x) {
        if (x == 0) return;
        int k = 0;
        for (int j = 0; j < n; ++j) {
            const Pair s = two_sum(x, e[j]);
            if (s.lo != 0) e[k++] = s.lo;
            x = s.hi;
        }
        if (x != 0) {
            if (k < N)
                e[k++] = x;
            else
                full = true;
        }
        n = k;
    }
    void add_product(double x, double y) {
        if (x == 0 || y == 0) return;
        const Pair p = two_prod(x, y);
        add(p.lo);
        add(p.hi);
    }
    // Checked growth, for input of any range: x·y where two_prod is exact for it
    // (exact_product), else the value is marked incomplete (`full`).
    void add_product_checked(double x, double y) {
        if (exact_product(x, y))
            add_product(x, y);
        else
            full = true;
    }
    int sign() const { return n == 0 ? 0 : (e[n - 1] > 0 ? 1 : -1); }
    // The smallest last-bit exponent of the components (every component, and every sum
    // of them, is a multiple of 2^grain()) and the binary exponent of the largest (every
    // component is below 2^(top() + 1)); for no components, 2000 and -2000.
    int grain() const {
        int g = 2000;
        for (int j = 0; j < n; ++j) g = std::min(g, last_bit_exponent(e[j]));
        return g;
    }
    int top() const { return n == 0 ? -2000 : binary_exponent(e[n - 1]); }
    // Every component times 2^k where each product is exact (no bit falls below 2^-1074,
    // none reaches 2^1024): the value times 2^k, still nonoverlapping; false (nothing
    // changed) otherwise.
    bool scale(int k) {
        if (n == 0) return true;
        if (grain() + k < -1074 || top() + k > 1023) return false;
        for (int j = 0; j < n; ++j) e[j] = times_pow2(e[j], k);
        return true;
    }
    double estimate() const {  // the components summed from the smallest: within a few ulps
        double s = 0;
        for (int j = 0; j < n; ++j) s += e[j];
        return s;
    }
    // The same value in as few components as COMPRESS leaves (exact_impl::compress:
    // exact on a nonoverlapping expansion), still nonoverlapping by increasing
    // magnitude: fewer terms for the products taken next.
    void compress() { n = exact_impl::compress(e, n); }
};

// Whether every product of a component of x by one of y (GrowingSum) is exact by
// two_prod and below 2^1000 (exact_product's argument, from the sums' grain and top).
template <class X, class Y> bool exact_products(const X& x, const Y& y) {
    if (x.n == 0 || y.n == 0) return true;
    return x.grain() + y.grain() >= -1074 && x.top() + y.top() <= 998;
}

// sign(x1·y1 - x2·y2) for exact sums (GrowingSum) whose every product of a component of
// an x by one of the y beside it two_prod takes exactly (the caller's ranges say so, or
// exact_products): the products grown into one sum of at most N components; none where
// N does not suffice.
template <int N, class X, class Y>
std::optional<int> sign_cross_difference(const X& x1, const Y& y1, const X& x2, const Y& y2) {
    GrowingSum<N> s;
    for (int i = 0; i < x1.n; ++i)
        for (int j = 0; j < y1.n; ++j) s.add_product(x1.e[i], y1.e[j]);
    for (int i = 0; i < x2.n; ++i)
        for (int j = 0; j < y2.n; ++j) s.add_product(-x2.e[i], y2.e[j]);
    if (s.full) return std::nullopt;
    return s.sign();
}

// The exact sign of x[0] + ... + x[n-1] (finite doubles, n <= 8, no partial sum near
// overflow): the terms grown into one expansion (GrowingSum), whose largest component
// has the sign of the whole.
inline int exact_sum_sign(const double* x, int n) {
    GrowingSum<8> s;
    for (int i = 0; i < n; ++i) s.add(x[i]);
    return s.sign();
}

// Whether two_prod(x, y) (x finite or not, y finite and nonzero) was exact with its hi
// at most 2^1000: x == 0 (the product is 0), or |hi| in [2^-916, 2^1000], where the
// error term is normal, hence exact (eft.hpp); false for a NaN or infinite hi.
RAYPROOF_ALWAYS_INLINE bool exact_product_taken(double x, double hi) {
    const double a = std::abs(hi);
    return int(x == 0) | (int(a >= exact_impl::kMinExactProduct) & int(a <= 0x1p1000));
}

// sign(x - y) for reals x = x.hi + x.lo and y = y.hi + y.lo (exactly) whose hi parts
// are their roundings to nearest (two_sum's and two_prod's results): rounding is
// monotone, so x <= y would give x.hi <= y.hi, and x.hi > y.hi proves x > y (likewise
// <); on equal hi parts x - y = x.lo - y.lo exactly, whose sign the comparison of the
// two lo parts gives. Two comparisons, no sum.
RAYPROOF_ALWAYS_INLINE int compare_rounded_pairs(const Pair& x, const Pair& y) {
    const int hi = int(x.hi > y.hi) - int(x.hi < y.hi), lo = int(x.lo > y.lo) - int(x.lo < y.lo);
    return hi != 0 ? hi : lo;
}

// sign(x1·y1 − x2·y2) for finite doubles, exactly at any scale (no product need be
// representable): the products' signs first; for two of the same nonzero sign, each
// factor split as m·2^e (split_exponent, exact) and E1 = e_x1 + e_y1, E2 = e_x2 + e_y2;
// where they differ by 2 or more the exponents decide (|x1 y1| >= 2^E1 >= 2^(E2 + 2) >
// |x2 y2|, or the other way), else the products of the ms, each exactly two doubles of
// magnitude [1, 4) and a low part 0 or at least 2^-104 (two_prod, no underflow), the
// first scaled by 2^(E1 - E2), one of 1/2, 1, 2 (exact), compared as rounded pairs.
inline int compare_products(double x1, double y1, double x2, double y2) {
    const auto sign = [](double x) { return int(x > 0) - int(x < 0); };
    const int s1 = sign(x1) * sign(y1), s2 = sign(x2) * sign(y2);
    if (s1 != s2 || s1 == 0) return int(s1 > s2) - int(s1 < s2);
    const SplitDouble a = split_exponent(x1), b = split_exponent(y1), c = split_exponent(x2), d = split_exponent(y2);
    const int k = (a.e + b.e) - (c.e + d.e);
    if (k >= 2) return s1;
    if (k <= -2) return -s1;
    const Pair p = two_prod(std::abs(a.m), std::abs(b.m)), q = two_prod(std::abs(c.m), std::abs(d.m));
    const double scale = k == 0 ? 1.0 : k > 0 ? 2.0 : 0.5;
    return compare_rounded_pairs(Pair{p.hi * scale, p.lo * scale}, q) * s1;
}

// sign((p1 − o1)/d1 − (p2 − o2)/d2) for finite slab values with d1, d2 finite and
// nonzero, without an expansion type, for input of any range: p − o = s + e exactly
// (two_sum), each part's product by the other denominator exactly two doubles where
// exact_product_taken says so, and the sign of s1·d2 + e1·d2 − s2·d1 − e2·d1 times
// sign(d1 d2). two_sum is exact unless one of its steps overflows, and then its error
// term is ±inf or NaN (an infinite step propagates to it), whose product fails the
// check. Every input 0 or in [2^-100, 2^100] (expansion_safe) always passes: |s·d| >=
// 2^-200 and |e·d| >= 2^-253 where nonzero, below 2^201.
// Where both differences are exact (e1 = e2 = 0: the common case, and every grazing
// configuration of small integers), the sign is that of s1·d2 − s2·d1: two exact
// products as rounded pairs (compare_rounded_pairs) where both are taken, else
// compare_products (exact at any scale), so that this case is never declined;
// otherwise that of the eight-term sum (each term at most 2^1000: it cannot overflow),
// grown exactly, and none where one of its products may be inexact.
inline std::optional<int> compare_slab_values(double p1, double o1, double d1, double p2, double o2, double d2) {
    const Pair n1 = two_sum(p1, -o1), n2 = two_sum(p2, -o2);
    const Pair a = two_prod(n1.hi, d2), c = two_prod(n2.hi, d1);
    const bool taken = exact_product_taken(n1.hi, a.hi) && exact_product_taken(n2.hi, c.hi);
    const int sign_d = (d1 > 0) == (d2 > 0) ? 1 : -1;
    if (n1.lo == 0 && n2.lo == 0)
        return (taken ? compare_rounded_pairs(a, c) : compare_products(n1.hi, d2, n2.hi, d1)) * sign_d;
    if (!taken) return std::nullopt;
    const Pair b = two_prod(n1.lo, d2), d = two_prod(n2.lo, d1);
    if (!(exact_product_taken(n1.lo, b.hi) && exact_product_taken(n2.lo, d.hi))) return std::nullopt;
    const double x[8] = {a.lo, b.lo, -c.lo, -d.lo, a.hi, b.hi, -c.hi, -d.hi};
    return exact_sum_sign(x, 8) * sign_d;
}
// sign((p − o)/d − t) likewise for a finite t: the sign of (s + e) − t·d, s + e = p − o
// (two_sum: s its rounding) and t·d (two_prod) both as rounded pairs
// (compare_rounded_pairs) where t·d is taken and e is finite (no step of two_sum
// overflowed); where it is not taken but e = 0, the sign of s·1 − t·d by
// compare_products; none otherwise.
inline std::optional<int> compare_slab_value(double p, double o, double d, double t) {
    const Pair n = two_sum(p, -o), td = two_prod(t, d);
    const int sign_d = d > 0 ? 1 : -1;
    if (exact_product_taken(t, td.hi) && n.lo - n.lo == 0) return compare_rounded_pairs(n, td) * sign_d;
    if (n.lo == 0) return compare_products(n.hi, 1.0, t, d) * sign_d;
    return std::nullopt;
}

// The determinant a(ei − fh) − b(di − fg) + c(dh − eg) in an exact type.
template <class E, class T> E det3_exact(const Eigen::Matrix<T, 3, 3>& m) {
    const E a(m(0, 0)), b(m(0, 1)), c(m(0, 2));
    const E d(m(1, 0)), e(m(1, 1)), f(m(1, 2));
    const E g(m(2, 0)), h(m(2, 1)), i(m(2, 2));
    return a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g);
}

// Exact sign of det(m) for any finite entries (0 for a non-finite entry).
// Filter: when every nonzero entry is in [2^-300, 2^300] (always for float), the
// determinant is evaluated in double as a(ei − fh) − b(di − fg) + c(dh − eg) with no
// overflow (everything < 2^904) and no underflow (products of two entries are normal
// and >= 2^-600, hence multiples of 2^-652, so a nonzero minor is >= 2^-652 and
// a·minor >= 2^-952; >= 2^-1004 if the compiler fuses e·i − f·h into one fma), so
// each monomial sees at most 5 roundings (product, difference, product, two sums;
// fewer if fused): |det_fl − det| <= gamma(5)·P, P = Σ|monomials|. The permanent P_fl,
// evaluated the same way on |entries| (nonnegative terms, each >= 2^-900), satisfies
// P <= P_fl/(1 − gamma(5)), so the error is <= gamma(5)/(1 − gamma(5))·P_fl
// <= gamma(6)·P_fl. The bound is computed as fl(fl(gamma(7))·P_fl) (normal: >= 2^-950)
// >= gamma(7)(1 − u)^2·P_fl >= gamma(6)·P_fl, so |det_fl| > bound proves the sign.
// Otherwise: exact, with Expansion when the entries are expansion_safe (degree 3),
// else (or on overflow) with BigDyadic. Finite entries outside the filter's or the
// Expansion type's range are first rescaled by one power of two 2^s into
// [2^-100, 2^100] where they span at most 199 binades (ExponentSpan; each product
// exact), which multiplies the determinant by 2^(3s), its sign unchanged.
template <class T> int det3_sign(const Eigen::Matrix<T, 3, 3>& m) {
    static_assert(std::is_same_v<T, float> || std::is_same_v<T, double>);
    bool filterable = true, finite = true;
    ExponentSpan span;
    for (int k = 0; k < 9; ++k) {
        const double v = static_cast<double>(m.data()[k]), x = std::abs(v);
        filterable &= x == 0 || (x >= 0x1p-300 && x <= 0x1p300);  // false for NaN, inf
        finite &= std::isfinite(v);
        if (std::isfinite(v)) span.add(v);
    }
    if (finite && !expansion_safe(m))
        if (const std::optional<int> s = span.safe_shift(); s && *s != 0) {
            Eigen::Matrix<double, 3, 3> w;
            for (int k = 0; k < 9; ++k) w.data()[k] = times_pow2(static_cast<double>(m.data()[k]), *s);
            return det3_sign(w);
        }
    if (filterable) {
        const double a = m(0, 0), b = m(0, 1), c = m(0, 2);
        const double d = m(1, 0), e = m(1, 1), f = m(1, 2);
        const double g = m(2, 0), h = m(2, 1), i = m(2, 2);
        const double det = a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g);
        const double perm = std::abs(a) * (std::abs(e) * std::abs(i) + std::abs(f) * std::abs(h)) +
                            std::abs(b) * (std::abs(d) * std::abs(i) + std::abs(f) * std::abs(g)) +
                            std::abs(c) * (std::abs(d) * std::abs(h) + std::abs(e) * std::abs(g));
        constexpr double kBound = gamma<double>(7);
        const double bound = kBound * perm;
        if (det > bound) return 1;
        if (-det > bound) return -1;
    }
    const std::optional<int> s = with_exact(expansion_safe(m), [&](auto tag) -> std::optional<int> {
        using E = typename decltype(tag)::type;
        const E det = det3_exact<E>(m);
        if (det.overflowed()) return std::nullopt;
        return det.sign();
    });
    return s.value_or(0);  // nullopt only for a non-finite entry
}

}  // namespace rayproof::detail

#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif
