// ray_plane_props.cpp — RapidCheck properties of ray vs plane: rays lying exactly in the plane, exactly parallel rays off it, nearly parallel rays.
//
// Covered, for float and double, over every generator of the shape (see
// props_support.hpp): every mode answers invalid exactly for invalid inputs;
// conservative never misses an exact hit and encloses the exact interval; certified
// equals the exact oracle (verdict, face, faithfully rounded t); both of them again,
// against the oracle, on the case moved elsewhere in the exponent range by an exact
// power-of-two scaling; oracle-free invariants of certified under exact power-of-two
// scaling, axis permutation and ray reversal; a
// hit's interval is ordered; batch equals scalar bit for bit (also the certified lane
// path, in both SIMD backends); a PreparedRay's certified
// answer equals the Ray's bit for bit and its conservative answer meets the contract;
// for float, every conservative hit a hit of the double enclosure (the float stage adds
// no false hit); and the fast mode's wrong answers counted per generator (printed, not
// asserted).
#include "props_support.hpp"

RAYPROOF_PROPERTY_SUITE(PlaneProps, rayproof::Plane)

// The certified batch's lane path (detail/ray_plane_batch.hpp: the enclosure for float
// rays, the verdict filter for double rays) in both SIMD backends, against the scalar
// certified answer bit for bit (props_support.hpp, lane_batch_equals_scalar).
TYPED_TEST(PlaneProps, CertifiedLaneBatchEqualsScalar) {
    rayproof::props::lane_batch_equals_scalar<TypeParam, rayproof::Plane<TypeParam>>();
}

// Float input only: conservative mode's first stage computes the enclosure in float and
// answers where it lies inside [t_min, t_max] (a hit, exact then) or outside it; the rest
// goes to the enclosure in double. So every conservative hit is a hit of the double
// enclosure, on every case where that enclosure holds: a float stage that answered a
// straddling enclosure would add false hits near t_min and t_max. (For double input the
// double enclosure is the first stage: nothing to compare.)
TEST(PlaneFloatConservative, EveryHitIsAHitOfTheDoubleEnclosure) {
    using T = float;
    rayproof::props::run_cases<T, rayproof::Plane<T>>([](const auto& d, auto) -> std::optional<std::string> {
        namespace dt = rayproof::detail;
        const rayproof::Ray<T>& r = d.c.ray;
        const dt::PlaneEnclosure<double> e = dt::plane_enclosure(dt::plane_sums<double>(r, d.c.shape));
        if (!(e.ok && dt::valid_range(r))) return std::nullopt;
        const bool double_hit = dt::outward_to<T>(e.lo, e.hi, r.t_min, r.t_max).meets;
        const rayproof::Hit<T> h = rayproof::intersect(r, d.c.shape, rayproof::conservative);
        if (h.verdict != rayproof::Verdict::hit || double_hit) return std::nullopt;
        std::ostringstream os;
        os << "conservative " << h << ", the double enclosure [" << std::hexfloat << e.lo << ", " << e.hi
           << "] misses";
        return os.str();
    });
}
