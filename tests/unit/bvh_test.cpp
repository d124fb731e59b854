// Bvh (bvh.hpp) against the brute force over every primitive (closest.hpp), float and
// double, W = 4 and 8, every mode. Every scene and ray below goes through check_ray:
//   - certified: closest_hit equals brute-force closest_hit bit for bit (verdict, index,
//     Hit); any_hit has brute force's verdict, and its Hit is its primitive's own
//     certified Hit;
//   - conservative: closest_hit and any_hit hit whenever brute force certified hits;
//     closest_hit's t_enter is at most the certified closest t_enter, and when it
//     names the same primitive its interval encloses the certified one; every Hit
//     answered is its primitive's own conservative Hit;
//   - fast: invalid exactly for invalid rays; every Hit answered is its primitive's own
//     fast Hit;
//   - for_each_candidate, certified and conservative: each index at most once, and every
//     primitive the ray meets exactly (the certified query) on [t_min, L] among the
//     candidates, for L = t_max and for L lowered by the callback midway.
// The scenes: seeded random mixes of boxes, oriented boxes, spheres, bounded, unbounded
// and empty polyhedra, planes and invalid primitives (1 to 600 primitives), with rays
// aimed at primitives, random rays, rays parallel to axes and rays whose [t_min,
// t_max] cuts the scene; and adversarial ones: no primitive, one, only planes, only
// invalid ones, directions beyond the node filters' ranges, coincident boxes (ties to
// the lowest index), touching boxes with a ray
// along their shared face and through their shared edges, many spheres entered at the
// same t, a thousand equal centroids (median splits), invalid rays. Beside the answers:
// stats() (every primitive in exactly one leaf or beside the tree, the counts), node
// lane boxes equal to the exact union of what lies below them (so they enclose their
// primitives' boxes), empty slots empty, a leaf in lane 0 starting its node's range of
// positions, and PreparedRay::with_range equal to a ray prepared on that range; the
// fast node test equal to the fast packet's lanes. RAYPROOF_SEED=<n> replays a failure
// with its seed.
#include "same_hit.hpp"
#include "seeded.hpp"
#include <rayproof/bvh.hpp>
#include <rayproof/io.hpp>
#include <rayproof/rayproof.hpp>

#include <gtest/gtest.h>

#include <cfenv>
#include <cmath>
#include <cstdint>
#include <deque>
#include <functional>
#include <optional>
#include <limits>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#if defined(__x86_64__) || defined(_M_X64)
#include <xmmintrin.h>
#endif

using namespace rayproof;
using rayproof::testing::same_bits;
using rayproof::testing::same_hit;

namespace {

std::uint64_t base_seed() {
    static const std::uint64_t s = rayproof::testing::env_seed_or(20261203);
    return s;
}
std::mt19937_64 make_rng() { return rayproof::testing::rng_for_current_test(base_seed()); }

template <class T> constexpr T inf = std::numeric_limits<T>::infinity();
template <class T> Vec3<T> v3(double x, double y, double z) { return Vec3<T>(T(x), T(y), T(z)); }

template <class T> std::string describe(const Primitive<T>& p) {
    if (p.valueless_by_exception()) return "valueless";
    std::ostringstream os;
    std::visit([&](const auto& s) { os << s; }, p);
    return os.str();
}

// A scene: the primitives and the planes their polyhedra point into (kept alive here).
template <class T> struct Scene {
    std::deque<std::vector<Plane<T>>> planes;
    std::vector<Primitive<T>> prims;

    void cube(const Vec3<T>& c, T h) {  // a bounded polyhedron: the box c ± h as 6 planes
        std::vector<Plane<T>> p;
        for (int a = 0; a < 3; ++a) {
            Vec3<T> n = Vec3<T>::Zero();
            n[a] = 1;
            p.push_back(Plane<T>{n, c[a] + h});
            p.push_back(Plane<T>{Vec3<T>(-n), -(c[a] - h)});
        }
        planes.push_back(std::move(p));
        prims.push_back(ConvexPolyhedron<T>{std::span<const Plane<T>>(planes.back())});
    }
    void polyhedron(std::vector<Plane<T>> p) {
        planes.push_back(std::move(p));
        prims.push_back(ConvexPolyhedron<T>{std::span<const Plane<T>>(planes.back())});
    }
};

template <class T> Mat3<T> random_axes(std::mt19937_64& g) {
    // Not orthonormal: the contract takes the columns as stored (dependent ones, which
    // a random draw all but never gives, would be an invalid Obb: beside the tree).
    std::uniform_real_distribution<double> u(-1, 1);
    Mat3<T> m;
    for (int i = 0; i < 9; ++i) m.data()[i] = T(u(g));
    return m;
}

// Seeded random scene of n primitives in [-10, 10]^3, every kind.
template <class T> Scene<T> random_scene(std::mt19937_64& g, int n) {
    Scene<T> s;
    std::uniform_real_distribution<double> u(-10, 10), size(0.05, 1.5);
    std::uniform_int_distribution<int> kind(0, 99);
    for (int i = 0; i < n; ++i) {
        const Vec3<T> c = v3<T>(u(g), u(g), u(g));
        const T h = T(size(g));
        const int k = kind(g);
        if (k < 30) {
            s.prims.push_back(Sphere<T>{c, h});
        } else if (k < 55) {
            s.prims.push_back(Aabb<T>{c - Vec3<T>::Constant(h), c + Vec3<T>(h, T(size(g)), T(size(g) * 0.1))});
        } else if (k < 75) {
            s.prims.push_back(Obb<T>{c, random_axes<T>(g), v3<T>(size(g), size(g), size(g))});
        } else if (k < 85) {
            s.cube(c, h);
        } else if (k < 88) {  // unbounded: a wedge
            s.polyhedron({Plane<T>{v3<T>(1, 0, 0), c[0]}, Plane<T>{v3<T>(0, 1, 1), c[1]}});
        } else if (k < 90) {  // empty: x <= c - 1 and x >= c
            s.polyhedron({Plane<T>{v3<T>(1, 0, 0), c[0] - 1}, Plane<T>{v3<T>(-1, 0, 0), -c[0]}});
        } else if (k < 93) {
            s.prims.push_back(Plane<T>{v3<T>(u(g), u(g), u(g)), T(u(g))});
        } else if (k < 95) {  // invalid, each kind
            switch (kind(g) % 4) {
                case 0: s.prims.push_back(Sphere<T>{c, T(-1)}); break;
                case 1: s.prims.push_back(Aabb<T>{c, c - Vec3<T>::Constant(1)}); break;
                case 2: s.prims.push_back(Sphere<T>{Vec3<T>(std::numeric_limits<T>::quiet_NaN(), 0, 0), h}); break;
                default: s.prims.push_back(Plane<T>{Vec3<T>::Zero(), T(1)}); break;
            }
        } else {  // flat box (valid) and a point sphere
            if (k % 2) s.prims.push_back(Aabb<T>{c, Vec3<T>(c[0] + h, c[1], c[2] + h)});
            else s.prims.push_back(Sphere<T>{c, T(0)});
        }
    }
    return s;
}

// A point inside (or near) primitive p, to aim rays at.
template <class T> Vec3<T> aim(const Primitive<T>& p) {
    if (const auto* a = std::get_if<Aabb<T>>(&p)) return (a->lo + a->hi) / T(2);
    if (const auto* o = std::get_if<Obb<T>>(&p)) return o->center;
    if (const auto* s = std::get_if<Sphere<T>>(&p)) return s->center;
    if (const auto* c = std::get_if<ConvexPolyhedron<T>>(&p))
        if (c->planes.size() == 6)
            return v3<T>((double(c->planes[0].offset) - double(c->planes[1].offset)) / 2,
                         (double(c->planes[2].offset) - double(c->planes[3].offset)) / 2,
                         (double(c->planes[4].offset) - double(c->planes[5].offset)) / 2);
    return Vec3<T>::Zero();
}

template <class T> std::string repro(const Ray<T>& r, const std::vector<Primitive<T>>& prims, std::int64_t a,
                                     std::int64_t b) {
    std::ostringstream os;
    os << "ray " << r << ", " << prims.size() << " primitives";
    for (const std::int64_t i : {a, b})
        if (i >= 0 && std::size_t(i) < prims.size()) os << "; [" << i << "] " << describe(prims[std::size_t(i)]);
    return os.str();
}

// The primitive's own answer in the mode.
template <class T, class Mode> Hit<T> own(const PreparedRay<T>& r, const Primitive<T>& p, Mode m) {
    return std::visit([&](const auto& s) { return intersect(r, s, m); }, p);
}

// Every property of the header comment for one ray; returns whether certified hit.
template <class T, int W> bool check_ray(const Bvh<T, W>& bvh, const std::vector<Primitive<T>>& prims, const Ray<T>& r) {
    const PreparedRay<T> pr(r);
    const std::span<const Primitive<T>> all(prims);
    const ClosestHit<T> ref = closest_hit(pr, all, certified);

    // certified
    const ClosestHit<T> cc = bvh.closest_hit(pr, certified);
    {
        SCOPED_TRACE("certified closest_hit: " + repro(r, prims, ref.index, cc.index));
        EXPECT_EQ(cc.verdict, ref.verdict);
        EXPECT_EQ(cc.index, ref.index);
        EXPECT_TRUE(same_hit(cc.hit, ref.hit));
        const ClosestHit<T> viaray = bvh.closest_hit(r, certified);
        EXPECT_EQ(viaray.index, cc.index);
        EXPECT_TRUE(same_hit(viaray.hit, cc.hit));
    }
    const ClosestHit<T> ca = bvh.any_hit(pr, certified);
    {
        SCOPED_TRACE("certified any_hit: " + repro(r, prims, ref.index, ca.index));
        EXPECT_EQ(ca.verdict, any_hit(pr, all, certified).verdict);
        EXPECT_EQ(ca.verdict, ref.verdict);
        if (ca) {
            EXPECT_TRUE(same_hit(ca.hit, own(pr, prims[std::size_t(ca.index)], certified)));
        } else {
            EXPECT_EQ(ca.index, -1);
        }
    }
    // conservative
    for (const bool closest : {true, false}) {
        const ClosestHit<T> c = closest ? bvh.closest_hit(pr, conservative) : bvh.any_hit(pr, conservative);
        SCOPED_TRACE(std::string("conservative ") + (closest ? "closest_hit: " : "any_hit: ") +
                     repro(r, prims, ref.index, c.index));
        if (ref.verdict == Verdict::invalid) {
            EXPECT_EQ(c.verdict, Verdict::invalid);
            continue;
        }
        if (ref) {
            EXPECT_TRUE(bool(c)) << "conservative lost the hit " << ref.hit;
        }
        if (c) {
            EXPECT_TRUE(same_hit(c.hit, own(pr, prims[std::size_t(c.index)], conservative)));
            if (closest && ref) {
                EXPECT_LE(c.hit.t_enter, ref.hit.t_enter);
                if (c.index == ref.index) {
                    EXPECT_GE(c.hit.t_exit, ref.hit.t_exit);
                }
            }
        }
    }
    // fast
    for (const bool closest : {true, false}) {
        const ClosestHit<T> f = closest ? bvh.closest_hit(pr, fast) : bvh.any_hit(pr, fast);
        SCOPED_TRACE(std::string("fast: ") + repro(r, prims, ref.index, f.index));
        EXPECT_EQ(f.verdict == Verdict::invalid, ref.verdict == Verdict::invalid);
        if (f) {
            EXPECT_TRUE(same_hit(f.hit, own(pr, prims[std::size_t(f.index)], fast)));
        } else {
            EXPECT_EQ(f.index, -1);
        }
    }
    // for_each_candidate: t_limit = t_max, then lowered midway to the middle of the
    // certified closest hit's interval.
    auto candidates = [&](auto mode, bool lower) {
        std::vector<int> seen(prims.size(), 0);
        T limit = r.t_max;
        std::size_t calls = 0;
        T lowered = limit;
        bool was_lowered = false;
        bvh.for_each_candidate(pr, mode, limit, [&](std::size_t i) {
            ++seen[i];
            if (lower && ++calls == 3 && ref) {
                lowered = ref.hit.t_exit;
                limit = lowered;
                was_lowered = true;
            }
            return true;
        });
        SCOPED_TRACE(std::string("for_each_candidate ") + mode_name(mode) + (lower ? " lowered" : "") + ": " +
                     repro(r, prims, ref.index, -1));
        if (ref.verdict == Verdict::invalid) {
            for (std::size_t i = 0; i < prims.size(); ++i) EXPECT_EQ(seen[i], 0);
            return;
        }
        const PreparedRay<T> cut = was_lowered ? pr.with_range(r.t_min, lowered) : pr;
        for (std::size_t i = 0; i < prims.size(); ++i) {
            EXPECT_LE(seen[i], 1) << "candidate " << i << " twice";
            // Before the third call every meeting on [t_min, t_max] counts; a candidate
            // met only after the limit came down may be skipped: hold to the narrowed
            // range, which is what the contract promises throughout.
            if (own(cut, prims[i], certified)) {
                EXPECT_EQ(seen[i], 1) << "skipped " << i << ": " << describe(prims[i]);
            }
        }
    };
    for (const bool lower : {false, true}) {
        candidates(certified, lower);
        candidates(conservative, lower);
    }
    return bool(ref);
}

// The tree itself: stats, every primitive once, lane boxes the exact unions below them.
template <class T, int W> void check_tree(const Bvh<T, W>& bvh, const std::vector<Primitive<T>>& prims) {
    const BvhStats s = bvh.stats();
    EXPECT_EQ(s.primitives, prims.size());
    EXPECT_EQ(bvh.size(), prims.size());
    // Stored order: leaf order, then the primitives beside the tree; each stored copy is
    // the primitive index_of names, and index_of is a permutation.
    ASSERT_EQ(bvh.stored().size(), prims.size());
    {
        std::vector<int> named(prims.size(), 0);
        const std::size_t in_tree = bvh.leaf_indices().size();
        for (std::size_t p = 0; p < prims.size(); ++p) {
            const std::size_t i = bvh.index_of(p);
            ASSERT_LT(i, prims.size()) << "stored position " << p;
            ++named[i];
            EXPECT_EQ(i, p < in_tree ? std::size_t(bvh.leaf_indices()[p]) : bvh.outside()[p - in_tree]);
            EXPECT_EQ(describe(bvh.stored()[p]), describe(prims[i])) << "stored position " << p << ", index " << i;
        }
        for (std::size_t i = 0; i < prims.size(); ++i) EXPECT_EQ(named[i], 1) << "index " << i;
    }
    std::vector<int> where(prims.size(), 0);
    for (const std::size_t i : bvh.outside()) {
        ASSERT_LT(i, prims.size());
        ++where[i];
        EXPECT_FALSE(detail::bvh_box(prims[i]).has_value()) << "boxed primitive kept beside the tree: " << i;
    }
    EXPECT_EQ(s.outside, bvh.outside().size());
    const auto nodes = bvh.nodes();
    const auto order = bvh.leaf_indices();
    EXPECT_EQ(s.nodes, nodes.size());
    std::size_t leaves = 0, reached = 0;
    int depth = 0;
    // Returns the union of a node's lane boxes, checking each lane against its contents.
    struct Box {
        T lo[3] = {inf<T>, inf<T>, inf<T>}, hi[3] = {-inf<T>, -inf<T>, -inf<T>};
        void add(const T* l, const T* h) {
            for (int a = 0; a < 3; ++a) {
                lo[a] = std::min(lo[a], l[a]);
                hi[a] = std::max(hi[a], h[a]);
            }
        }
    };
    // lowest[id]: the lowest leaf position below node id. Lane 0 starts the node's range
    // of positions (the build's invariant the traversal's ball prefetch relies on).
    std::vector<std::uint32_t> lowest(nodes.size(), std::numeric_limits<std::uint32_t>::max());
    std::function<Box(std::uint32_t, int)> walk = [&](std::uint32_t id, int d) -> Box {
        ++reached;
        depth = std::max(depth, d);
        const auto& n = nodes[id];
        Box all;
        const auto lowest_at_end = [&] {
            if (n.count[0] > 0) {
                EXPECT_EQ(n.first[0], lowest[id]) << "lane 0 of node " << id << " starts its range";
            }
        };
        for (int i = 0; i < W; ++i) {
            const Aabb<T> lane = n.box.box(i);
            Box below;
            if (n.count[i] > 0) {
                ++leaves;
                lowest[id] = std::min(lowest[id], n.first[i]);
                for (std::uint32_t k = n.first[i]; k < n.first[i] + n.count[i]; ++k) {
                    const std::size_t p = order[k];
                    ++where[p];
                    const std::optional<Aabb<T>> b = detail::bvh_box(prims[p]);
                    EXPECT_TRUE(b.has_value()) << "unboxed primitive in a leaf: " << p;
                    if (b) below.add(b->lo.data(), b->hi.data());
                }
                EXPECT_LE(int(n.count[i]), 4);
            } else if (lane.lo[0] <= lane.hi[0]) {
                EXPECT_GT(n.first[i], id) << "children come after their parent";
                below = walk(n.first[i], d + 1);
                lowest[id] = std::min(lowest[id], lowest[n.first[i]]);
            } else {
                EXPECT_GT(lane.lo[0], lane.hi[0]);  // an empty slot stays empty on every axis
                EXPECT_GT(lane.lo[1], lane.hi[1]);
                EXPECT_GT(lane.lo[2], lane.hi[2]);
                continue;
            }
            for (int a = 0; a < 3; ++a) {
                EXPECT_TRUE(same_bits(lane.lo[a], below.lo[a]) || lane.lo[a] == below.lo[a])
                    << "lane " << i << " of node " << id << " is not the union below it";
                EXPECT_EQ(lane.hi[a], below.hi[a]) << "lane " << i << " of node " << id;
            }
            all.add(lane.lo.data(), lane.hi.data());
        }
        lowest_at_end();
        return all;
    };
    if (!nodes.empty()) walk(0, 1);
    EXPECT_EQ(reached, nodes.size()) << "every node reached once";
    EXPECT_EQ(leaves, s.leaves);
    EXPECT_EQ(depth, s.depth);
    for (std::size_t i = 0; i < prims.size(); ++i) EXPECT_EQ(where[i], 1) << "primitive " << i << ": " << describe(prims[i]);
    EXPECT_GT(s.bytes, nodes.size() * sizeof(nodes[0]));
}

template <class P> class BvhTest : public ::testing::Test {};
template <class T, int W> struct Config {
    using type = T;
    static constexpr int width = W;
};
using Configs = ::testing::Types<Config<float, 4>, Config<float, 8>, Config<double, 4>, Config<double, 8>>;
TYPED_TEST_SUITE(BvhTest, Configs);

template <class T> Ray<T> ray_to(const Vec3<T>& from, const Vec3<T>& to, T t_min = 0, T t_max = inf<T>) {
    return Ray<T>{from, to - from, t_min, t_max};
}

TYPED_TEST(BvhTest, RandomScenesEqualBruteForce) {
    using T = typename TypeParam::type;
    constexpr int W = TypeParam::width;
    RAYPROOF_SEED_TRACE(base_seed());
    std::mt19937_64 g = make_rng();
    std::uniform_real_distribution<double> u(-12, 12), t01(0, 1);
    std::size_t hits = 0, rays = 0;
    for (const int n : {1, 2, 9, 60, 600}) {
        for (int rep = 0; rep < 3; ++rep) {
            const Scene<T> s = random_scene<T>(g, n);
            const Bvh<T, W> bvh(std::span<const Primitive<T>>(s.prims), BvhOptions{4, 16});
            SCOPED_TRACE("scene of " + std::to_string(n) + ", repetition " + std::to_string(rep));
            check_tree(bvh, s.prims);
            const int nrays = n >= 600 ? 150 : 60;
            for (int k = 0; k < nrays; ++k) {
                const Vec3<T> o = v3<T>(u(g), u(g), u(g));
                Ray<T> r;
                switch (k % 5) {
                    case 0:
                    case 1: r = ray_to(o, aim(s.prims[std::size_t(g() % s.prims.size())])); break;
                    case 2: r = Ray<T>{o, v3<T>(u(g), u(g), u(g))}; break;
                    case 3: {  // parallel to one or two axes
                        Vec3<T> d = v3<T>(u(g), u(g), u(g));
                        d[int(g() % 3)] = 0;
                        if (g() % 2) d[int(g() % 3)] = T(-0.0);
                        if (d.isZero()) d[0] = 1;
                        r = Ray<T>{o, d};
                        break;
                    }
                    default: {  // the range cuts the scene
                        r = ray_to(o, aim(s.prims[std::size_t(g() % s.prims.size())]));
                        r.t_min = T(t01(g) * 0.8);
                        r.t_max = T(double(r.t_min) + t01(g) * 1.2);
                        break;
                    }
                }
                ++rays;
                hits += check_ray(bvh, s.prims, r);
                if (::testing::Test::HasFailure()) return;
            }
        }
    }
    EXPECT_GT(hits, rays / 5) << "the rays should hit often enough to matter";
}

TYPED_TEST(BvhTest, EmptyOneAndOnlyOutside) {
    using T = typename TypeParam::type;
    constexpr int W = TypeParam::width;
    const Ray<T> r{v3<T>(0, 0, -5), v3<T>(0, 0, 1)};
    {
        const Bvh<T, W> empty;
        EXPECT_EQ(empty.closest_hit(r, certified).verdict, Verdict::miss);
        EXPECT_EQ(empty.any_hit(r, fast).verdict, Verdict::miss);
        EXPECT_EQ(empty.closest_hit(Ray<T>{v3<T>(0, 0, 0), v3<T>(0, 0, 0)}, certified).verdict, Verdict::invalid);
        const BvhStats s = empty.stats();
        EXPECT_EQ(s.primitives + s.nodes + s.leaves + s.outside, 0u);
        EXPECT_EQ(s.depth, 0);
        const std::vector<Primitive<T>> none;
        const Bvh<T, W> built(none);
        check_tree(built, none);
        check_ray(built, none, r);
    }
    {
        const std::vector<Primitive<T>> one{Sphere<T>{v3<T>(0, 0, 0), T(1)}};
        const Bvh<T, W> bvh(one);
        check_tree(bvh, one);
        EXPECT_EQ(bvh.stats().nodes, 1u);
        EXPECT_EQ(bvh.stats().depth, 1);
        EXPECT_TRUE(check_ray(bvh, one, r));
        const ClosestHit<T> h = bvh.closest_hit(r, certified);
        EXPECT_EQ(h.index, 0);
        EXPECT_EQ(h.hit.t_enter, T(4));
        check_ray(bvh, one, Ray<T>{v3<T>(0, 2, -5), v3<T>(0, 0, 1)});
    }
    {
        std::vector<Primitive<T>> planes;
        for (int i = 0; i < 5; ++i) planes.push_back(Plane<T>{v3<T>(0, 0, 1), T(i - 2)});
        planes.push_back(Plane<T>{v3<T>(0, 1, 0), T(0)});  // the ray lies in it: t_enter = t_min
        const Bvh<T, W> bvh(planes);
        check_tree(bvh, planes);
        EXPECT_EQ(bvh.stats().nodes, 0u);
        EXPECT_EQ(bvh.stats().outside, planes.size());
        EXPECT_TRUE(check_ray(bvh, planes, r));
        EXPECT_EQ(bvh.closest_hit(r, certified).index, 5);
        check_ray(bvh, planes, Ray<T>{v3<T>(0, 1, -5), v3<T>(0, 0, 1), T(-inf<T>), T(2)});
        check_ray(bvh, planes, Ray<T>{v3<T>(0, 0, -5), v3<T>(0, 0, 1), T(-inf<T>), T(2)});
    }
    {
        const std::vector<Primitive<T>> bad{Sphere<T>{v3<T>(0, 0, 0), T(-1)},
                                            Aabb<T>{v3<T>(1, 1, 1), v3<T>(0, 0, 0)},
                                            Plane<T>{v3<T>(0, 0, 0), T(0)},
                                            Aabb<T>{v3<T>(0, 0, 0), v3<T>(inf<T>, 1, 1)},
                                            Sphere<T>{v3<T>(0, 0, std::numeric_limits<T>::quiet_NaN()), T(1)}};
        const Bvh<T, W> bvh(bad);
        check_tree(bvh, bad);
        EXPECT_EQ(bvh.stats().outside, bad.size());
        for (const Ray<T>& q : {r, Ray<T>{v3<T>(0.5, 0.5, -5), v3<T>(0, 0, 1)}}) {
            EXPECT_FALSE(check_ray(bvh, bad, q));
            EXPECT_EQ(bvh.closest_hit(q, certified).verdict, Verdict::miss);
            EXPECT_EQ(bvh.any_hit(q, conservative).verdict, Verdict::miss);
        }
    }
}

TYPED_TEST(BvhTest, InvalidRays) {
    using T = typename TypeParam::type;
    constexpr int W = TypeParam::width;
    std::mt19937_64 g = make_rng();
    const Scene<T> s = random_scene<T>(g, 40);
    const Bvh<T, W> bvh(s.prims);
    const T nan = std::numeric_limits<T>::quiet_NaN();
    for (const Ray<T>& r : {Ray<T>{v3<T>(0, 0, 0), v3<T>(0, 0, 0)}, Ray<T>{v3<T>(0, nan, 0), v3<T>(1, 0, 0)},
                            Ray<T>{v3<T>(0, 0, 0), v3<T>(1, 0, inf<T>)}, Ray<T>{v3<T>(0, 0, 0), v3<T>(1, 0, 0), T(2), T(1)},
                            Ray<T>{v3<T>(0, 0, 0), v3<T>(1, 0, 0), inf<T>, inf<T>}}) {
        SCOPED_TRACE(::testing::PrintToString(r));
        check_ray(bvh, s.prims, r);
        EXPECT_EQ(bvh.closest_hit(r, certified).verdict, Verdict::invalid);
        EXPECT_EQ(bvh.closest_hit(r, fast).verdict, Verdict::invalid);
        EXPECT_EQ(bvh.any_hit(r, conservative).verdict, Verdict::invalid);
        EXPECT_EQ(bvh.closest_hit(r, certified).index, -1);
    }
}

// Directions whose reciprocals the node filters cannot use (a float tree's float lanes
// need |d_i| in [2^-128, 2^126], the double lanes |d_i| < 2^1022): the node tests
// fall back to wider lanes or to the scalar query, and the answers stay those of brute
// force.
TYPED_TEST(BvhTest, ExtremeDirections) {
    using T = typename TypeParam::type;
    constexpr int W = TypeParam::width;
    RAYPROOF_SEED_TRACE(base_seed());
    std::mt19937_64 g = make_rng();
    const Scene<T> s = random_scene<T>(g, 200);
    const Bvh<T, W> bvh(s.prims);
    const T tiny = std::numeric_limits<T>::denorm_min() * T(3), huge = std::numeric_limits<T>::max() / T(4);
    std::uniform_real_distribution<double> u(-12, 12);
    std::size_t hits = 0;
    for (int k = 0; k < 60; ++k) {
        const Vec3<T> to = aim(s.prims[std::size_t(g() % s.prims.size())]), from = v3<T>(u(g), u(g), u(g));
        Vec3<T> d = to - from;
        const int a = int(g() % 3);
        switch (k % 4) {
            case 0: d[a] = tiny; break;                                   // a subnormal component
            case 1: d[a] = -tiny; d[(a + 1) % 3] = T(0x1p-130); break;    // below the float lanes' range
            case 2: d *= T(0x1p100); d[a] = huge; break;                  // beyond the float lanes' range
            default: d = d.normalized() * huge; break;                    // every component huge
        }
        if (d.isZero()) d[a] = T(1);
        hits += check_ray(bvh, s.prims, Ray<T>{from, d});
        if (::testing::Test::HasFailure()) return;
    }
    EXPECT_GT(hits, 5u);
}

// Coincident and touching boxes, a ray along their shared face and through a shared
// edge, equal entries everywhere: ties go to the lowest index.
TYPED_TEST(BvhTest, TiesTouchingAndCoincident) {
    using T = typename TypeParam::type;
    constexpr int W = TypeParam::width;
    std::vector<Primitive<T>> prims;
    for (int i = 0; i < 32; ++i)  // a row of touching unit boxes along x
        prims.push_back(Aabb<T>{v3<T>(i, 0, 0), v3<T>(i + 1, 1, 1)});
    for (int i = 0; i < 20; ++i)  // the same box twenty times
        prims.push_back(Aabb<T>{v3<T>(40, 0, 0), v3<T>(41, 1, 1)});
    // Spheres around b, pairs along each axis direction, all entered at t = 4 by the rays
    // from b along the axes: centre b ± 5k·e_axis, radius 5k - 4 (k = 1, 2).
    const Vec3<T> b = v3<T>(-20, -20, -20);
    for (int k = 1; k <= 2; ++k)
        for (int a = 0; a < 3; ++a)
            for (const int side : {1, -1}) {
                Vec3<T> c = b;
                c[a] += T(side * 5 * k);
                prims.push_back(Sphere<T>{c, T(5 * k - 4)});
            }
    const Bvh<T, W> bvh(prims);
    check_tree(bvh, prims);
    const std::vector<Ray<T>> rays{
        Ray<T>{v3<T>(-1, 0, 0.5), v3<T>(1, 0, 0)},          // along the shared face y = 0
        Ray<T>{v3<T>(-1, 1, 1), v3<T>(1, 0, 0)},            // along the shared top edge
        Ray<T>{v3<T>(5, 0.5, -3), v3<T>(0, 0, 1)},          // down the shared face x = 5: boxes 4 and 5 tie
        Ray<T>{v3<T>(5, 0, -3), v3<T>(0, 0, 1)},            // down the shared edge x = 5, y = 0
        Ray<T>{v3<T>(5, -1, -1), v3<T>(0, 1, 1)},           // diagonally into the edge
        Ray<T>{v3<T>(40.5, 0.5, -2), v3<T>(0, 0, 1)},       // the twenty coincident boxes
        Ray<T>{v3<T>(41, 1, 1), v3<T>(1, 1, 1)},            // from their common corner outwards
        Ray<T>{v3<T>(0.5, 0.5, 0.5), v3<T>(1, 0, 0)},       // from inside box 0
        Ray<T>{v3<T>(-1, 0.5, 0.5), v3<T>(1, 0, 0), T(10.5), T(12)},  // a range inside the row
        Ray<T>{v3<T>(-1, 0.5, 0.5), v3<T>(1, 0, 0), T(11), T(11)},    // one point, on a shared face
        Ray<T>{b, v3<T>(1, 0, 0)},  Ray<T>{b, v3<T>(-1, 0, 0)},  // the spheres: pairs entered at t = 4
        Ray<T>{b, v3<T>(0, 0, 1)},  Ray<T>{b, v3<T>(0, -1, 0)},
    };
    for (const Ray<T>& r : rays) {
        SCOPED_TRACE(::testing::PrintToString(r));
        EXPECT_TRUE(check_ray(bvh, prims, r));
    }
    EXPECT_EQ(bvh.closest_hit(rays[2], certified).index, 4);
    EXPECT_EQ(bvh.closest_hit(rays[5], certified).index, 32);
    EXPECT_EQ(bvh.closest_hit(rays[5], fast).index, 32);
    EXPECT_EQ(bvh.closest_hit(rays[9], certified).index, 9);
    EXPECT_EQ(bvh.closest_hit(rays[10], certified).index, 52);  // b + 5·e_x, before b + 10·e_x
    EXPECT_EQ(bvh.closest_hit(rays[10], certified).hit.t_enter, T(4));
    EXPECT_EQ(bvh.closest_hit(rays[13], certified).index, 55);
}

// A thousand boxes with the same centroid (the bins cannot split them: medians) and a
// thousand copies of one sphere: still every primitive once, the lowest index answered.
TYPED_TEST(BvhTest, EqualCentroids) {
    using T = typename TypeParam::type;
    constexpr int W = TypeParam::width;
    std::vector<Primitive<T>> prims;
    for (int i = 0; i < 1000; ++i) prims.push_back(Aabb<T>{v3<T>(-1 - i, -1, -1), v3<T>(1 + i, 1, 1)});
    for (int i = 0; i < 1000; ++i) prims.push_back(Sphere<T>{v3<T>(0, 5, 0), T(0.5)});
    const Bvh<T, W> bvh(prims, BvhOptions{2, 8});
    check_tree<T, W>(bvh, prims);  // leaf_size 2 <= 4
    EXPECT_LE(bvh.stats().depth, detail::bvh_max_depth);
    for (const Ray<T>& r : {Ray<T>{v3<T>(0, 0, -5), v3<T>(0, 0, 1)}, Ray<T>{v3<T>(-3000, 0, 0), v3<T>(1, 0, 0)},
                            Ray<T>{v3<T>(0, 5, -5), v3<T>(0, 0, 1)}, Ray<T>{v3<T>(0, 10, 0), v3<T>(0, -1, 0)}})
        EXPECT_TRUE(check_ray(bvh, prims, r));
    EXPECT_EQ(bvh.closest_hit(Ray<T>{v3<T>(0, 5, -5), v3<T>(0, 0, 1)}, certified).index, 1000);
    EXPECT_EQ(bvh.closest_hit(Ray<T>{v3<T>(-3000, 0, 0), v3<T>(1, 0, 0)}, certified).index, 999);
}

// with_range: the prepared ray on another range equals one prepared on it.
TYPED_TEST(BvhTest, WithRangeEqualsPreparedOnTheRange) {
    using T = typename TypeParam::type;
    const T nan = std::numeric_limits<T>::quiet_NaN();
    const std::vector<Ray<T>> rays{Ray<T>{v3<T>(1, 2, 3), v3<T>(0.5, -0, 3)}, Ray<T>{v3<T>(1, 2, 3), v3<T>(0, 0, 0)},
                                   Ray<T>{v3<T>(nan, 2, 3), v3<T>(1, 0, 0)}, Ray<T>{v3<T>(1, 2, 3), v3<T>(1e-300, 1, 0)}};
    const std::vector<std::pair<T, T>> ranges{{T(0), T(1)}, {T(2), T(1)}, {-inf<T>, inf<T>}, {inf<T>, inf<T>},
                                              {T(0), nan},  {T(1), T(1)}, {-inf<T>, -inf<T>}};
    for (const Ray<T>& r : rays)
        for (const auto& [lo, hi] : ranges) {
            Ray<T> q = r;
            q.t_min = lo;
            q.t_max = hi;
            const PreparedRay<T> a = PreparedRay<T>(r).with_range(lo, hi), b(q);
            SCOPED_TRACE(::testing::PrintToString(q));
            EXPECT_EQ(a.valid(), b.valid());
            EXPECT_EQ(a.reciprocals_normal(), b.reciprocals_normal());
            EXPECT_EQ(a.template reciprocals_usable_in<float>(), b.template reciprocals_usable_in<float>());
            EXPECT_EQ(a.template reciprocals_usable_in<double>(), b.template reciprocals_usable_in<double>());
            EXPECT_EQ(a.parallel_axes(), b.parallel_axes());
            EXPECT_TRUE(same_bits(a.ray().t_min, lo) && same_bits(a.ray().t_max, hi));
            for (int i = 0; i < 3; ++i) {
                EXPECT_TRUE(same_bits(a.rinv(i), b.rinv(i)));
                EXPECT_TRUE(same_bits(a.inv(i), b.inv(i)));
                EXPECT_EQ(a.negative(i), b.negative(i));
            }
        }
}

// The fast node test (detail::bvh_node_fast) is the fast packet's lanes on a tree's own
// boxes: on every node of random trees (empty slots included) and random rays with no
// axis parallel and no slab value overflowing, the same mask, and on the hit lanes the
// same entries, bit for bit, with the native and the portable backend alike.
TYPED_TEST(BvhTest, FastNodeTestIsTheFastPacketsLanes) {
    using T = typename TypeParam::type;
    constexpr int W = TypeParam::width;
    RAYPROOF_SEED_TRACE(base_seed());
    std::mt19937_64 g = make_rng();
    std::uniform_real_distribution<double> u(-12, 12), t01(0, 1);
    std::size_t lanes_hit = 0;
    for (const int n : {9, 60, 600}) {
        const Scene<T> s = random_scene<T>(g, n);
        const Bvh<T, W> bvh(std::span<const Primitive<T>>(s.prims));
        for (int k = 0; k < 40; ++k) {
            Ray<T> r = k % 2 ? ray_to(v3<T>(u(g), u(g), u(g)), aim(s.prims[std::size_t(g() % s.prims.size())]))
                             : Ray<T>{v3<T>(u(g), u(g), u(g)), v3<T>(u(g), u(g), u(g))};
            if (k % 3 == 0) {
                r.t_min = T(t01(g) * 4);
                r.t_max = T(double(r.t_min) + t01(g) * 8);
            }
            const PreparedRay<T> pr(r);
            if (detail::bvh_fast_filter_for(pr) != detail::BvhFilter::lean) continue;  // a zero component
            SCOPED_TRACE(::testing::PrintToString(r));
            for (const auto& node : bvh.nodes()) {
                T t[std::size_t(W)], tp[std::size_t(W)], want[std::size_t(W)];
                const std::uint32_t mask = detail::bvh_node_fast<detail::simd::native>(pr, node.box, t);
                const std::uint32_t mask_p = detail::bvh_node_fast<detail::simd::portable>(pr, node.box, tp);
                const auto l = detail::packet::fast_lanes<detail::simd::native, false>(pr, node.box);
                l.enter.store(want);
                ASSERT_EQ(mask, l.ok.bits());
                ASSERT_EQ(mask_p, mask);
                for (int i = 0; i < W; ++i)
                    if (mask >> i & 1) {
                        ++lanes_hit;
                        ASSERT_TRUE(same_bits(t[i], want[i]) && same_bits(tp[i], want[i])) << "lane " << i;
                    }
            }
        }
    }
    EXPECT_GT(lanes_hit, 100u) << "the rays should meet enough lanes to matter";
}

// The scene with every coordinate and length multiplied by scale (a power of two, so
// exactly unless it leaves T's range).
template <class T> Scene<T> scaled(Scene<T> s, double scale) {
    auto sc = [&](T x) { return T(double(x) * scale); };
    for (Primitive<T>& p : s.prims) {
        if (auto* a = std::get_if<Aabb<T>>(&p)) *a = Aabb<T>{a->lo.unaryExpr(sc), a->hi.unaryExpr(sc)};
        if (auto* b = std::get_if<Sphere<T>>(&p)) *b = Sphere<T>{b->center.unaryExpr(sc), sc(b->radius)};
        if (auto* o = std::get_if<Obb<T>>(&p)) *o = Obb<T>{o->center.unaryExpr(sc), o->axes, o->half_extent.unaryExpr(sc)};
    }
    return s;
}

// The scaled node test (detail::bvh_node_scaled, the conservative and certified modes'
// node test where bvh_scaled_usable admits the ray) never drops a lane the exact ray
// meets: on every node of random trees at three scales (normal; every coordinate in the
// subnormals, where the slab products underflow; near 2^100 in float, 2^900 in double),
// against the certified packet verdict on the same range (exact), with rays at random,
// aimed at node corners (grazing) and with ranges ending at a lane's certified entry.
// Its entry bound lies at or below the certified t_enter (faithful, so the exact entry
// is above its predecessor), empty slots never hit, the native and portable backends
// agree bit for bit, and it keeps few lanes the exact test drops.
TYPED_TEST(BvhTest, ScaledNodeTestKeepsEveryExactHit) {
    using T = typename TypeParam::type;
    constexpr int W = TypeParam::width;
    constexpr bool f = std::is_same_v<T, float>;
    RAYPROOF_SEED_TRACE(base_seed());
    std::mt19937_64 g = make_rng();
    std::uniform_real_distribution<double> u(-12, 12), t01(0, 1);
    std::size_t used = 0, exact_hits = 0, extra = 0, underflow_lanes = 0;
    for (const double scale : {1.0, f ? 0x1p-140 : 0x1p-1060, f ? 0x1p100 : 0x1p900}) {
        SCOPED_TRACE("scale " + ::testing::PrintToString(scale));
        const Scene<T> s = scaled(random_scene<T>(g, 300), scale);
        auto sc = [&](T x) { return T(double(x) * scale); };
        const Bvh<T, W> bvh(std::span<const Primitive<T>>(s.prims));
        double extent = 0;
        std::vector<std::pair<int, int>> lanes;  // (node, lane) of every non-empty lane
        for (std::size_t n = 0; n < bvh.nodes().size(); ++n)
            for (int i = 0; i < W; ++i) {
                const auto& box = bvh.nodes()[n].box;
                if (!(box.lo[0][i] <= box.hi[0][i])) continue;
                lanes.emplace_back(int(n), i);
                for (int a = 0; a < 3; ++a)
                    extent = std::max({extent, std::abs(double(box.lo[a][i])), std::abs(double(box.hi[a][i]))});
            }
        ASSERT_FALSE(lanes.empty());
        for (int k = 0; k < 90; ++k) {
            // Directions at the scene's scale, except in the subnormals (normal directions
            // there, so that the reciprocals stay in range and the products underflow).
            const double dscale = scale < 1 ? 1.0 : scale;
            const Vec3<T> o = v3<T>(u(g), u(g), u(g)).unaryExpr(sc);
            Ray<T> r{o, v3<T>(u(g) * dscale, u(g) * dscale, u(g) * dscale)};
            if (k % 3 == 1) {  // at a corner of some lane's box, ahead (t = 1) or behind (t = -1)
                const auto [n, i] = lanes[std::size_t(g() % lanes.size())];
                const auto& box = bvh.nodes()[std::size_t(n)].box;
                Vec3<T> corner;
                for (int a = 0; a < 3; ++a) corner[a] = g() % 2 ? box.lo[a][i] : box.hi[a][i];
                r.direction = k % 2 ? Vec3<T>(corner - o) : Vec3<T>(o - corner);
                if (scale < 1) r.direction = (r.direction.template cast<double>() / scale).template cast<T>();
                if (k % 2 == 0) r.t_min = -inf<T>;
            }
            if (k % 3 == 2) {  // a range cutting the scene, sometimes reaching behind the origin
                r.t_min = T(t01(g) * 0.5 - (k % 4 == 2 ? 1.0 : 0.0));
                r.t_max = T(double(r.t_min) + t01(g) * 2);
            }
            if (r.direction.isZero()) continue;
            const PreparedRay<T> pr0(r);
            if (k % 5 == 4 && pr0.valid()) {  // the range ends at a lane's certified entry
                const auto [n, i] = lanes[std::size_t(g() % lanes.size())];
                const PacketHit<T, W> h = intersect(pr0, bvh.nodes()[std::size_t(n)].box, certified);
                if ((h.mask >> i) & 1) r.t_max = h.t_enter[i];
            }
            const PreparedRay<T> pr(r);
            if (!pr.valid() || !detail::bvh_scaled_usable(pr, extent)) continue;
            ++used;
            SCOPED_TRACE(::testing::PrintToString(r));
            for (std::size_t n = 0; n < bvh.nodes().size(); ++n) {
                const auto& box = bvh.nodes()[n].box;
                double t[std::size_t(W)], tp[std::size_t(W)];
                const std::uint32_t mask = detail::bvh_node_scaled<detail::simd::native>(pr, box, t);
                const std::uint32_t mask_p = detail::bvh_node_scaled<detail::simd::portable>(pr, box, tp);
                const PacketHit<T, W> exact = intersect(pr, box, certified);
                ASSERT_EQ(mask_p, mask) << "node " << n;
                ASSERT_EQ(exact.mask & ~mask, 0u) << "node " << n << ": an exact hit dropped";
                for (int i = 0; i < W; ++i) {
                    ASSERT_TRUE(same_bits(t[i], tp[i])) << "node " << n << " lane " << i;
                    if (!(box.lo[0][i] <= box.hi[0][i])) {
                        ASSERT_FALSE((mask >> i) & 1) << "node " << n << ": an empty slot hit";
                    }
                    if ((exact.mask >> i) & 1) {
                        ++exact_hits;
                        ASSERT_LE(t[i], double(exact.t_enter[i])) << "node " << n << " lane " << i;
                        underflow_lanes += std::abs(double(exact.t_enter[i])) < double(std::numeric_limits<T>::min()) &&
                                           exact.t_enter[i] != 0;
                    } else if ((mask >> i) & 1) {
                        ++extra;
                    }
                }
            }
        }
    }
    EXPECT_GT(used, 150u) << "the test should reach the scaled node test";
    EXPECT_GT(exact_hits, 500u);
    EXPECT_LE(extra, std::max<std::size_t>(20, exact_hits / 20)) << "the scaled test keeps too many misses";
    EXPECT_GT(underflow_lanes, 10u) << "the subnormal scene should reach entries in the subnormals";
}

#if defined(__x86_64__) || defined(_M_X64)
// The caller's floating-point environment does not change the answers: under
// flush-to-zero with denormals-are-zero, and under upward rounding, the tree is built
// the same bit for bit and certified closest_hit equals the brute force asked in the
// default environment, on a scene at a normal scale and on one scaled into the
// subnormals (where DAZ would read every coordinate as zero); for_each_candidate given an
// FpEnvScope made there lists the candidates it lists in the default environment without
// one, and the scope's end restores the caller's control state.
template <class T, int W> void check_foreign_env(unsigned csr_bits, int round) {
    std::mt19937_64 g = make_rng();
    std::uniform_real_distribution<double> u(-12, 12);
    for (const double scale : {1.0, sizeof(T) == 4 ? 0x1p-140 : 0x1p-1060}) {
        const Scene<T> s = scaled(random_scene<T>(g, 50), scale);
        auto sc = [&](T x) { return T(double(x) * scale); };
        const Bvh<T, W> home(s.prims);
        std::vector<Ray<T>> rays;
        std::vector<ClosestHit<T>> refs;
        for (int k = 0; k < 40; ++k) {
            const Vec3<T> o = v3<T>(u(g), u(g), u(g)).unaryExpr(sc);
            rays.push_back(k % 2 ? ray_to(o, aim(s.prims[std::size_t(g() % s.prims.size())])) : Ray<T>{o, v3<T>(u(g), u(g), u(g))});
            refs.push_back(closest_hit(rays.back(), std::span<const Primitive<T>>(s.prims), certified));
        }
        // for_each_candidate's list (every candidate, t_limit = t_max), without a scope in
        // the default environment and with an FpEnvScope made under the foreign one.
        const auto candidates_of = [&](const Ray<T>& r, const FpEnvScope* scope) {
            std::vector<std::size_t> c;
            T limit = r.t_max;
            const PreparedRay<T> pr(r);
            const auto take = [&c](std::size_t i) {
                c.push_back(i);
                return true;
            };
            if (scope)
                home.for_each_candidate(pr, certified, limit, take, *scope);
            else
                home.for_each_candidate(pr, certified, limit, take);
            return c;
        };
        std::vector<std::vector<std::size_t>> ref_candidates, scoped_candidates;
        for (const Ray<T>& r : rays) ref_candidates.push_back(candidates_of(r, nullptr));
        const unsigned saved = _mm_getcsr();
        _mm_setcsr(saved | csr_bits);
        const int saved_round = std::fegetround();
        std::fesetround(round);
        const Bvh<T, W> away(s.prims);
        std::vector<ClosestHit<T>> got, cons;
        for (const Ray<T>& r : rays) {
            got.push_back(away.closest_hit(r, certified));
            cons.push_back(away.closest_hit(r, conservative));
        }
        const unsigned csr_before_scope = _mm_getcsr();
        {
            const FpEnvScope scope;
            EXPECT_TRUE(scope.switched()) << "the environment made here is foreign";
            for (const Ray<T>& r : rays) scoped_candidates.push_back(candidates_of(r, &scope));
        }
        const unsigned csr_after_scope = _mm_getcsr();
        std::fesetround(saved_round);
        _mm_setcsr(saved);
        // The control bits (6-15: DAZ, masks, rounding, FTZ) as the scope found them.
        EXPECT_EQ(csr_after_scope & 0xFFC0u, csr_before_scope & 0xFFC0u)
            << "the FpEnvScope did not restore the caller's control state";
        EXPECT_NE(csr_before_scope & 0xFFC0u, 0x1F80u) << "the caller's environment is foreign";
        EXPECT_EQ(scoped_candidates, ref_candidates) << "for_each_candidate in an FpEnvScope";
        SCOPED_TRACE("scale " + std::to_string(scale));
        ASSERT_EQ(home.nodes().size(), away.nodes().size());
        for (std::size_t n = 0; n < home.nodes().size(); ++n)
            for (int a = 0; a < 3; ++a)
                for (int i = 0; i < W; ++i) {
                    EXPECT_TRUE(same_bits(home.nodes()[n].box.lo[a][i], away.nodes()[n].box.lo[a][i])) << n;
                    EXPECT_TRUE(same_bits(home.nodes()[n].box.hi[a][i], away.nodes()[n].box.hi[a][i])) << n;
                }
        std::size_t hits = 0;
        for (std::size_t k = 0; k < rays.size(); ++k) {
            SCOPED_TRACE(repro(rays[k], s.prims, refs[k].index, got[k].index));
            EXPECT_EQ(got[k].verdict, refs[k].verdict);
            EXPECT_EQ(got[k].index, refs[k].index);
            EXPECT_TRUE(same_hit(got[k].hit, refs[k].hit));
            if (refs[k]) {
                EXPECT_TRUE(bool(cons[k]));
            }
            hits += bool(refs[k]);
        }
        EXPECT_GT(hits, 0u);
    }
}
TYPED_TEST(BvhTest, AnswersAlikeInAForeignEnvironment) {
    using T = typename TypeParam::type;
    constexpr int W = TypeParam::width;
    RAYPROOF_SEED_TRACE(base_seed());
    check_foreign_env<T, W>(0x8040u, FE_TONEAREST);  // FTZ (bit 15), DAZ (bit 6)
    check_foreign_env<T, W>(0u, FE_UPWARD);
    check_foreign_env<T, W>(0x8040u, FE_DOWNWARD);
}
#endif

// The bit helpers the traversal uses in place of min and nextafter.
TYPED_TEST(BvhTest, BitHelpers) {
    using T = typename TypeParam::type;
    for (const T x : {T(0), T(-0.0), T(1), T(-1), std::numeric_limits<T>::denorm_min(), -std::numeric_limits<T>::denorm_min(),
                      std::numeric_limits<T>::max(), std::numeric_limits<T>::lowest(), -inf<T>, T(1e-30)}) {
        EXPECT_TRUE(same_bits(detail::bvh_next_up(x), std::nextafter(x, inf<T>)) || (x == 0 && detail::bvh_next_up(x) == std::numeric_limits<T>::denorm_min()))
            << x;
        EXPECT_TRUE(same_bits(detail::bvh_select(true, x, T(7)), x));
        EXPECT_TRUE(same_bits(detail::bvh_select(false, T(7), x), x));
    }
    EXPECT_EQ(detail::bvh_next_up(inf<T>), inf<T>);
    EXPECT_TRUE(std::isnan(detail::bvh_next_up(std::numeric_limits<T>::quiet_NaN())));
}

}  // namespace
