// rayproof/oracle/oracle.hpp — the exact ground truth (target rayproof::oracle).
//
// exact(ray, shape) answers with exact rational arithmetic (CGAL::Gmpq over the C GMP
// library) what the contract defines as the exact answer: the verdict, t_enter and
// t_exit, and the entry face with the lowest-axis tie rule. Every float or double input
// is converted exactly; NaN and inf are screened first (the validity rules of the
// contract are re-implemented here, independently of the kernel).
//
// The exact t values are rationals (Aabb, Obb, Plane, ConvexPolyhedron, and t_min/t_max
// when they clip), ±inf (a ray lying in a plane or in a polyhedron on an unbounded
// range), or roots of a quadratic with rational coefficients (Sphere, irrational in
// general). They are never converted to a double: an ExactValue answers where a given
// float lies relative to it (below, equal, above) and which floats enclose it (its
// faithful roundings).
//
// judge(hit, exact) classifies a floating-point answer against the exact one.
//
// This header does not include CGAL or GMP: fuzz targets, benchmarks and the audit tool
// include it cheaply; the CGAL code lives in the library's sources.
#pragma once

#include <rayproof/types.hpp>

#include <cstdint>
#include <iosfwd>
#include <memory>
#include <string>

namespace rayproof::oracle {

// Where a floating-point number lies relative to an exact real value. `unordered`: the
// number is NaN, or there is no value (the t of a miss).
enum class Order { below, equal, above, unordered };

// The faithful roundings of an exact value v in T: lo <= v <= hi, adjacent in T (lo == hi
// when v is representable). Beyond the largest finite value the upper neighbour is +inf
// (and symmetrically); between 0 and the smallest denormal, the lower one is 0.
template <class T> struct Bracket {
    T lo, hi;
    bool representable() const { return lo == hi; }
};

// An exact real number: ±inf, a rational, or a root p + σ·sqrt(r) of a quadratic with
// rational coefficients (r > 0 not the square of a rational, so the value is irrational).
class ExactValue {
public:
    enum class Kind { none, minus_infinity, plus_infinity, rational, quadratic_root };
    struct Impl;  // defined in the library (holds GMP numbers)

    ExactValue() = default;  // Kind::none: no value
    explicit ExactValue(std::shared_ptr<const Impl> impl) : impl_(std::move(impl)) {}

    Kind kind() const;
    bool has_value() const { return impl_ != nullptr; }

    // Where f lies relative to this value (exact; -0 and +0 are both 0).
    Order compare(float f) const;
    Order compare(double f) const;
    // The two floats that enclose the value (see Bracket).
    template <class T> Bracket<T> faithful() const;
    // The double nearest to the value (±inf, ±0 outside the double range): for display.
    double approx() const;
    // The exact value as text: "p/q", "p/q + sqrt(r/s)", "-inf"; numbers longer than
    // max_digits are elided in the middle.
    std::string str(std::size_t max_digits = 60) const;
    // Exact equality of two values.
    friend bool operator==(const ExactValue& a, const ExactValue& b);
    // sign(a - b), exact: -1, 0 or 1 (-inf below every finite value, two equal infinities
    // 0). Precondition: both have a value.
    friend int compare(const ExactValue& a, const ExactValue& b);

    const Impl* impl() const { return impl_.get(); }

private:
    std::shared_ptr<const Impl> impl_;
};

// The exact answer for one query.
template <class T> struct Exact {
    Verdict verdict = Verdict::miss;
    ExactValue t_enter, t_exit;  // Kind::none unless verdict == hit
    int face = -1;               // boxes: 2·axis + side of the entry plane, -1 when t_min is in the box;
                                 // polyhedra: the index of the entry plane (lowest on ties), -1 likewise

    Order enter_vs(T f) const { return t_enter.compare(f); }
    Order exit_vs(T f) const { return t_exit.compare(f); }
    Bracket<T> enter_bracket() const { return t_enter.template faithful<T>(); }
    Bracket<T> exit_bracket() const { return t_exit.template faithful<T>(); }
};

// The contract's validity rules, decided exactly (the Obb axes by the exact determinant).
template <class T> bool valid(const Ray<T>& r);
template <class T> bool valid(const Aabb<T>& b);
template <class T> bool valid(const Obb<T>& b);
template <class T> bool valid(const Plane<T>& p);
template <class T> bool valid(const Sphere<T>& s);
template <class T> bool valid(const ConvexPolyhedron<T>& p);  // every plane valid (no planes: valid)

// The exact answers (T = float or double; explicitly instantiated in the library).
template <class T> Exact<T> exact(const Ray<T>& ray, const Aabb<T>& box);
template <class T> Exact<T> exact(const Ray<T>& ray, const Obb<T>& box);
template <class T> Exact<T> exact(const Ray<T>& ray, const Plane<T>& plane);
template <class T> Exact<T> exact(const Ray<T>& ray, const Sphere<T>& sphere);
template <class T> Exact<T> exact(const Ray<T>& ray, const ConvexPolyhedron<T>& poly);

// How a floating-point answer relates to the exact one.
enum class Outcome {
    agree,             // same verdict (and, for two hits, the same face)
    false_hit,         // exact miss, answered hit
    false_miss,        // exact hit, answered miss
    invalid_mismatch,  // exactly one of the two says invalid
    face_mismatch,     // both hit, different entry faces
};

struct Judgement {
    Outcome outcome = Outcome::agree;
    // When both hit: how many representable values of T lie between the answered t and
    // the nearest faithful rounding of the exact t (0 when the answer is a faithful
    // rounding; UINT64_MAX for NaN). 0 otherwise.
    std::uint64_t enter_ulps = 0, exit_ulps = 0;
    // When both hit: [hit.t_enter, hit.t_exit] contains the exact interval. true otherwise.
    bool encloses = true;

    bool verdict_wrong() const { return outcome == Outcome::false_hit || outcome == Outcome::false_miss ||
                                        outcome == Outcome::invalid_mismatch; }
    // The answer is what the certified mode promises: verdict and face exact, each t a
    // faithful rounding.
    bool exact_match() const { return outcome == Outcome::agree && enter_ulps == 0 && exit_ulps == 0; }
    std::uint64_t max_ulps() const { return enter_ulps > exit_ulps ? enter_ulps : exit_ulps; }
};

// Classifies `hit` against `exact`. With compare_face == false two hits agree whatever
// their faces (the conservative mode may differ on ties).
template <class T> Judgement judge(const Hit<T>& hit, const Exact<T>& exact, bool compare_face = true);

// The distance in representable steps from f to the nearest faithful rounding of v: 0
// when f is one of them; UINT64_MAX when f is NaN or v has no value.
template <class T> std::uint64_t ulps_from(T f, const ExactValue& v);
// The number of representable steps from a to b (|a - b| in ulps; -0 and +0 are one
// point; inf counts as the step after the largest finite value). UINT64_MAX for NaN.
template <class T> std::uint64_t ulp_distance(T a, T b);

const char* to_string(Outcome o);
const char* to_string(Order o);
std::ostream& operator<<(std::ostream& os, Outcome o);
std::ostream& operator<<(std::ostream& os, Order o);
std::ostream& operator<<(std::ostream& os, const ExactValue& v);
template <class T> std::ostream& operator<<(std::ostream& os, const Exact<T>& e);
std::ostream& operator<<(std::ostream& os, const Judgement& j);

}  // namespace rayproof::oracle
