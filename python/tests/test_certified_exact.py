"""The certified mode's answers against exact rational arithmetic, and the conservative
mode's promises, on every hard-case strategy of every shape, float32 and float64: the
verdict exact, t_enter and t_exit faithful (the exact value or one of its two
neighbouring floats), the face exact (boxes); conservative never misses an exact hit and
its interval encloses the exact one."""

import numpy as np
import pytest
from hypothesis import given

import exact
import rayproof as rp
from rayproof import strategies as rs

DTYPES = [np.float64, np.float32]
SLAB = {"Aabb": exact.aabb_exact, "Obb": exact.obb_exact, "Plane": exact.plane_exact}


def check_certified_rational(case, want):
    hit = rp.intersect(case.ray, case.shape, rp.certified)
    assert rp.verdict(case.ray, case.shape, rp.certified) == hit.verdict
    if want is None:
        assert hit.verdict == rp.Verdict.miss, (case, hit)
        return
    assert hit.verdict == rp.Verdict.hit, (case, hit, want)
    enter, leave, face = want
    assert exact.faithful(hit.t_enter, enter, case.dtype), (case, hit, want)
    assert exact.faithful(hit.t_exit, leave, case.dtype), (case, hit, want)
    assert hit.face == face, (case, hit, want)


@pytest.mark.parametrize("dtype", DTYPES)
@pytest.mark.parametrize("shape", ["Aabb", "Obb", "Plane"])
def test_certified_is_exact_for_slabs_and_planes(shape, dtype):
    @given(rs.cases(shape, dtype))
    def check(case):
        check_certified_rational(case, SLAB[shape](case.ray, case.shape))

    check()


@pytest.mark.parametrize("dtype", DTYPES)
def test_certified_is_exact_for_spheres(dtype):
    @given(rs.cases("Sphere", dtype))
    def check(case):
        e = exact.SphereExact(case.ray, case.shape)
        hit = rp.intersect(case.ray, case.shape, rp.certified)
        assert rp.verdict(case.ray, case.shape, rp.certified) == hit.verdict
        assert hit.verdict == (rp.Verdict.hit if e.hits() else rp.Verdict.miss), (case, hit)
        if e.hits():
            assert exact.faithful_by(hit.t_enter, e.enter_cmp(), case.dtype), (case, hit)
            assert exact.faithful_by(hit.t_exit, e.exit_cmp(), case.dtype), (case, hit)
            assert hit.face == -1

    check()


@pytest.mark.parametrize("dtype", DTYPES)
@pytest.mark.parametrize("shape", ["Aabb", "Obb", "Plane"])
def test_conservative_encloses_the_exact_interval(shape, dtype):
    @given(rs.cases(shape, dtype))
    def check(case):
        want = SLAB[shape](case.ray, case.shape)
        hit = rp.intersect(case.ray, case.shape, rp.conservative)
        if want is not None:
            assert hit.verdict == rp.Verdict.hit, (case, hit, want)
            assert exact.q(hit.t_enter) <= want[0] and want[1] <= exact.q(hit.t_exit), (case, hit, want)

    check()


def test_an_exact_check_can_fail():
    # The checks above are not vacuous: a hit one ulp off its exact t, or a wrong face,
    # is refused.
    ray, box = rp.Ray([0, 0, 0], [3, 0, 0]), rp.Aabb([1, -1, -1], [2, 1, 1])
    want = exact.aabb_exact(ray, box)
    assert want == (exact.Fraction(1, 3), exact.Fraction(2, 3), 0)
    third = 1 / 3
    assert exact.faithful(third, want[0], np.float64)
    assert exact.faithful(np.nextafter(third, 1), want[0], np.float64) != exact.faithful(np.nextafter(third, 0),
                                                                                         want[0], np.float64)
    assert not exact.faithful(np.nextafter(np.nextafter(third, 1), 1), want[0], np.float64)
    assert not exact.faithful(third, want[0], np.float32)  # a double between float32 values
    with pytest.raises(AssertionError):
        check_certified_rational(rs.Case(ray, box, "hand"), (want[0], want[1], 1))
