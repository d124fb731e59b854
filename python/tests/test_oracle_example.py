"""rayproof as the oracle of other geometry code: a textbook slab test written in plain
Python, property-tested against the certified mode on the grazing strategies. Hypothesis
finds where it is wrong (the test asserts that it does, and that the exact answer sides
with rayproof), and shrinks the case it reports."""

import math

import numpy as np
from hypothesis import find, settings
from hypothesis import strategies as st

import exact
import rayproof as rp
from rayproof import strategies as rs


def textbook_slab(origin, direction, lo, hi, t_min, t_max):
    """The slab test as textbooks write it: reciprocal direction, products, min and max."""
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        inv = 1.0 / np.asarray(direction, dtype=np.float64)
        t0 = (np.asarray(lo) - origin) * inv
        t1 = (np.asarray(hi) - origin) * inv
    enter = max(t_min, *np.minimum(t0, t1))
    leave = min(t_max, *np.maximum(t0, t1))
    return enter <= leave


def disagrees(case):
    r, b = case.ray, case.shape
    mine = textbook_slab(r.origin, r.direction, b.lo, b.hi, r.t_min, r.t_max)
    return mine != (rp.verdict(r, b, rp.certified) == rp.Verdict.hit)


def test_hypothesis_finds_the_textbook_slab_failing_on_grazing_rays():
    # What a user's property test would be:
    #     @given(st.one_of(rs.aabb_grazing(), rs.aabb_near_grazing(), rs.aabb_parallel()))
    #     def test_my_slab(case): assert not disagrees(case)
    # Here the search is run directly and must succeed.
    grazing = st.one_of(rs.aabb_grazing(), rs.aabb_near_grazing(), rs.aabb_parallel())
    case = find(grazing, disagrees, settings=settings(max_examples=2000))
    assert disagrees(case)
    # The exact answer sides with rayproof.
    want = exact.aabb_exact(case.ray, case.shape)
    assert (rp.verdict(case.ray, case.shape, rp.certified) == rp.Verdict.hit) == (want is not None)


def test_the_textbook_slab_is_right_on_plain_rays():
    # The failure is the hard cases' doing: on easy input the two agree.
    ray, box = rp.Ray([-4, 0.5, 0.25], [1, 0.01, 0]), rp.Aabb([-1, -1, -1], [1, 1, 1])
    assert not disagrees(rs.Case(ray, box, "plain"))
    assert textbook_slab(ray.origin, ray.direction, box.lo, box.hi, 0.0, math.inf)
