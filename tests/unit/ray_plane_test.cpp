// Ray vs Plane, hand-computed answers, over float and double and every mode the kernel
// has. Covers: a perpendicular crossing, a non-unit normal (same plane), an oblique
// normal, a ray lying in the plane (hit on its whole range, t_min = -inf included), a
// parallel ray off the plane, crossings exactly at t_min and t_max and one ulp outside,
// a crossing behind the origin (miss, then hit with t_min = -inf); for double, the
// certified verdict and full query where the limit times the computed denominator
// overflows while the crossing lies a few percent from the limit (a miss and a hit),
// its t checked faithful against the exact rational N/D (GMP).
#include "unit_support.hpp"

#include <gmpxx.h>

#include <cmath>
#include <limits>

using namespace rayproof;
using namespace rayproof::testing;

template <class T> class RayPlane : public ::testing::Test {};
using Scalars = ::testing::Types<float, double>;
TYPED_TEST_SUITE(RayPlane, Scalars);

TYPED_TEST(RayPlane, Crossings) {
    using T = TypeParam;
    const Plane<T> floor{v<T>(0, 1, 0), -1};
    check(Ray<T>{v<T>(0, 3, 0), v<T>(0, -1, 0)}, floor, hit<T>(4, 4));
    check(Ray<T>{v<T>(0, 3, 0), v<T>(0, -2, 0)}, floor, hit<T>(2, 2));
    check(Ray<T>{v<T>(0, 3, 0), v<T>(0, -1, 0)}, Plane<T>{v<T>(0, 2, 0), -2}, hit<T>(4, 4));
    check(Ray<T>{v<T>(0, -3, 0), v<T>(5, 1, 7)}, floor, hit<T>(2, 2));   // from below
    check(Ray<T>{v<T>(0, 0, 0), v<T>(1, 0, 0)}, Plane<T>{v<T>(1, 1, 1), 3}, hit<T>(3, 3));
    check(Ray<T>{v<T>(0, 3, 0), v<T>(0, 1, 0)}, floor, miss<T>());        // moving away
    const T inf = std::numeric_limits<T>::infinity();
    check(Ray<T>{v<T>(0, 3, 0), v<T>(0, 1, 0), -inf, inf}, floor, hit<T>(-4, -4));
}

TYPED_TEST(RayPlane, ParallelInAndOffThePlane) {
    using T = TypeParam;
    const T inf = std::numeric_limits<T>::infinity();
    const Plane<T> floor{v<T>(0, 1, 0), -1};
    check(Ray<T>{v<T>(0, -1, 0), v<T>(1, 0, 1)}, floor, hit<T>(0, inf));
    check(Ray<T>{v<T>(0, -1, 0), v<T>(1, -0.0, 1), -2, 7}, floor, hit<T>(-2, 7));
    check(Ray<T>{v<T>(0, -1, 0), v<T>(1, 0, 1), -inf, inf}, floor, hit<T>(-inf, inf));
    check(Ray<T>{v<T>(0, 0, 0), v<T>(1, 0, 0)}, floor, miss<T>());
    check(Ray<T>{v<T>(0, std::nextafter(T(-1), T(0)), 0), v<T>(1, 0, 0)}, floor, miss<T>());
    // oblique plane x + y + z = 3, direction in it: (1,-1,0)
    check(Ray<T>{v<T>(1, 1, 1), v<T>(1, -1, 0), -1, 1}, Plane<T>{v<T>(1, 1, 1), 3}, hit<T>(-1, 1));
}

TYPED_TEST(RayPlane, ClippingByTminTmax) {
    using T = TypeParam;
    const Plane<T> floor{v<T>(0, 1, 0), -1};
    const Vec3<T> o = v<T>(0, 3, 0), d = v<T>(0, -1, 0);  // crossing at t = 4
    check(Ray<T>{o, d, 0, 4}, floor, hit<T>(4, 4));
    check(Ray<T>{o, d, 4, 9}, floor, hit<T>(4, 4));
    check(Ray<T>{o, d, 4, 4}, floor, hit<T>(4, 4));
    check(Ray<T>{o, d, 0, std::nextafter(T(4), T(0))}, floor, miss<T>());
    check(Ray<T>{o, d, std::nextafter(T(4), T(5)), 9}, floor, miss<T>());
}

// t_min·D~ overflows while t = N/D lies 2.6% beyond t_min (a miss) or 2.3% inside it (a
// hit), with D = n·d computed with cancellation (terms 2^78, the sum about 9·2^26, 5%
// off): the verdict filter's bound says nothing about an overflowed product, so neither
// query may answer from it. Double only: float inputs cannot overflow a product in
// double.
TEST(RayPlaneExtreme, CertifiedWhenTheLimitTimesTheDenominatorOverflows) {
    const double inf = std::numeric_limits<double>::infinity();
    const double d_computed = std::ldexp(9.0, 26);                     // fl(fl(2^78 + d_1) - 2^78)
    const double t_min = -1.01 * std::ldexp(1.0, 1024 - 26) / 9.0;     // |t_min|·D~ = 1.01·2^1024
    const Plane<double> plane{v<double>(1, 1, 1), 0.97 * t_min * d_computed};  // N~/D~ = 0.97 t_min
    for (const double d1 : {std::ldexp(9 - 0.49, 26), std::ldexp(9 + 0.49, 26)}) {
        const Ray<double> ray{v<double>(0, 0, 0), Vec3<double>(std::ldexp(1.0, 78), d1, -std::ldexp(1.0, 78)), t_min, inf};
        const double t = plane.offset / d1;  // N/D, within one rounding: far from the 2% margins
        const bool inside = t >= t_min;
        ASSERT_EQ(inside, d1 > d_computed) << repro(ray, plane);
        const Verdict expect = inside ? Verdict::hit : Verdict::miss;
        EXPECT_EQ(verdict(ray, plane, certified), expect) << repro(ray, plane);
        const Hit<double> h = intersect(ray, plane, certified);
        EXPECT_EQ(h.verdict, expect) << repro(ray, plane) << ' ' << h;
        if (inside) {  // the exact crossing N/D, N = offset - n·o, D = n·d (GMP rationals)
            mpq_class num(plane.offset), den(0);
            for (int i = 0; i < 3; ++i) {
                num -= mpq_class(plane.normal[i]) * mpq_class(ray.origin[i]);
                den += mpq_class(plane.normal[i]) * mpq_class(ray.direction[i]);
            }
            const mpq_class exact_t = num / den;
            EXPECT_TRUE(is_faithful(h.t_enter, minus_rational(exact_t))) << "t_enter: " << h;
            EXPECT_TRUE(is_faithful(h.t_exit, minus_rational(exact_t))) << "t_exit: " << h;
        }
    }
}
