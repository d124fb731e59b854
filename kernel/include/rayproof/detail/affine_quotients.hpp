// rayproof/detail/affine_quotients.hpp — the exact side of the slab frames whose values
// are quotients of two affine forms: (s_i - a_i·(o - c)) / (a_i·d) for rows i < R, with
// s_i = -h_i (side 0) or +h_i (side 1). The oriented box's three slabs (a_i its axes, c
// its centre, h_i its half-extents; ray_obb.hpp) and the plane's crossing (R = 1, a_0 the
// normal, c = 0, h_0 = -offset, side 0: (offset - n·o)/(n·d); ray_plane.hpp).
// As a source of exact quotients (detail/certified.hpp, ExactQuotients) over the input
// in double: as given (widened), or rescaled into the range where the Expansion type
// and quick_compare are exact (rescaled()); quick_compare, quick_faithful and the exact
// signs of num and den without an expansion type, from fixed-size sums of error-free
// products (GrowingSum, exact.hpp). AffineSource serves a frame both, each made on first
// use.
// Rescaling: the positions (o, c) by 2^sp, the rows a_i by 2^sa, the h_i by 2^(sp + sa)
// and the direction by 2^sd (each exact: every scaled value is a normal double) multiply
// every num by 2^(sp + sa), every den by 2^(sa + sd) and every quotient by
// 2^(sp - sd) = 2^shift(), so that every sign of a num or a den, and of a difference of
// two quotients or of one and a constant scaled alike, is unchanged.
#pragma once

#include <rayproof/detail/certified.hpp>
#include <rayproof/detail/exact.hpp>
#include <rayproof/detail/float_util.hpp>
#include <rayproof/detail/rounding.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>
#include <utility>

namespace rayproof::detail {

// The input of AffineQuotients in double: a[i][j] is row i's component j.
template <int R> struct AffineValues {
    double o[3], c[3], d[3], a[std::size_t(R)][3], h[std::size_t(R)];
};

template <int R> class AffineQuotients {
public:
    // floats: the values are floats widened (every float is safe for expansions).
    AffineQuotients(const AffineValues<R>& v, bool floats) : v_(v), shift_(0) {
        safe_ = true;
        if (!floats) {
            for (int j = 0; j < 3; ++j)
                safe_ = safe_ && expansion_safe(v.o[j]) && expansion_safe(v.c[j]) && expansion_safe(v.d[j]);
            for (int i = 0; i < R; ++i) {
                safe_ = safe_ && expansion_safe(v.h[i]);
                for (int j = 0; j < 3; ++j) safe_ = safe_ && expansion_safe(v.a[i][j]);
            }
        }
    }
    // The input rescaled as above with every scaled value in [2^-100, 2^100] or 0, where
    // such sp, sa, sd exist: each group's shifts form a range (ExponentSpan), and the
    // h_i's range bounds sp + sa; none where a range is empty.
    static std::optional<AffineQuotients> rescaled(const AffineValues<R>& v) {
        ExponentSpan positions, rows, halves, directions;
        for (int j = 0; j < 3; ++j) {
            positions.add(v.o[j]);
            positions.add(v.c[j]);
            directions.add(v.d[j]);
            for (int i = 0; i < R; ++i) rows.add(v.a[i][j]);
        }
        for (int i = 0; i < R; ++i) halves.add(v.h[i]);
        const std::optional<int> sd = directions.safe_shift();
        const ShiftRange p = positions.shift_range(), a = rows.shift_range(), h = halves.shift_range();
        // sp + sa in [p.lo + a.lo, p.hi + a.hi] ∩ [h.lo, h.hi]; then sp and sa within their own
        const int lo = std::max(p.lo + a.lo, h.lo), hi = std::min(p.hi + a.hi, h.hi);
        if (!sd || p.lo > p.hi || a.lo > a.hi || lo > hi) return std::nullopt;
        const int sum = std::clamp(0, lo, hi), sp = std::max(p.lo, sum - a.hi), sa = sum - sp;
        AffineValues<R> w = v;
        for (int j = 0; j < 3; ++j) {
            w.o[j] = times_pow2(v.o[j], sp);
            w.c[j] = times_pow2(v.c[j], sp);
            w.d[j] = times_pow2(v.d[j], *sd);
            for (int i = 0; i < R; ++i) w.a[i][j] = times_pow2(v.a[i][j], sa);
        }
        for (int i = 0; i < R; ++i) w.h[i] = times_pow2(v.h[i], sum);
        std::optional<AffineQuotients> q(std::in_place, w, false);
        q->shift_ = sp - *sd;
        q->safe_ = true;
        return q;
    }
    int shift() const { return shift_; }
    bool safe() const { return safe_; }
    template <class E> E num(int i, int side) const { return E(side ? v_.h[i] : -v_.h[i]) - oprime<E>(i); }
    template <class E> E den(int i) const {
        E s(0.0);
        for (int j = 0; j < 3; ++j) s = s + E(v_.a[i][j]) * E(v_.d[j]);
        return s;
    }
    template <class E> E oprime(int i) const {  // a_i·(o - c)
        E s(0.0);
        for (int j = 0; j < 3; ++j) s = s + E(v_.a[i][j]) * (E(v_.o[j]) - E(v_.c[j]));
        return s;
    }
    // The exact signs of num(i, side) and den(i) from their sums (quick_compare's), or
    // none where a checked product is not exact.
    std::optional<int> num_sign(int i, int side) const {
        const GrowingSum<16> s = num_sum(i, side);
        if (s.full) return std::nullopt;
        return s.sign();
    }
    std::optional<int> den_sign(int i) const {
        const GrowingSum<8> s = den_sum(i);
        if (s.full) return std::nullopt;
        return s.sign();
    }
    // exact_compare's sign without an expansion type. num = ±h_i - Σ_j a_ij o_j +
    // Σ_j a_ij c_j and den = Σ_j a_ij d_j as sums of error-free products (13 and 6
    // doubles), compressed; then sign(n1 d2 - n2 d1)·sign(d1 d2) from their components'
    // products, or sign(n - c·den)·sign(den) for a constant c.
    // For safe() input (every value 0 or a multiple of 2^-152 below 2^100; every float a
    // multiple of 2^-149 below 2^128) every product of two inputs is exact by two_prod
    // (its error term a multiple of 2^-304), and so is every product of the sums'
    // components (multiples of 2^-608, far above the 2^-916 two_prod needs, and below
    // 2^410). For other input every product is checked instead (exact_product,
    // exact_products; h_i below 2^1000), and where the sums' products are not
    // exact as they stand, the numerators are scaled alike by 2^kn and the denominators by
    // 2^kd (exactly, GrowingSum::scale) to bring their largest components near 1, which
    // multiplies n1 d2 - n2 d1 by 2^(kn + kd): the directions' and the positions'
    // binades then need not fit one range together. The products by c are checked in
    // both cases. None where a check or a capacity fails.
    std::optional<int> quick_compare(const SlabRef& a, const SlabRef& b) const {
        if (a.axis < 0) {
            const std::optional<int> s = quick_compare(b, a);
            if (!s) return std::nullopt;
            return -*s;
        }
        GrowingSum<16> n1 = num_sum(a.axis, a.side);
        GrowingSum<8> d1 = den_sum(a.axis);
        if (n1.full || d1.full) return std::nullopt;
        if (b.axis >= 0) {
            GrowingSum<16> n2 = num_sum(b.axis, b.side);
            GrowingSum<8> d2 = den_sum(b.axis);
            if (n2.full || d2.full) return std::nullopt;
            if (!safe_ && !(exact_products(n1, d2) && exact_products(n2, d1))) {
                const int kn = -std::max(n1.top(), n2.top()), kd = -std::max(d1.top(), d2.top());
                if (!(n1.scale(kn) && n2.scale(kn) && d1.scale(kd) && d2.scale(kd) && exact_products(n1, d2) &&
                      exact_products(n2, d1)))
                    return std::nullopt;
            }
            const std::optional<int> s = sign_cross_difference<32>(n1, d2, n2, d1);
            if (!s) return std::nullopt;
            return *s * d1.sign() * d2.sign();
        }
        GrowingSum<32> s;
        for (int k = 0; k < n1.n; ++k) s.add(n1.e[k]);
        for (int k = 0; k < d1.n; ++k) {
            if (!exact_product(b.c, d1.e[k])) return std::nullopt;
            s.add_product(-b.c, d1.e[k]);
        }
        if (s.full) return std::nullopt;
        return s.sign() * d1.sign();
    }

    // num(i, side)/den(i) faithfully rounded to T without an expansion type, as
    // faithful_quotient finds it (exact_impl::quotient): from a candidate, the sums'
    // estimates divided (rounded to T), stepped one T at a time towards the quotient
    // until sign(num - g·den) changes (at most four steps), each sign from the sums and
    // the products g·den_k (checked: exact_product). The answer is the candidate's
    // neighbour on its own side of the quotient, or the quotient itself. None where a
    // sum or a product is not exact, the candidate is not a normal T, or four steps do
    // not suffice.
    template <class T> std::optional<T> quick_faithful(int i, int side) const {
        const GrowingSum<16> n = num_sum(i, side);
        const GrowingSum<8> d = den_sum(i);
        if (n.full || d.full || d.n == 0) return std::nullopt;
        if (n.n == 0) return T(0);
        const int sd = d.sign();
        // sign(quotient - g), or 2 where a product is not exact
        const auto above = [&](T g) {
            GrowingSum<48> s;
            for (int k = 0; k < n.n; ++k) s.add(n.e[k]);
            for (int k = 0; k < d.n; ++k) {
                if (!exact_product(double(g), d.e[k])) return 2;
                s.add_product(-double(g), d.e[k]);
            }
            return s.full ? 2 : s.sign() * sd;
        };
        T q = T(n.estimate() / d.estimate());
        if (!(std::abs(q) >= std::numeric_limits<T>::min() && std::abs(q) <= std::numeric_limits<T>::max()))
            return std::nullopt;
        const int s = above(q);
        if (s == 2) return std::nullopt;
        if (s == 0) return q;
        for (int step = 0; step < 4; ++step) {
            const T next = s > 0 ? step_up(q) : step_down(q);
            if (std::isinf(next)) return std::nullopt;
            const int s1 = above(next);
            if (s1 == 2) return std::nullopt;
            if (s1 != s) return s1 == 0 ? next : q;  // next == quotient, or quotient strictly between q and next
            q = next;
        }
        return std::nullopt;
    }

private:
    // num(i, side) and den(i) as quick_compare takes them (its derivation): exact, with
    // room for every term; `full` where a checked product is not exact.
    GrowingSum<16> num_sum(int i, int side) const {
        GrowingSum<16> s;
        if (!safe_ && std::abs(v_.h[i]) >= 0x1p1000) {
            s.full = true;
            return s;
        }
        s.add(side ? v_.h[i] : -v_.h[i]);
        for (int j = 0; j < 3; ++j) {
            if (safe_) {
                s.add_product(-v_.a[i][j], v_.o[j]);
                s.add_product(v_.a[i][j], v_.c[j]);
            } else {
                s.add_product_checked(-v_.a[i][j], v_.o[j]);
                s.add_product_checked(v_.a[i][j], v_.c[j]);
            }
        }
        s.compress();
        return s;
    }
    GrowingSum<8> den_sum(int i) const {
        GrowingSum<8> s;
        for (int j = 0; j < 3; ++j) {
            if (safe_)
                s.add_product(v_.a[i][j], v_.d[j]);
            else
                s.add_product_checked(v_.a[i][j], v_.d[j]);
        }
        s.compress();
        return s;
    }
    AffineValues<R> v_;
    int shift_;
    bool safe_;
};

// The exact side of a frame whose slab values are affine quotients (ObbFrame, ray_obb.hpp;
// PlaneCrossing, ray_plane.hpp), as a source of exact quotients: the quotients on the
// given input, and the rescaled ones where those are not safe for expansions
// (exact_compare and exact_faithful use scaled() then). A query asks the exact side
// rarely and then several times, so each is made on first use, once, from the frame's
// Frame::affine_values() (CRTP: the frame derives from AffineSource<R, Frame>).
template <int R, class Frame> class AffineSource {
public:
    template <class E> E num(int i, int side) const { return given().template num<E>(i, side); }
    template <class E> E den(int i) const { return given().template den<E>(i); }
    bool safe() const { return given().safe(); }
    std::optional<int> quick_compare(const SlabRef& a, const SlabRef& b) const { return given().quick_compare(a, b); }
    template <class U> std::optional<U> quick_faithful(int i, int side) const {
        return given().template quick_faithful<U>(i, side);
    }
    const std::optional<AffineQuotients<R>>& scaled() const {
        if (!scaled_made_) {
            scaled_made_ = true;
            scaled_ = AffineQuotients<R>::rescaled(values());
        }
        return scaled_;
    }
    // The exact signs of den(i) and num(i, side) without the interval filter: from the
    // fixed-size sums on the given input, else on the rescaled one (signs unchanged by
    // the scaling), else in an exact type.
    int exact_den_sign(int i) const {
        if (const std::optional<int> s = from_sums([&](const AffineQuotients<R>& q) { return q.den_sign(i); }))
            return *s;
        return exact_sign(safe(), [&](auto tag) { return den<typename decltype(tag)::type>(i); });
    }
    int exact_num_sign(int i, int side) const {
        if (const std::optional<int> s = from_sums([&](const AffineQuotients<R>& q) { return q.num_sign(i, side); }))
            return *s;
        return exact_sign(safe(), [&](auto tag) { return num<typename decltype(tag)::type>(i, side); });
    }

protected:
    explicit AffineSource(bool floats) : floats_(floats) {}

private:
    // What decide(q) answers (an optional) on the given quotients, else on the rescaled
    // ones when the given are not safe; nullopt where neither decides.
    template <class Decide> auto from_sums(Decide&& decide) const -> decltype(decide(std::declval<const AffineQuotients<R>&>())) {
        if (auto x = decide(given())) return x;
        if (!safe() && scaled()) return decide(*scaled());
        return std::nullopt;
    }
    const AffineQuotients<R>& given() const {
        if (!given_) given_.emplace(values(), floats_);
        return *given_;
    }
    AffineValues<R> values() const { return static_cast<const Frame&>(*this).affine_values(); }
    mutable std::optional<AffineQuotients<R>> given_, scaled_;
    mutable bool scaled_made_ = false;
    bool floats_;
};

}  // namespace rayproof::detail
