"""Each strategy really produces its hard case, checked exactly (Fractions) on every
example: the grazing rays pass through a corner or an edge point at t_special, the
tangents are tangent, the in-plane rays lie in the plane, the parallel rays have their
zero components (and both signed zeros occur), the far-small spheres are tiny, far and
aimed at within a few ulps (and both verdicts occur), the extreme cases are extreme."""

import math

import numpy as np
import pytest
from hypothesis import find, given, settings

import exact
import rayproof as rp
from exact import Fraction, cross, dot, q, qv, sub
from rayproof import strategies as rs

DTYPES = [np.float64, np.float32]
# find() stops at the first example that satisfies it; this only bounds a search that fails.
SEARCH = settings(max_examples=2000)


def point_at(case, t):
    return [o + t * d for o, d in zip(qv(case.ray.origin), qv(case.ray.direction))]


def max_exponent(dtype):
    return 128 if np.dtype(dtype) == np.float32 else 1024


def min_exponent(dtype):  # the smallest normal is 2^(min_exponent - 1)
    return -125 if np.dtype(dtype) == np.float32 else -1021


@pytest.mark.parametrize("dtype", DTYPES)
def test_aabb_grazing_touches_a_corner_or_an_edge(dtype):
    @given(rs.aabb_grazing(dtype))
    def check(case):
        p = point_at(case, case.t_special)
        lo, hi = qv(case.shape.lo), qv(case.shape.hi)
        assert all(a <= x <= b for a, x, b in zip(lo, p, hi))
        assert sum(x == a or x == b for a, x, b in zip(lo, p, hi)) >= 2

    check()


@pytest.mark.parametrize("dtype", DTYPES)
def test_obb_grazing_touches_a_corner_or_an_edge(dtype):
    @given(rs.obb_grazing(dtype))
    def check(case):
        rel = sub(point_at(case, case.t_special), qv(case.shape.center))
        s = [abs(dot(rel, qv(case.shape.axes[:, i]))) for i in range(3)]
        h = qv(case.shape.half_extent)
        assert all(x <= y for x, y in zip(s, h))
        assert sum(x == y for x, y in zip(s, h)) >= 2

    check()


@pytest.mark.parametrize("dtype", DTYPES)
def test_sphere_tangent_is_exactly_tangent(dtype):
    @given(rs.sphere_tangent(dtype))
    def check(case):
        e = exact.SphereExact(case.ray, case.shape)
        assert e.disc == 0  # one double root
        assert -e.b / e.a == case.t_special

    check()


@pytest.mark.parametrize("dtype", DTYPES)
def test_plane_in_plane_lies_in_the_plane(dtype):
    @given(rs.plane_in_plane(dtype))
    def check(case):
        n = qv(case.shape.normal)
        assert dot(n, qv(case.ray.direction)) == 0
        assert dot(n, qv(case.ray.origin)) == q(case.shape.offset)

    check()


@pytest.mark.parametrize("dtype", DTYPES)
def test_parallel_strategies_are_parallel(dtype):
    @given(rs.aabb_parallel(dtype))
    def aabb(case):
        assert 1 <= sum(x == 0 for x in case.ray.direction) <= 2

    @given(rs.obb_parallel(dtype))
    def obb(case):
        d = qv(case.ray.direction)
        assert any(dot(d, qv(case.shape.axes[:, i])) == 0 for i in range(3))

    @given(rs.plane_parallel(dtype))
    def plane(case):
        assert dot(qv(case.shape.normal), qv(case.ray.direction)) == 0

    @given(rs.sphere_parallel(dtype))
    def sphere(case):
        assert sum(x == 0 for x in case.ray.direction) == 2

    for check in (aabb, obb, plane, sphere):
        check()
    # Both zeros occur, and the sign of the zero is kept through the binding.
    for sign in (1.0, -1.0):
        found = find(rs.aabb_parallel(dtype),
                     lambda c: any(x == 0 and math.copysign(1.0, x) == sign for x in c.ray.direction), settings=SEARCH)
        assert any(x == 0 and math.copysign(1.0, x) == sign for x in found.ray.direction)


@pytest.mark.parametrize("dtype", DTYPES)
def test_sphere_far_small_is_far_small_and_aimed_within_ulps(dtype):
    @given(rs.sphere_far_small(dtype))
    def check(case):
        c, o, d = qv(case.shape.center), qv(case.ray.origin), qv(case.ray.direction)
        far = max(abs(x) for x in c)
        assert far >= 2 ** 20
        assert q(case.shape.radius) <= far / 2 ** 10
        # The line's distance from the centre: |w x d| / |d|, w = c - o. d is w rounded,
        # one component moved by up to 3 ulps: off by at most 3.5 ulps per component,
        # an ulp taken at 2 * far, so dist^2 <= 13 ulp^2.
        ulp = Fraction(2) ** (math.frexp(float(2 * far))[1] - (24 if np.dtype(dtype) == np.float32 else 53))
        w = sub(c, o)
        cr = cross(w, d)
        assert dot(cr, cr) <= 13 * ulp * ulp * dot(d, d)

    check()
    # Hard in both directions: the aim decides, within ulps, whether it hits.
    for v in (rp.Verdict.hit, rp.Verdict.miss):
        found = find(rs.sphere_far_small(dtype), lambda c: rp.verdict(c.ray, c.shape, rp.certified) == v, settings=SEARCH)
        assert (rp.verdict(found.ray, found.shape, rp.certified) == rp.Verdict.hit) == exact.SphereExact(
            found.ray, found.shape).hits()


@pytest.mark.parametrize("dtype", DTYPES)
def test_extreme_strategies_reach_the_ends_of_the_range(dtype):
    # denormal sizes: at most 2^(min_exponent + 1), four times the smallest normal
    top, bottom = Fraction(2) ** (max_exponent(dtype) - 7), Fraction(2) ** (min_exponent(dtype) + 1)

    @given(rs.aabb_extreme(dtype))
    def aabb(case):
        lo, hi = qv(case.shape.lo), qv(case.shape.hi)
        size = max(b - a for a, b in zip(lo, hi))
        if case.kind == "aabb_extreme_huge":
            assert all(b - a >= top for a, b in zip(lo, hi))
        elif case.kind == "aabb_extreme_denormal":
            assert all(abs(x) <= bottom for x in lo + hi)
        elif case.kind == "aabb_extreme_tiny_far":
            far = max(abs(a + b) / 2 for a, b in zip(lo, hi))
            assert far >= 2 ** 19 and size <= far / 2 ** 6
        else:
            assert case.kind == "aabb_extreme_long_thin"
            sizes = sorted(b - a for a, b in zip(lo, hi))
            assert sizes[2] >= 2 ** 19 * sizes[1] > 0

    @given(rs.sphere_extreme(dtype))
    def sphere(case):
        r = q(case.shape.radius)
        if case.kind == "sphere_extreme_huge":
            assert r >= top
        else:
            assert case.kind == "sphere_extreme_denormal"
            assert 0 < r <= bottom and all(abs(x) <= bottom for x in qv(case.shape.center))

    aabb()
    sphere()


def test_a_strategy_check_can_fail():
    # A case that is not tangent is refused by the tangent check's relation.
    ray, sphere = rp.Ray([0, 1.5, 0], [1, 0, 0]), rp.Sphere([0, 0, 0], 1)
    assert exact.SphereExact(ray, sphere).disc != 0
    ray.origin = [0, 1, 0]
    assert exact.SphereExact(ray, sphere).disc == 0
