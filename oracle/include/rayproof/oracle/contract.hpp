// rayproof/oracle/contract.hpp — what each mode promises, judged against the exact oracle:
// the one contract checker of the audit tool (tools/audit), the fuzz targets (fuzz/) and
// the property suites (tests/props), and the tally of judgements that the audit and the
// trade report's accuracy half (bench/trade_accuracy.cpp) print.
//
// The promises (docs/semantics.md, "What each mode promises"):
//   every mode     invalid exactly when the contract says invalid
//   fast           nothing more: its error rate is measured, not promised
//   conservative   never a false miss; a hit's [t_enter, t_exit] encloses the exact one
//   certified      the exact verdict and face, each t a faithful rounding of the exact t
// and the form of an answer, which needs no oracle:
//   every mode     the verdict is miss, hit or invalid; a hit carries no NaN t
//   conservative,  a hit has t_min <= t_enter <= t_exit <= t_max; its face is in [-1, 5]
//   certified      for boxes, in [-1, n - 1] for a polyhedron of n planes, -1 for planes
//                  and spheres
//
// check_contract() reports every breach of an answer at once; each caller decides what it
// reports: the audit counts broken promises, the fuzz targets abort on the first breach,
// the property suites fail with the case.
#pragma once

#include <rayproof/oracle/oracle.hpp>
#include <rayproof/types.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <type_traits>

namespace rayproof::oracle {

enum class ModeId { fast, conservative, certified };
constexpr ModeId mode_id(fast_t) { return ModeId::fast; }
constexpr ModeId mode_id(conservative_t) { return ModeId::conservative; }
constexpr ModeId mode_id(certified_t) { return ModeId::certified; }
constexpr const char* to_string(ModeId m) {
    return m == ModeId::fast ? "fast" : m == ModeId::conservative ? "conservative" : "certified";
}

// One way an answer breaks its mode's contract. The order is the order of first():
// the form of the answer, then validity, then the mode's own promise, then the interval
// and the face.
enum class Breach : unsigned {
    verdict_out_of_range = 1u << 0,    // every mode: not miss, hit or invalid
    nan_in_hit = 1u << 1,              // every mode: a hit with a NaN t_enter or t_exit
    invalid_not_reported = 1u << 2,    // every mode: the input is invalid, the answer is not
    valid_reported_invalid = 1u << 3,  // every mode: the input is valid, the answer is invalid
    not_exact = 1u << 4,               // certified: verdict or face differs, or a t is not faithful
    false_miss = 1u << 5,              // conservative: the exact answer hits, the answer misses
    not_enclosing = 1u << 6,           // conservative: [t_enter, t_exit] misses part of the exact one
    interval_out_of_range = 1u << 7,   // conservative, certified: not t_min <= t_enter <= t_exit <= t_max
    face_out_of_range = 1u << 8,       // conservative, certified, boxes: face outside [-1, 5]; polyhedra: [-1, n - 1]
    face_not_none = 1u << 9,           // conservative, certified, planes and spheres: face != -1
};
inline constexpr unsigned kBreachCount = 10;

// The breaches of what the mode promises against the exact answer (the table of
// docs/semantics.md); the others are breaches of the answer's form.
inline constexpr unsigned kPromiseBreaches =
    unsigned(Breach::invalid_not_reported) | unsigned(Breach::valid_reported_invalid) | unsigned(Breach::not_exact) |
    unsigned(Breach::false_miss) | unsigned(Breach::not_enclosing);

// What a breach is called in a report (the fuzz targets' triage filters match these).
constexpr const char* describe(Breach b) {
    switch (b) {
        case Breach::verdict_out_of_range: return "verdict out of range";
        case Breach::nan_in_hit: return "NaN in a hit";
        case Breach::invalid_not_reported: return "invalid input not reported";
        case Breach::valid_reported_invalid: return "valid input reported invalid";
        case Breach::not_exact: return "certified answer not exact";
        case Breach::false_miss: return "conservative missed an exact hit";
        case Breach::not_enclosing: return "conservative interval does not enclose the exact one";
        case Breach::interval_out_of_range: return "hit interval not ordered within [t_min, t_max]";
        case Breach::face_out_of_range: return "face out of range";
        case Breach::face_not_none: return "face must be -1 for this shape";
    }
    return "?";
}

// The verdict of one answer against the contract of its mode.
struct ContractCheck {
    ModeId mode = ModeId::fast;
    // The answer judged against the exact one, faces compared whatever the mode.
    Judgement judgement;
    unsigned breaches = 0;  // Breach bits

    bool ok() const { return breaches == 0; }
    bool has(Breach b) const { return (breaches & unsigned(b)) != 0; }
    // The answer breaks what its mode promises against the exact answer.
    bool promise_broken() const { return (breaches & kPromiseBreaches) != 0; }
    // The answer's verdict and the exact one disagree about validity.
    bool invalid_mismatch() const { return judgement.outcome == Outcome::invalid_mismatch; }
    // The judgement by the mode's own rule: faces compared only in certified mode (the
    // conservative mode may differ on ties, the fast mode promises nothing).
    Judgement mode_judgement() const {
        Judgement j = judgement;
        if (mode != ModeId::certified && j.outcome == Outcome::face_mismatch) j.outcome = Outcome::agree;
        return j;
    }
    // The first breach in the order of the Breach enumeration (ok() must be false).
    Breach first() const {
        for (unsigned k = 0; k < kBreachCount; ++k)
            if (breaches & (1u << k)) return Breach(1u << k);
        return Breach::verdict_out_of_range;
    }
};

namespace contract_detail {
template <class T, class Shape> constexpr bool is_box = std::is_same_v<Shape, Aabb<T>> || std::is_same_v<Shape, Obb<T>>;
}

// Checks `hit`, the answer of mode `mode` for (ray, shape), against `exact`, the oracle's
// answer for the same input. A hit may name the faces -1 to `face_last` (boxes 5, a
// polyhedron of n planes n - 1); `faces` false: the shape names none, the face must be -1
// (planes, spheres).
template <class T>
ContractCheck check_contract(ModeId mode, bool faces, int face_last, const Ray<T>& ray, const Hit<T>& hit,
                             const Exact<T>& exact) {
    ContractCheck c;
    c.mode = mode;
    c.judgement = judge(hit, exact, /*compare_face=*/true);
    const auto flag = [&](Breach b) { c.breaches |= unsigned(b); };
    const Judgement& j = c.judgement;

    if (hit.verdict != Verdict::miss && hit.verdict != Verdict::hit && hit.verdict != Verdict::invalid)
        flag(Breach::verdict_out_of_range);
    if (hit.verdict == Verdict::hit && (std::isnan(hit.t_enter) || std::isnan(hit.t_exit))) flag(Breach::nan_in_hit);
    if (j.outcome == Outcome::invalid_mismatch)
        flag(exact.verdict == Verdict::invalid ? Breach::invalid_not_reported : Breach::valid_reported_invalid);
    if (mode == ModeId::fast) return c;

    if (mode == ModeId::certified) {
        if (!j.exact_match()) flag(Breach::not_exact);
    } else {
        if (j.outcome == Outcome::false_miss) flag(Breach::false_miss);
        if (!j.encloses) flag(Breach::not_enclosing);
    }
    if (hit.verdict == Verdict::hit) {
        if (!(ray.t_min <= hit.t_enter && hit.t_enter <= hit.t_exit && hit.t_exit <= ray.t_max))
            flag(Breach::interval_out_of_range);
        if (faces) {
            if (hit.face < -1 || hit.face > face_last) flag(Breach::face_out_of_range);
        } else if (hit.face != -1) {
            flag(Breach::face_not_none);
        }
    }
    return c;
}

// The same for a box (`box`: faces -1 to 5) or a plane or sphere (face -1).
template <class T>
ContractCheck check_contract(ModeId mode, bool box, const Ray<T>& ray, const Hit<T>& hit, const Exact<T>& exact) {
    return check_contract(mode, box, 5, ray, hit, exact);
}

template <class T, class Shape, class Mode>
ContractCheck check_contract(const Ray<T>& ray, const Shape&, const Hit<T>& hit, const Exact<T>& exact, Mode mode) {
    return check_contract(mode_id(mode), contract_detail::is_box<T, Shape>, ray, hit, exact);
}

// A polyhedron names its planes: faces -1 to planes.size() - 1 (no planes: -1 only).
template <class T, class Mode>
ContractCheck check_contract(const Ray<T>& ray, const ConvexPolyhedron<T>& poly, const Hit<T>& hit,
                             const Exact<T>& exact, Mode mode) {
    return check_contract(mode_id(mode), true, int(poly.planes.size()) - 1, ray, hit, exact);
}

// Counts of judgements: the rows of the audit and of the trade report's accuracy half.
struct Tally {
    std::uint64_t cases = 0;       // answers counted
    std::uint64_t exact_hits = 0;  // of those, the exact verdict is hit
    std::uint64_t refused = 0;     // valid inputs a method declines to answer (not judged)
    std::uint64_t false_hit = 0, false_miss = 0, invalid_mismatch = 0, face_mismatch = 0;
    std::uint64_t t_judged = 0;       // answers whose t was judged (both hit)
    std::uint64_t t_off = 0;          // of those, a t not a faithful rounding of the exact one
    std::uint64_t max_ulps = 0;       // the largest distance from a faithful rounding (UINT64_MAX: NaN)
    std::uint64_t not_enclosing = 0;  // of those, [t_enter, t_exit] not containing the exact interval
    std::uint64_t incoherent = 0;     // hits with t_enter > t_exit or a NaN t
    std::uint64_t violations = 0;     // answers that break their mode's contract

    // Wrong verdicts: false hits + false misses + invalid mismatches.
    std::uint64_t wrong() const { return false_hit + false_miss + invalid_mismatch; }

    // The verdict (and face) of one judged answer.
    void count_outcome(const Judgement& j) {
        switch (j.outcome) {
            case Outcome::false_hit: ++false_hit; break;
            case Outcome::false_miss: ++false_miss; break;
            case Outcome::invalid_mismatch: ++invalid_mismatch; break;
            case Outcome::face_mismatch: ++face_mismatch; break;
            case Outcome::agree: break;
        }
    }
    // One judged t: its distance in ulps from the nearest faithful rounding.
    void count_t(std::uint64_t ulps) {
        ++t_judged;
        t_off += ulps != 0;
        max_ulps = std::max(max_ulps, ulps);
    }
    // Both t of an answer that hits where the exact answer hits: their larger distance
    // and whether the interval encloses the exact one.
    void count_interval(const Judgement& j) {
        count_t(j.max_ulps());
        not_enclosing += !j.encloses;
    }
    template <class T> void count_coherence(const Hit<T>& h) {
        incoherent += h.verdict == Verdict::hit && !(h.t_enter <= h.t_exit);  // NaN included
    }
};

}  // namespace rayproof::oracle
