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
// against the scalar certified answer bit for bit (props_support.hpp,
// lane_batch_equals_scalar).
TYPED_TEST(AabbProps, CertifiedLaneBatchEqualsScalar) {
    rayproof::props::lane_batch_equals_scalar<TypeParam, rayproof::Aabb<TypeParam>>();
}
