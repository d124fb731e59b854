// rayproof/generators/scene_check.hpp — what a closest-hit structure must answer for one
// ray and one scene, judged by brute force (closest.hpp) and by the exact oracle: shared
// by the BVH properties (tests/props/bvh_props.cpp) and the BVH fuzz target
// (fuzz/bvh_fuzz.cpp). Needs rayproof::oracle (include it only from targets that link it).
//
// Each check returns the first violation as readable text (nothing when all hold):
//
// check_brute_force (the reference itself, against the oracle):
//   certified     closest_hit hits iff the oracle hits some primitive; its index is one the
//                 oracle hits, its Hit is that primitive's own certified Hit bit for bit,
//                 exact per the oracle (verdict, face, faithful t), and its exact t_enter is
//                 below every other hit's exact t_enter or equal to it with a lower index
//                 (oracle::compare: sphere roots compared exactly); any_hit's verdict is
//                 closest_hit's, its index the lowest the oracle hits
//   conservative  hits whenever the oracle does; the primitive it names: its interval
//                 encloses that primitive's exact one when exactly hit, and its t_enter is
//                 at most the exact t_enter of the certified closest
//   fast          invalid exactly when the ray is invalid
//   every mode    invalid (index -1) exactly when the ray is invalid
//
// check_structure (a Bvh<T, W> built over the same primitives):
//   certified     closest_hit equals brute force: verdict, index and Hit bit for bit;
//                 any_hit's verdict equals closest_hit's and its index is a primitive the
//                 certified brute force hits
//   conservative  closest_hit and any_hit hit whenever certified brute force does; the
//                 index named is hit by that primitive's own conservative answer, and
//                 closest_hit's interval encloses its exact one when exactly hit, with
//                 t_enter at most the exact t_enter of the certified closest
//   fast          verdict validity only (plain floating point promises nothing)
//   for_each_candidate, certified and conservative: with t_limit = t_max, with a t_limit
//                 drawn from the scene (an entry or exit of a hit primitive, or between
//                 them), and with f lowering t_limit to each candidate's certified t_enter
//                 (the tracer's use): every primitive whose certified answer on
//                 [t_min, final t_limit] is a hit is visited; every index visited is in
//                 range (fast: only that)
//   stats         size() and stats().primitives equal the scene's count
#pragma once

#include <rayproof/bvh.hpp>
#include <rayproof/closest.hpp>
#include <rayproof/io.hpp>
#include <rayproof/oracle/oracle.hpp>

#include <cstdint>
#include <cstring>
#include <optional>
#include <span>
#include <sstream>
#include <string>
#include <variant>
#include <vector>

namespace rayproof::gen {

namespace check_detail {

template <class T> bool same_bits(T a, T b) { return std::memcmp(&a, &b, sizeof(T)) == 0; }
template <class T> bool identical(const Hit<T>& a, const Hit<T>& b) {
    return a.verdict == b.verdict && a.face == b.face && same_bits(a.t_enter, b.t_enter) && same_bits(a.t_exit, b.t_exit);
}
template <class T> bool identical(const ClosestHit<T>& a, const ClosestHit<T>& b) {
    return a.verdict == b.verdict && a.index == b.index && identical(a.hit, b.hit);
}
template <class T> std::string text(const ClosestHit<T>& c) {
    std::ostringstream os;
    os << to_string(c.verdict) << " index " << c.index << ' ' << c.hit;
    return os.str();
}
template <class T, class Mode> Hit<T> own(const Ray<T>& ray, const Primitive<T>& p, Mode mode) {
    return std::visit([&](const auto& s) { return intersect(ray, s, mode); }, p);
}
template <class T> oracle::Exact<T> exact_of(const Ray<T>& ray, const Primitive<T>& p) {
    return std::visit([&](const auto& s) { return oracle::exact(ray, s); }, p);
}
// f <= v exactly (f lies below or on the exact value v).
template <class T> bool at_most(T f, const oracle::ExactValue& v) {
    const oracle::Order o = v.compare(f);
    return o == oracle::Order::below || o == oracle::Order::equal;
}
template <class T> bool encloses(const Hit<T>& h, const oracle::Exact<T>& e) {
    const oracle::Order x = e.t_exit.compare(h.t_exit);
    return at_most(h.t_enter, e.t_enter) && (x == oracle::Order::above || x == oracle::Order::equal);
}

}  // namespace check_detail

// The exact answer of every primitive (the oracle), computed once per scene.
template <class T> std::vector<oracle::Exact<T>> exact_answers(const Ray<T>& ray, std::span<const Primitive<T>> prims) {
    std::vector<oracle::Exact<T>> ex;
    ex.reserve(prims.size());
    for (const Primitive<T>& p : prims) ex.push_back(check_detail::exact_of(ray, p));
    return ex;
}

// The certified brute-force closest primitive's index (-1 for none): the reference.
template <class T>
std::optional<std::string> check_brute_force(const Ray<T>& ray, std::span<const Primitive<T>> prims,
                                             const std::vector<oracle::Exact<T>>& ex) {
    using namespace check_detail;
    std::ostringstream os;
    const bool ray_ok = oracle::valid(ray);
    const ClosestHit<T> cb = closest_hit(ray, prims, certified), ab = any_hit(ray, prims, certified);
    const ClosestHit<T> cc = closest_hit(ray, prims, conservative), cf = closest_hit(ray, prims, fast);
    for (const auto* c : {&cb, &ab, &cc, &cf}) {
        if ((c->verdict == Verdict::invalid) != !ray_ok || (!ray_ok && c->index != -1)) {
            os << "brute force: " << text(*c) << " but the ray is " << (ray_ok ? "valid" : "invalid");
            return os.str();
        }
    }
    if (!ray_ok) return std::nullopt;
    std::int64_t lowest = -1;
    for (std::size_t j = 0; j < prims.size(); ++j)
        if (ex[j].verdict == Verdict::hit) {
            lowest = std::int64_t(j);
            break;
        }
    if ((cb.verdict == Verdict::hit) != (lowest >= 0)) {
        os << "brute-force certified closest_hit " << text(cb) << " but the oracle hits "
           << (lowest >= 0 ? "primitive " + std::to_string(lowest) : std::string("none"));
        return os.str();
    }
    if (ab.verdict != cb.verdict || ab.index != lowest) {
        os << "brute-force certified any_hit " << text(ab) << ", the lowest primitive the oracle hits is " << lowest;
        return os.str();
    }
    if (lowest < 0) return std::nullopt;  // conservative may hit a grazing miss; fast checked above
    const std::size_t i = std::size_t(cb.index);
    if (cb.index < 0 || i >= prims.size() || ex[i].verdict != Verdict::hit) {
        os << "brute-force certified closest_hit names primitive " << cb.index << ", which the oracle does not hit";
        return os.str();
    }
    const Hit<T> own_hit = own(ray, prims[i], certified);
    if (!identical(own_hit, cb.hit) || !oracle::judge(cb.hit, ex[i]).exact_match()) {
        os << "brute-force certified closest_hit " << text(cb) << ": the primitive's own certified answer is " << own_hit
           << ", exact " << ex[i];
        return os.str();
    }
    for (std::size_t j = 0; j < prims.size(); ++j) {
        if (j == i || ex[j].verdict != Verdict::hit) continue;
        const int s = compare(ex[i].t_enter, ex[j].t_enter);
        if (s > 0 || (s == 0 && j < i)) {
            os << "brute-force certified closest_hit chose primitive " << i << " (exact t_enter " << ex[i].t_enter
               << ") but primitive " << j << " is entered " << (s > 0 ? "earlier" : "at the same t with a lower index")
               << " (exact t_enter " << ex[j].t_enter << ")";
            return os.str();
        }
    }
    if (cc.verdict != Verdict::hit) {
        os << "brute-force conservative closest_hit " << text(cc) << " but the oracle hits primitive " << lowest;
        return os.str();
    }
    const std::size_t k = std::size_t(cc.index);
    if (cc.index < 0 || k >= prims.size() || (ex[k].verdict == Verdict::hit && !encloses(cc.hit, ex[k])) ||
        !at_most(cc.hit.t_enter, ex[i].t_enter)) {
        os << "brute-force conservative closest_hit " << text(cc) << " does not enclose its primitive's exact answer "
           << (k < prims.size() ? ex[k] : oracle::Exact<T>{}) << " or enters after the certified closest's exact t_enter "
           << ex[i].t_enter;
        return os.str();
    }
    return std::nullopt;
}

// The drawn limit of for_each_candidate: from `choice`, t_max, a certified entry or exit
// of a hit primitive, or the midpoint of such an interval.
template <class T> T drawn_limit(const Ray<T>& ray, std::span<const Primitive<T>> prims, std::uint64_t choice) {
    std::vector<Hit<T>> hits;
    for (const Primitive<T>& p : prims) {
        const Hit<T> h = check_detail::own(ray, p, certified);
        if (h.verdict == Verdict::hit) hits.push_back(h);
    }
    if (hits.empty() || choice % 5 == 0) return ray.t_max;
    const Hit<T>& h = hits[(choice >> 8) % hits.size()];
    switch ((choice >> 4) % 3) {
        case 0: return h.t_enter;
        case 1: return h.t_exit;
        default: {
            const T m = h.t_enter / 2 + h.t_exit / 2;
            return std::isfinite(m) && m >= ray.t_min ? m : h.t_enter;
        }
    }
}

template <class T, int W, class Mode>
std::optional<std::string> check_candidates(const Bvh<T, W>& bvh, const Ray<T>& ray, std::span<const Primitive<T>> prims,
                                            Mode mode, T limit, bool lowering) {
    using namespace check_detail;
    const PreparedRay<T> pr(ray);
    std::vector<char> seen(prims.size(), 0);
    std::size_t bad = prims.size();
    T t_limit = limit;
    bvh.for_each_candidate(pr, mode, t_limit, [&](std::size_t idx) {
        if (idx >= prims.size()) {
            bad = idx;
            return false;
        }
        seen[idx] = 1;
        if (lowering) {
            const Hit<T> h = own(Ray<T>{ray.origin, ray.direction, ray.t_min, t_limit}, prims[idx], certified);
            if (h.verdict == Verdict::hit && h.t_enter < t_limit) t_limit = h.t_enter;
        }
        return true;
    });
    std::ostringstream os;
    os << "for_each_candidate (" << mode_name(mode) << ", W=" << W << ", t_limit " << (lowering ? "lowered from " : "");
    ::rayproof::detail::put(os, limit);
    if (lowering) {
        os << " to ";
        ::rayproof::detail::put(os, t_limit);
    }
    os << "): ";
    if (bad != prims.size()) {
        os << "visited index " << bad << " of " << prims.size();
        return os.str();
    }
    if constexpr (std::is_same_v<Mode, fast_t>) return std::nullopt;
    if (!oracle::valid(ray) || std::isnan(t_limit) || t_limit < ray.t_min) return std::nullopt;
    const Ray<T> cut{ray.origin, ray.direction, ray.t_min, t_limit};
    for (std::size_t j = 0; j < prims.size(); ++j) {
        if (seen[j]) continue;
        const Hit<T> h = own(cut, prims[j], certified);
        if (h.verdict == Verdict::hit) {
            os << "primitive " << j << " is hit on [t_min, t_limit] (certified " << h << ") but was not visited";
            return os.str();
        }
    }
    return std::nullopt;
}

// A Bvh<T, W> over `prims` against brute force (see the header comment). `choice` picks
// the drawn t_limit.
template <class T, int W>
std::optional<std::string> check_structure(const Bvh<T, W>& bvh, const Ray<T>& ray, std::span<const Primitive<T>> prims,
                                           const std::vector<oracle::Exact<T>>& ex, std::uint64_t choice) {
    using namespace check_detail;
    std::ostringstream os;
    os << "Bvh<" << (std::is_same_v<T, float> ? "float" : "double") << ", " << W << ">: ";
    if (bvh.size() != prims.size() || bvh.stats().primitives != prims.size()) {
        os << "holds " << bvh.size() << " primitives (stats " << bvh.stats().primitives << "), the scene "
           << prims.size();
        return os.str();
    }
    const PreparedRay<T> pr(ray);
    const bool ray_ok = oracle::valid(ray);
    const ClosestHit<T> ref = closest_hit(pr, prims, certified);
    const ClosestHit<T> c = bvh.closest_hit(pr, certified);
    if (!identical(c, ref)) {
        os << "certified closest_hit " << text(c) << ", brute force " << text(ref);
        return os.str();
    }
    std::vector<char> hit_certified(prims.size(), 0);
    for (std::size_t j = 0; j < prims.size(); ++j) hit_certified[j] = own(ray, prims[j], certified).verdict == Verdict::hit;
    const auto in_set = [&](std::int64_t idx) { return idx >= 0 && std::size_t(idx) < prims.size() && hit_certified[std::size_t(idx)]; };
    const ClosestHit<T> a = bvh.any_hit(pr, certified);
    if (a.verdict != c.verdict || (a.verdict == Verdict::hit && !in_set(a.index))) {
        os << "certified any_hit " << text(a) << ", closest_hit " << text(c);
        return os.str();
    }
    // conservative
    const ClosestHit<T> cc = bvh.closest_hit(pr, conservative), ca = bvh.any_hit(pr, conservative);
    for (const auto* x : {&cc, &ca}) {
        const char* what = x == &cc ? "closest_hit" : "any_hit";
        if ((x->verdict == Verdict::invalid) != !ray_ok) {
            os << "conservative " << what << ' ' << text(*x) << " but the ray is " << (ray_ok ? "valid" : "invalid");
            return os.str();
        }
        if (ref.verdict == Verdict::hit && x->verdict != Verdict::hit) {
            os << "conservative " << what << ' ' << text(*x) << " misses; certified brute force " << text(ref);
            return os.str();
        }
        if (x->verdict == Verdict::hit &&
            (x->index < 0 || std::size_t(x->index) >= prims.size() ||
             own(ray, prims[std::size_t(x->index)], conservative).verdict != Verdict::hit)) {
            os << "conservative " << what << ' ' << text(*x) << " names a primitive its own conservative answer misses";
            return os.str();
        }
    }
    if (cc.verdict == Verdict::hit) {
        const std::size_t k = std::size_t(cc.index);
        const bool bad_enclosure = ex[k].verdict == Verdict::hit && !encloses(cc.hit, ex[k]);
        const bool late = ref.verdict == Verdict::hit && !at_most(cc.hit.t_enter, ex[std::size_t(ref.index)].t_enter);
        if (bad_enclosure || late) {
            os << "conservative closest_hit " << text(cc) << (bad_enclosure ? " does not enclose its exact " : " enters after the certified closest, exact ")
               << (bad_enclosure ? ex[k] : ex[std::size_t(ref.index)]);
            return os.str();
        }
    }
    // fast: validity only
    for (const ClosestHit<T>& x : {bvh.closest_hit(pr, fast), bvh.any_hit(pr, fast)}) {
        if ((x.verdict == Verdict::invalid) != !ray_ok) {
            os << "fast answer " << text(x) << " but the ray is " << (ray_ok ? "valid" : "invalid");
            return os.str();
        }
    }
    // for_each_candidate
    const T drawn = drawn_limit(ray, prims, choice);
    std::optional<std::string> f;
    const auto each = [&](auto mode) {
        if (!f) f = check_candidates(bvh, ray, prims, mode, ray.t_max, false);
        if (!f) f = check_candidates(bvh, ray, prims, mode, drawn, false);
        if (!f) f = check_candidates(bvh, ray, prims, mode, ray.t_max, true);
    };
    each(certified);
    each(conservative);
    each(fast);
    if (f) return os.str() + *f;
    return std::nullopt;
}

}  // namespace rayproof::gen
