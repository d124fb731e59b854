// ray_obb_props.cpp — RapidCheck properties of ray vs oriented box with integer, non-normalized, rotated and sheared axes, nearly dependent axes.
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
// for float, every conservative hit a hit of the double enclosure (the float stage adds
// no false hit); and the fast mode's wrong answers counted per generator (printed, not
// asserted).
#include "props_support.hpp"

RAYPROOF_PROPERTY_SUITE(ObbProps, rayproof::Obb)

// Float input only: conservative mode's first stage computes the frame and the slab values
// in float and answers a miss where its entry bound exceeds its exit bound, a hit where
// they lie 5·E_max apart or more (an exact hit then); the rest goes to the double
// enclosure. So every conservative hit is a hit of the double enclosure, on every valid
// case where that enclosure holds: a float stage that answered near a graze would add
// false hits. (For double input the double enclosure is the first stage.)
TEST(ObbFloatConservative, EveryHitIsAHitOfTheDoubleEnclosure) {
    using T = float;
    rayproof::props::run_cases<T, rayproof::Obb<T>>([](const auto& d, auto) -> std::optional<std::string> {
        namespace dt = rayproof::detail;
        const rayproof::Hit<T> h = rayproof::intersect(d.c.ray, d.c.shape, rayproof::conservative);
        if (h.verdict != rayproof::Verdict::hit) return std::nullopt;
        const dt::ObbEnclosure<double> e = dt::obb_enclosure<double>(d.c.ray, d.c.shape);
        if (!e.ok || e.lo <= e.hi) return std::nullopt;
        std::ostringstream os;
        os << "conservative " << h << ", the double enclosure [" << std::hexfloat << e.lo << ", " << e.hi
           << "] misses";
        return os.str();
    });
}
