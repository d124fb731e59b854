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
// and the fast mode's wrong answers counted per generator (printed, not asserted).
#include "props_support.hpp"

RAYPROOF_PROPERTY_SUITE(PlaneProps, rayproof::Plane)

// The certified batch's lane path (detail/ray_plane_batch.hpp: the enclosure for float
// rays, the verdict filter for double rays) in both SIMD backends, against the scalar
// certified answer bit for bit (props_support.hpp, lane_batch_equals_scalar).
TYPED_TEST(PlaneProps, CertifiedLaneBatchEqualsScalar) {
    rayproof::props::lane_batch_equals_scalar<TypeParam, rayproof::Plane<TypeParam>>();
}
