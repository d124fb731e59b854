// ray_aabb_props.cpp — RapidCheck properties of ray vs axis-aligned box: slab entries, the lowest-axis face tie rule at edges and corners, ±0 directions.
//
// Covered, for float and double, over every generator of the shape (see
// props_support.hpp): every mode answers invalid exactly for invalid inputs;
// conservative never misses an exact hit and encloses the exact interval; certified
// equals the exact oracle (verdict, face, faithfully rounded t); both of them again,
// against the oracle, on the case moved elsewhere in the exponent range by an exact
// power-of-two scaling; oracle-free invariants of certified under exact power-of-two
// scaling, axis permutation and ray reversal; a
// hit's interval is ordered; batch equals scalar bit for bit; a PreparedRay's certified
// answer equals the Ray's bit for bit and its conservative answer meets the contract;
// and the fast mode's wrong answers counted per generator (printed, not asserted).
#include "props_support.hpp"

RAYPROOF_PROPERTY_SUITE(AabbProps, rayproof::Aabb)

// The certified batch's lane path (detail/ray_aabb_batch.hpp) in both SIMD backends,
// called directly (batch_of takes it only where it pays, so BatchEqualsScalar above may
// not reach it): for Ray and PreparedRay spans, intersect and verdict, each element
// equals the scalar certified answer bit for bit (which CertifiedEqualsOracle judges
// against the exact oracle). The batch is case i's ray followed by more rays of its
// generator (W to 4W + W - 1 of them, so that the case's ray and its neighbours fill
// whole blocks and a partial one; shrunk towards W), against case i's box.
#include <rayproof/detail/ray_aabb_batch.hpp>

namespace {
template <class B, class R, class T>
std::optional<std::string> lanes_equal_scalar(const std::vector<rayproof::Ray<T>>& in, const rayproof::Aabb<T>& box) {
    using namespace rayproof;
    std::vector<R> rs;
    for (const Ray<T>& r : in) rs.push_back(R(r));
    const auto prepared = detail::prepare(box);
    std::vector<Hit<T>> hits(rs.size());
    std::vector<Verdict> verdicts(rs.size());
    detail::batch::certified_lanes<B>(std::span<const R>(rs), prepared, std::span<Hit<T>>(hits));
    detail::batch::certified_lanes<B>(std::span<const R>(rs), prepared, std::span<Verdict>(verdicts));
    for (std::size_t i = 0; i < rs.size(); ++i) {
        const Hit<T> s = intersect(rs[i], box, certified);
        if (!props::identical(s, hits[i]) || verdicts[i] != s.verdict) {
            std::ostringstream os;
            os << (std::is_same_v<B, detail::simd::portable> ? "portable" : "native")
               << (detail::is_prepared_ray_v<R> ? " prepared" : " ray") << " element " << i << " of " << rs.size()
               << " " << in[i] << ": lanes " << hits[i] << " / " << verdicts[i] << ", scalar " << s;
            return os.str();
        }
    }
    return std::nullopt;
}
}  // namespace

TYPED_TEST(AabbProps, CertifiedLaneBatchEqualsScalar) {
    using T = TypeParam;
    using namespace rayproof;
    props::run_cases<T, Aabb<T>>([](const auto& d, auto pick) -> std::optional<std::string> {
        constexpr int W = detail::batch::kBatchLanes;
        const auto& g = gen::generators<T, Aabb<T>>()[d.plan->generator_of(d.index)];
        const auto n = std::size_t(pick(W + int(d.choice(props::kBatchSalt) % (4 * W)), W));
        gen::Rng rng(d.seed());
        const auto first = g.make(rng);  // == d.c
        std::vector<Ray<T>> rays{first.ray};
        while (rays.size() < n) rays.push_back(g.make(rng).ray);
        namespace simd = detail::simd;
        if (auto f = lanes_equal_scalar<simd::portable, Ray<T>>(rays, first.shape)) return f;
        if (auto f = lanes_equal_scalar<simd::native, Ray<T>>(rays, first.shape)) return f;
        if (auto f = lanes_equal_scalar<simd::portable, PreparedRay<T>>(rays, first.shape)) return f;
        return lanes_equal_scalar<simd::native, PreparedRay<T>>(rays, first.shape);
    });
}
