"""Hypothesis strategies for the hard cases of ray intersection, with rayproof as the
oracle that judges other geometry code.

Each strategy draws a Case (ray, shape, kind, t_special) for one float type (float64 by
default, float32 with dtype=np.float32). The constructions follow the C++ case
generators of the project's suites: small integer geometry in which the special point
(a corner touched, a tangent, a ray lying in a plane) is exact, moved by an exactly
representable translation, its signed zeros chosen, and rescaled by exact powers of
two, so the special geometry survives in the float type at every magnitude. Everything
is drawn from Hypothesis primitives, so a failing case shrinks (towards small integers,
no translation, no scaling, [0, inf)).

    from hypothesis import given
    from rayproof import strategies as rs

    @given(rs.aabb_grazing())
    def test_my_slab(case):
        assert my_slab(case.ray, case.shape) == bool(rp.verdict(case.ray, case.shape, rp.certified) == rp.Verdict.hit)

The hard cases: aabb_grazing / obb_grazing (the ray through a corner or an edge
point), aabb_near_grazing (the same a ulp away), aabb_parallel / obb_parallel /
plane_parallel / sphere_parallel (direction components +0 and -0, or d exactly
perpendicular to an axis), plane_in_plane (the ray lies in the plane), sphere_tangent /
sphere_near_tangent, sphere_far_small (a tiny sphere far away aimed at within a few
ulps), aabb_extreme / sphere_extreme (magnitudes near overflow, denormal sizes, tiny
and far, long and thin), and the general_* strategies; cases(shape) mixes them all.
"""

import dataclasses
import fractions
import math
from typing import Optional

import numpy as np
from hypothesis import strategies as st

from . import types as _types

__all__ = [
    "Case", "cases", "finite_floats",
    "general_aabb", "general_obb", "general_plane", "general_sphere",
    "aabb_grazing", "aabb_near_grazing", "aabb_parallel", "aabb_extreme",
    "obb_grazing", "obb_parallel",
    "plane_in_plane", "plane_parallel",
    "sphere_tangent", "sphere_near_tangent", "sphere_parallel", "sphere_far_small", "sphere_extreme",
]


@dataclasses.dataclass
class Case:
    """One drawn input: the ray and the shape (rayproof objects of one float type), the
    strategy's name for it and, for a constructed case, the exact parameter of its
    special point (the corner or edge point touched, the tangent point, the point in the
    plane) as a Fraction."""

    ray: object
    shape: object
    kind: str
    t_special: Optional[fractions.Fraction] = None

    @property
    def dtype(self):
        return np.dtype(self.shape.dtype)


# ---------------------------------------------------------------------------------
# Floating-point structure.


def _info(dtype):
    dt = np.dtype(dtype)
    if dt == np.float32:
        return dt, 24, 128, -125  # precision, max_exponent, min_exponent (C's FLT_MAX_EXP, FLT_MIN_EXP)
    if dt == np.float64:
        return dt, 53, 1024, -1021
    raise TypeError(f"rayproof answers float32 and float64, not {dt}")


def _fits(x, dtype):
    """x (a Python float or int) is exactly a finite value of dtype."""
    dt = np.dtype(dtype)
    if isinstance(x, int):
        if abs(x) > 2 ** 62:
            return False
        x_f = float(x)
        if x_f != x:
            return False
        x = x_f
    if not math.isfinite(x):
        return False
    if dt == np.float64:
        return True
    return abs(x) <= float(np.finfo(np.float32).max) and float(np.float32(x)) == x


def _round(x, dtype):
    """x rounded to nearest in dtype, as a Python float."""
    with np.errstate(over="ignore"):
        return float(np.dtype(dtype).type(x))


def _step(x, dtype, up):
    dt = np.dtype(dtype)
    return float(np.nextafter(dt.type(x), dt.type(math.inf if up else -math.inf)))


def _nudge(x, dtype, steps):
    for _ in range(abs(steps)):
        x = _step(x, dtype, steps > 0)
    return x


def finite_floats(dtype=np.float64, **kwargs):
    """Every finite value of dtype (both zeros and the denormals included)."""
    dt, *_ = _info(dtype)
    return st.floats(allow_nan=False, allow_infinity=False, width=8 * dt.itemsize, **kwargs)


def _uniform(dtype, lo, hi):
    dt, *_ = _info(dtype)
    return st.floats(lo, hi, width=8 * dt.itemsize)


@st.composite
def _magnitude(draw, dtype, lo_exp, hi_exp, signed=True):
    """A value of dtype with a random mantissa in [1, 2) times 2^e, e in [lo_exp, hi_exp]."""
    m = draw(st.floats(1, 2, exclude_max=True))
    x = _round(math.ldexp(m, draw(st.integers(lo_exp, hi_exp))), dtype)
    if math.isinf(x):  # rounded up past the largest finite value
        x = float(np.finfo(np.dtype(dtype)).max)
    return -x if signed and draw(st.booleans()) else x


# ---------------------------------------------------------------------------------
# Exact integer geometry.


def _i3(lo, hi):
    return st.tuples(st.integers(lo, hi), st.integers(lo, hi), st.integers(lo, hi)).map(list)


def _nonzero_i3(r):
    return _i3(-r, r).filter(any)


def _add(a, b):
    return [x + y for x, y in zip(a, b)]


def _sub(a, b):
    return [x - y for x, y in zip(a, b)]


def _mul(s, a):
    return [s * x for x in a]


def _dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def _cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def _signed_int(lo, hi):
    return st.tuples(st.integers(lo, hi), st.booleans()).map(lambda p: -p[0] if p[1] else p[0])


@st.composite
def _translation(draw, dtype):
    """Zero (where it shrinks to), or up to 2^(precision - 10) per coordinate: far from
    the origin with every sum of the small integers exact."""
    _, p, *_ = _info(dtype)
    if not draw(st.booleans()):
        return [0, 0, 0]
    out = []
    for _ in range(3):
        m = 2 ** draw(st.integers(0, p - 10))
        out.append(draw(st.integers(-m, m)))
    return out


@st.composite
def _with_signed_zeros(draw, v):
    """The integer vector as floats, each zero +0 or -0."""
    return [(-0.0 if draw(st.booleans()) else 0.0) if x == 0 else float(x) for x in v]


@st.composite
def _pythagorean_quadruple(draw, r=4):
    """(a, b, c), n with a^2 + b^2 + c^2 == n^2, n > 0 (Carmichael's parametrization)."""
    m, n, p, q = draw(st.tuples(*[st.integers(-r, r)] * 4).filter(any))
    return [m * m + n * n - p * p - q * q, 2 * (m * q + n * p), 2 * (n * q - m * p)], m * m + n * n + p * p + q * q


@st.composite
def _integer_rotation(draw, r=3):
    """Orthogonal integer columns of equal norm (an integer quaternion's rotation times its norm)."""
    w, x, y, z = draw(st.tuples(*[st.integers(-r, r)] * 4).filter(any))
    return [
        [w * w + x * x - y * y - z * z, 2 * (x * y + w * z), 2 * (x * z - w * y)],
        [2 * (x * y - w * z), w * w - x * x + y * y - z * z, 2 * (y * z + w * x)],
        [2 * (x * z + w * y), 2 * (y * z - w * x), w * w - x * x - y * y + z * z],
    ]


@st.composite
def _integer_axes(draw):
    """Three integer box axes (columns) with det != 0: a permuted scaled identity, a
    scaled integer rotation, or a sheared integer matrix."""
    while True:
        kind = draw(st.sampled_from(["identity", "rotation", "sheared"]))
        if kind == "identity":
            perm = draw(st.permutations([0, 1, 2]))
            cols = []
            for i in range(3):
                col = [0, 0, 0]
                col[perm[i]] = draw(_signed_int(1, 4))
                cols.append(col)
        elif kind == "rotation":
            cols = [_mul(draw(_signed_int(1, 3)), c) for c in draw(_integer_rotation())]
        else:
            cols = [draw(_i3(-4, 4)) for _ in range(3)]
        if _dot(cols[0], _cross(cols[1], cols[2])) != 0:
            return cols


# ---------------------------------------------------------------------------------
# Ranges and cases.


@st.composite
def _special_t_range(draw, s):
    """[0, inf), or a range with the special parameter s at an end: [s, inf), [-inf, s],
    [s, s], [min(0, s), max(0, s)], or the whole line."""
    kind = draw(st.sampled_from(["zero_inf", "from_s", "to_s", "at_s", "zero_to_s", "line"]))
    return {
        "zero_inf": (0.0, math.inf),
        "from_s": (s, math.inf),
        "to_s": (-math.inf, s),
        "at_s": (s, s),
        "zero_to_s": (min(0.0, s), max(0.0, s)),
        "line": (-math.inf, math.inf),
    }[kind]


@st.composite
def _random_t_range(draw, dtype, scale):
    kind = draw(st.sampled_from(["zero_inf", "line", "zero_b", "a_b"]))
    if kind == "zero_inf":
        return 0.0, math.inf
    if kind == "line":
        return -math.inf, math.inf
    if kind == "zero_b":
        return 0.0, draw(_uniform(dtype, 0, scale))
    a, b = sorted([draw(_uniform(dtype, -scale, scale)), draw(_uniform(dtype, -scale, scale))])
    return a, b


# Each shape's fields and how they scale: "p" positions (2^kp), "a" the shape's own
# vectors (2^ka), "pa" products of the two (2^(kp + ka)).
_FIELDS = {
    "Aabb": (("lo", "p"), ("hi", "p")),
    "Obb": (("center", "p"), ("axes", "a"), ("half_extent", "pa")),
    "Plane": (("normal", "a"), ("offset", "pa")),
    "Sphere": (("center", "p"), ("radius", "p")),
}


def _scaled(x, k, dtype):
    """x * 2^k when that is exact in dtype (inf stays), else None."""
    if isinstance(x, list):
        out = [_scaled(v, k, dtype) for v in x]
        return None if any(v is None for v in out) else out
    if math.isinf(x):
        return x
    try:
        y = math.ldexp(x, k)
    except OverflowError:
        return None
    return y if _fits(y, dtype) and math.ldexp(y, -k) == x else None


def _scale(raw, shape_name, dtype, kp, kd, ka):
    """The raw case with positions times 2^kp, the direction 2^kd, the shape's vectors 2^ka
    and t_min, t_max (and the special t) 2^(kp - kd): the same points, exactly; or None
    when some number would not be exact."""
    k = {"p": kp, "a": ka, "pa": kp + ka}
    out = {"o": _scaled(raw["o"], kp, dtype), "d": _scaled(raw["d"], kd, dtype),
           "t_min": _scaled(raw["t_min"], kp - kd, dtype), "t_max": _scaled(raw["t_max"], kp - kd, dtype)}
    for name, role in _FIELDS[shape_name]:
        out[name] = _scaled(raw[name], k[role], dtype)
    if any(v is None for v in out.values()):
        return None
    out["t_special"] = None if raw.get("t_special") is None else raw["t_special"] * fractions.Fraction(2) ** (kp - kd)
    return out


@st.composite
def _exact_scaling(draw, raw, shape_name, dtype):
    """Half the time unchanged; otherwise an exact power-of-two rescaling anywhere in the
    exponent range (halving the exponents until it is exact)."""
    _, p, max_exp, min_exp = _info(dtype)
    if not draw(st.booleans()):
        return raw
    e = max_exp - min_exp + p
    kp = draw(st.integers(-e // 2, e // 2))
    kd = kp if draw(st.booleans()) else draw(st.integers(-e // 2, e // 2))
    ka = draw(st.integers(-e // 4, e // 4))
    for _ in range(8):
        out = _scale(raw, shape_name, dtype, kp, kd, ka)
        if out is not None:
            return out
        kp, kd, ka = int(kp / 2), int(kd / 2), int(ka / 2)
    return raw


def _make(raw, shape_name, dtype, kind):
    """The Case of rayproof objects from raw Python numbers (each exact in dtype)."""
    t = _types(dtype)
    ray = t.Ray(raw["o"], raw["d"], raw["t_min"], raw["t_max"])
    if shape_name == "Obb":
        shape = t.Obb(raw["center"], np.array(raw["axes"], dtype=np.dtype(dtype)).T, raw["half_extent"])
    else:
        shape = getattr(t, shape_name)(*[raw[name] for name, _ in _FIELDS[shape_name]])
    return Case(ray, shape, kind, raw.get("t_special"))


def _exact_ints(raw, names, dtype):
    """Every integer listed is exact in dtype; converts them to floats in place."""
    for name in names:
        v = raw[name]
        vals = [x for col in v for x in (col if isinstance(col, list) else [col])] if isinstance(v, list) else [v]
        if not all(_fits(x, dtype) for x in vals if isinstance(x, int)):
            return False
        if isinstance(v, list):
            raw[name] = [[float(x) for x in c] if isinstance(c, list) else float(c) for c in v]
        else:
            raw[name] = float(v)
    return True


@st.composite
def _constructed(draw, build, shape_name, dtype, kind):
    """build(draw) -> a raw case of integers (or None to draw again), made exact floats,
    then rescaled exactly."""
    while True:
        raw = build(draw)
        if raw is None:
            continue
        names = ["o"] + [name for name, _ in _FIELDS[shape_name]]
        if not _exact_ints(raw, names, dtype):
            continue
        raw = draw(_exact_scaling(raw, shape_name, dtype))
        return _make(raw, shape_name, dtype, kind)


# ---------------------------------------------------------------------------------
# Aabb.


def _integer_box(draw):
    """Even coordinates in [-16, 16], extents 0 (a flat axis) to 16."""
    lo, hi = [], []
    for _ in range(3):
        a = 2 * draw(st.integers(-8, 8))
        lo.append(a)
        hi.append(a + 2 * draw(st.integers(0, 8)))
    return lo, hi


def _box_coord(draw, lo, hi, i, where):
    """On axis i: lo, hi, or an odd integer strictly inside (lo on a flat axis)."""
    if where == 0:
        return lo[i]
    if where == 1:
        return hi[i]
    if hi[i] == lo[i]:
        return lo[i]
    return lo[i] + 1 + 2 * draw(st.integers(0, (hi[i] - lo[i]) // 2 - 1))


def _aabb_raw(draw, lo, hi, origin, d, dtype):
    tau = draw(_translation(dtype))
    return {"lo": _add(lo, tau), "hi": _add(hi, tau), "o": _add(origin, tau), "d": draw(_with_signed_zeros(d))}


def aabb_grazing(dtype=np.float64):
    """The ray passes exactly through a corner or an edge point of the box at the exact
    parameter t_special (touching it only, or entering there), t_min or t_max sometimes
    exactly there."""

    def build(draw):
        lo, hi = _integer_box(draw)
        free_axis = draw(st.sampled_from([-1, 0, 1, 2]))  # -1: a corner
        p = [_box_coord(draw, lo, hi, i, 2 if i == free_axis else draw(st.integers(0, 1))) for i in range(3)]
        d = draw(_nonzero_i3(8))
        s = draw(st.integers(0, 8))
        raw = _aabb_raw(draw, lo, hi, _sub(p, _mul(s, d)), d, dtype)
        raw["t_min"], raw["t_max"] = draw(_special_t_range(float(s)))
        raw["t_special"] = fractions.Fraction(s)
        return raw

    return _constructed(build, "Aabb", dtype, "aabb_grazing")


@st.composite
def _nudged(draw, case_strategy, dtype, kind, fields):
    """A case of case_strategy with one number of the ray moved by one ulp either way."""
    case = draw(case_strategy)
    ray = case.ray
    field = draw(st.sampled_from(fields))
    i = draw(st.integers(0, 2))
    v = [float(x) for x in getattr(ray, field)]
    v[i] = _step(v[i], dtype, draw(st.booleans()))
    if not any(v):
        v[i] = float(np.finfo(np.dtype(dtype)).smallest_subnormal)
    setattr(ray, field, v)
    return Case(ray, case.shape, kind, None)


def aabb_near_grazing(dtype=np.float64):
    """aabb_grazing with one direction component (or one origin coordinate) moved by one
    ulp: a hair off the corner or edge."""
    return _nudged(aabb_grazing(dtype), dtype, "aabb_near_grazing", ["direction", "direction", "direction", "origin"])


def aabb_parallel(dtype=np.float64):
    """Direction components +0 and -0 on one or two axes, the origin strictly inside,
    outside or exactly on a slab plane of each; the other axes aimed at the box."""

    def build(draw):
        lo, hi = _integer_box(draw)
        mask = draw(st.integers(1, 6))  # one or two axes parallel, never three
        s = draw(st.integers(1, 8))
        o, d = [0, 0, 0], [0, 0, 0]
        for i in range(3):
            if mask & (1 << i):
                where = draw(st.integers(0, 3))
                if where < 3:
                    o[i] = _box_coord(draw, lo, hi, i, where)
                else:
                    o[i] = lo[i] - draw(st.integers(1, 4)) if draw(st.booleans()) else hi[i] + draw(st.integers(1, 4))
            else:
                d[i] = draw(_signed_int(1, 8))
                o[i] = _box_coord(draw, lo, hi, i, draw(st.integers(0, 2))) - s * d[i]
        raw = _aabb_raw(draw, lo, hi, o, d, dtype)
        raw["t_min"], raw["t_max"] = draw(_random_t_range(dtype, 16))
        return raw

    return _constructed(build, "Aabb", dtype, "aabb_parallel")


@st.composite
def aabb_extreme(draw, dtype=np.float64):
    """A tiny box far from the origin aimed at within a few ulps (kind
    aabb_extreme_tiny_far), a huge box near the overflow threshold (_huge), a box of
    denormal size (_denormal), a long thin box with the ray nearly along it (_long_thin)."""
    dt, p, max_exp, min_exp = _info(dtype)
    fmax = float(np.finfo(dt).max)
    kind = draw(st.sampled_from(["tiny_far", "huge", "denormal", "long_thin"]))
    lo, hi, o, d = [0.0] * 3, [0.0] * 3, [0.0] * 3, [0.0] * 3
    if kind == "tiny_far":
        center = [draw(_magnitude(dt, 20, max_exp - 8)) for _ in range(3)]
        size = _round(math.ldexp(max(abs(c) for c in center), -draw(st.integers(8, p + 24))), dt)
        for i in range(3):
            h = _round(size * draw(st.floats(0, 1)), dt)
            lo[i], hi[i] = _round(center[i] - h, dt), _round(center[i] + h, dt)
            o[i] = draw(_uniform(dt, -1, 1))
        d = [_round(center[i] - o[i], dt) for i in range(3)]
        j = draw(st.integers(0, 2))
        d[j] = _nudge(d[j], dt, draw(st.integers(-3, 3)))
    elif kind == "huge":
        for i in range(3):
            lo[i] = -draw(_magnitude(dt, max_exp - 6, max_exp - 1, signed=False))
            hi[i] = draw(_magnitude(dt, max_exp - 6, max_exp - 1, signed=False))
            o[i] = draw(finite_floats(dt)) if draw(st.booleans()) else (fmax if draw(st.booleans()) else -fmax)
        d = draw(st.lists(finite_floats(dt), min_size=3, max_size=3).filter(any))
    elif kind == "denormal":
        for i in range(3):
            a, b = sorted([draw(_magnitude(dt, min_exp - p, min_exp)), draw(_magnitude(dt, min_exp - p, min_exp))])
            lo[i], hi[i] = a, b
            o[i] = draw(_magnitude(dt, min_exp - p, min_exp + 3))
        d = draw(st.lists(finite_floats(dt), min_size=3, max_size=3).filter(any))
    else:
        a = draw(st.integers(0, 2))
        for i in range(3):
            h = draw(_magnitude(dt, 20, max_exp - 8, signed=False) if i == a else _magnitude(dt, -30, 0, signed=False))
            lo[i], hi[i] = -h, h
            o[i] = -2.0 * h if i == a else draw(_uniform(dt, -2, 2))
            d[i] = 1.0 if i == a else draw(_magnitude(dt, -60, -10))
    if not any(d):
        d = [1.0, 0.0, 0.0]
    t_min = -math.inf if draw(st.booleans()) else 0.0
    raw = {"lo": lo, "hi": hi, "o": o, "d": d, "t_min": t_min, "t_max": math.inf}
    return _make(raw, "Aabb", dt, "aabb_extreme_" + kind)


@st.composite
def general_aabb(draw, dtype=np.float64):
    """A box in [-8, 8]^3 and an origin in [-16, 16]^3 aimed near it."""
    dt = np.dtype(dtype)
    lo, hi, o, target = [], [], [], []
    for _ in range(3):
        a, b = sorted([draw(_uniform(dt, -8, 8)), draw(_uniform(dt, -8, 8))])
        lo.append(a)
        hi.append(b)
        o.append(draw(_uniform(dt, -16, 16)))
        target.append(_round(a - 1 + (b - a + 2) * draw(st.floats(0, 1)), dt))
    d = [_round(target[i] - o[i], dt) for i in range(3)]
    if not any(d):
        d = [1.0, 0.0, 0.0]
    t_min, t_max = draw(_random_t_range(dt, 64))
    return _make({"lo": lo, "hi": hi, "o": o, "d": d, "t_min": t_min, "t_max": t_max}, "Aabb", dt, "general_aabb")


# ---------------------------------------------------------------------------------
# Obb.


def _half_extents_through(draw, axes, v, on_mask):
    """Half extents putting center + v exactly on the planes of the axes in on_mask and
    strictly inside the other slabs."""
    h = []
    for i in range(3):
        k = abs(_dot(v, axes[i]))
        h.append(k if on_mask & (1 << i) else k + draw(st.integers(1, 6)))
    return h


def _obb_raw(draw, axes, center, h, origin, d, dtype):
    tau = draw(_translation(dtype))
    return {"center": _add(center, tau), "axes": axes, "half_extent": h, "o": _add(origin, tau),
            "d": draw(_with_signed_zeros(d))}


def obb_grazing(dtype=np.float64):
    """The ray passes exactly through a corner or an edge point of an Obb with integer
    (rotated, non-normalized or sheared) axes at the exact parameter t_special."""

    def build(draw):
        axes = draw(_integer_axes())
        center = draw(_i3(-8, 8))
        v = draw(_nonzero_i3(6))
        mask = draw(st.sampled_from([7, 6, 5, 3]))  # a corner, or an edge (one axis free)
        h = _half_extents_through(draw, axes, v, mask)
        d = draw(_nonzero_i3(8))
        s = draw(st.integers(0, 8))
        raw = _obb_raw(draw, axes, center, h, _sub(_add(center, v), _mul(s, d)), d, dtype)
        raw["t_min"], raw["t_max"] = draw(_special_t_range(float(s)))
        raw["t_special"] = fractions.Fraction(s)
        return raw

    return _constructed(build, "Obb", dtype, "obb_grazing")


def obb_parallel(dtype=np.float64):
    """Directions exactly perpendicular to one box axis (d = a_i x w), the origin exactly
    on that slab's plane, strictly inside or outside it."""

    def build(draw):
        axes = draw(_integer_axes())
        i = draw(st.integers(0, 2))
        w = draw(_nonzero_i3(4)) if draw(st.booleans()) else axes[(i + draw(st.integers(1, 2))) % 3]
        d = _cross(axes[i], w)
        if not any(d):
            return None
        center = draw(_i3(-8, 8))
        v = draw(_nonzero_i3(6))
        h = _half_extents_through(draw, axes, v, 0)
        k = abs(_dot(v, axes[i]))
        where = draw(st.sampled_from(["on", "inside", "outside"]))
        h[i] = k if where == "on" else k + draw(st.integers(1, 6)) if where == "inside" else (
            draw(st.integers(0, k - 1)) if k > 0 else k)
        s = draw(st.integers(0, 4))
        raw = _obb_raw(draw, axes, center, h, _sub(_add(center, v), _mul(s, d)), d, dtype)
        raw["t_min"], raw["t_max"] = draw(_random_t_range(dtype, 8))
        return raw

    return _constructed(build, "Obb", dtype, "obb_parallel")


@st.composite
def general_obb(draw, dtype=np.float64):
    """An Obb with integer axes (rotated, sheared or permuted), an origin aimed near it."""
    dt = np.dtype(dtype)
    axes = draw(_integer_axes())
    center = [float(x) for x in draw(_i3(-8, 8))]
    h = [draw(_uniform(dt, 0, 16)) for _ in range(3)]
    o = [draw(_uniform(dt, -32, 32)) for _ in range(3)]
    d = [_round(center[i] + draw(_uniform(dt, -4, 4)) - o[i], dt) for i in range(3)]
    if not any(d):
        d = [0.0, 0.0, 1.0]
    t_min, t_max = draw(_random_t_range(dt, 8))
    raw = {"center": center, "axes": [[float(x) for x in c] for c in axes], "half_extent": h, "o": o, "d": d,
           "t_min": t_min, "t_max": t_max}
    return _make(raw, "Obb", dt, "general_obb")


# ---------------------------------------------------------------------------------
# Plane.


def _plane_raw(draw, n, point, origin, d, shift, dtype):
    tau = draw(_translation(dtype))
    point = _add(point, tau)
    return {"normal": draw(_with_signed_zeros(n)), "offset": _dot(n, point) + shift,
            "o": _add(origin, tau), "d": draw(_with_signed_zeros(d))}


def plane_in_plane(dtype=np.float64):
    """The ray lies exactly in the plane (n.d == 0 and n.o == offset exactly), on a range
    finite, half-infinite or the whole line: it hits on all of it."""

    def build(draw):
        n = draw(_nonzero_i3(8))
        d = _cross(n, draw(_nonzero_i3(8)))
        if not any(d):
            return None
        p = draw(_i3(-8, 8))
        s = draw(st.integers(-8, 8))
        raw = _plane_raw(draw, n, p, _sub(p, _mul(s, d)), d, 0, dtype)
        raw["t_min"], raw["t_max"] = draw(_special_t_range(float(s)))
        raw["t_special"] = fractions.Fraction(s)
        return raw

    return _constructed(build, "Plane", dtype, "plane_in_plane")


def plane_parallel(dtype=np.float64):
    """Exactly parallel rays (n.d == 0) off the plane by an integer or in it, and
    axis-aligned normals with the matching direction component +0 or -0."""

    def build(draw):
        if draw(st.booleans()):
            n = draw(_nonzero_i3(8))
            d = _cross(n, draw(_nonzero_i3(8)))
        else:
            a = draw(st.integers(0, 2))
            n = [0, 0, 0]
            n[a] = draw(_signed_int(1, 8))
            d = draw(_nonzero_i3(8))
            d[a] = 0
        if not any(d):
            return None
        p = draw(_i3(-8, 8))
        shift = draw(st.sampled_from([0, 1])) * draw(_signed_int(1, 16))
        s = draw(st.integers(-4, 4))
        raw = _plane_raw(draw, n, p, _sub(p, _mul(s, d)), d, shift, dtype)
        raw["t_min"], raw["t_max"] = draw(_random_t_range(dtype, 16))
        return raw

    return _constructed(build, "Plane", dtype, "plane_parallel")


@st.composite
def general_plane(draw, dtype=np.float64):
    """A normal in [-1, 1]^3, an offset in [-8, 8], an origin in [-16, 16]^3, a direction
    in [-1, 1]^3."""
    dt = np.dtype(dtype)
    vec = st.lists(_uniform(dt, -1, 1), min_size=3, max_size=3).filter(any)
    raw = {"normal": draw(vec), "offset": draw(_uniform(dt, -8, 8)),
           "o": [draw(_uniform(dt, -16, 16)) for _ in range(3)], "d": draw(vec)}
    raw["t_min"], raw["t_max"] = draw(_random_t_range(dt, 64))
    return _make(raw, "Plane", dt, "general_plane")


# ---------------------------------------------------------------------------------
# Sphere.


def _sphere_raw(draw, center, radius, origin, d, dtype):
    tau = draw(_translation(dtype))
    return {"center": _add(center, tau), "radius": radius, "o": _add(origin, tau), "d": draw(_with_signed_zeros(d))}


def sphere_tangent(dtype=np.float64):
    """The ray touches the sphere at exactly one point, at the exact parameter t_special:
    S = C + k(a, b, c) on the sphere of radius k n for a Pythagorean quadruple, d = (a, b,
    c) x w perpendicular to the radius there (or a point sphere that the ray passes
    through)."""

    def build(draw):
        center = draw(_i3(-8, 8))
        s = draw(st.integers(0, 8))
        if draw(st.integers(0, 7)) == 7:  # a point sphere
            d = draw(_nonzero_i3(8))
            raw = _sphere_raw(draw, center, 0, _sub(center, _mul(s, d)), d, dtype)
        else:
            q, n = draw(_pythagorean_quadruple())
            k = draw(st.integers(1, 4))
            d = _cross(q, draw(_nonzero_i3(8)))
            if not any(d):
                return None
            touch = _add(center, _mul(k, q))
            raw = _sphere_raw(draw, center, k * n, _sub(touch, _mul(s, d)), d, dtype)
        raw["t_min"], raw["t_max"] = draw(_special_t_range(float(s)))
        raw["t_special"] = fractions.Fraction(s)
        return raw

    return _constructed(build, "Sphere", dtype, "sphere_tangent")


@st.composite
def sphere_near_tangent(draw, dtype=np.float64):
    """sphere_tangent with one direction component, one origin coordinate or the radius
    moved by one ulp: a hair inside or outside tangency."""
    case = draw(sphere_tangent(dtype))
    if draw(st.integers(0, 2)) == 0:
        r = float(case.shape.radius)
        case.shape.radius = float(np.finfo(np.dtype(dtype)).smallest_subnormal) if r == 0 else _step(
            r, dtype, draw(st.booleans()))
        return Case(case.ray, case.shape, "sphere_near_tangent", None)
    c = draw(_nudged(st.just(case), dtype, "sphere_near_tangent", ["direction", "origin"]))
    return c


def sphere_parallel(dtype=np.float64):
    """Axis-aligned directions (the other components +0 or -0) passing the centre at an
    integer offset from a Pythagorean triple: exactly tangent, one unit inside or
    outside, or through the centre."""

    def build(draw):
        a = draw(st.integers(0, 2))
        b, e = (a + 1) % 3, (a + 2) % 3
        m = draw(st.integers(1, 5))
        n = draw(st.integers(0, m - 1))
        k = draw(st.integers(1, 4))
        p, q, h = k * (m * m - n * n), k * 2 * m * n, k * (m * m + n * n)
        if draw(st.booleans()):
            p, q = q, p
        center = draw(_i3(-8, 8))
        where = draw(st.sampled_from(["tangent", "crossing", "outside", "through_center"]))
        radius = {"crossing": h + 1, "outside": h - 1}.get(where, h)
        if where == "through_center":
            p = q = 0
        origin = list(center)
        origin[b] += draw(_signed_int(p, p))
        origin[e] += draw(_signed_int(q, q))
        origin[a] += draw(st.integers(-2 * h - 4, 2 * h + 4))
        d = [0, 0, 0]
        d[a] = draw(_signed_int(1, 8))
        raw = _sphere_raw(draw, center, radius, origin, d, dtype)
        raw["t_min"], raw["t_max"] = draw(_random_t_range(dtype, 16))
        return raw

    return _constructed(build, "Sphere", dtype, "sphere_parallel")


@st.composite
def sphere_far_small(draw, dtype=np.float64):
    """A tiny sphere (radius 1e-3, far below the ulp of its centre, or 0) at 2^20 to near
    the top of the range, aimed at from near the origin to within a few ulps: the
    direction is the rounded centre minus origin with one component moved by up to 3
    ulps."""
    dt, p, max_exp, _ = _info(dtype)
    far = max_exp // 2 - 4 if draw(st.booleans()) else max_exp - 8
    center = [draw(_magnitude(dt, 20, far)) for _ in range(3)]
    dist = max(abs(c) for c in center)
    radius = draw(st.sampled_from(["milli", "sub_ulp", "point"]))
    r = {"milli": _round(1e-3, dt), "point": 0.0}.get(radius)
    if r is None:
        r = _round(math.ldexp(dist, -draw(st.integers(10, p + 20))), dt)
    o = [draw(_uniform(dt, -1, 1)) for _ in range(3)]
    d = [_round(center[i] - o[i], dt) for i in range(3)]
    j = draw(st.integers(0, 2))
    d[j] = _nudge(d[j], dt, draw(st.integers(-3, 3)))
    t_min = -math.inf if draw(st.booleans()) else 0.0
    raw = {"center": center, "radius": r, "o": o, "d": d, "t_min": t_min, "t_max": math.inf}
    return _make(raw, "Sphere", dt, "sphere_far_small")


@st.composite
def sphere_extreme(draw, dtype=np.float64):
    """A huge sphere (radius near the overflow threshold; kind sphere_extreme_huge) or a
    sphere of denormal size (sphere_extreme_denormal)."""
    dt, p, max_exp, min_exp = _info(dtype)
    kind = draw(st.sampled_from(["huge", "denormal"]))
    if kind == "huge":
        r = draw(_magnitude(dt, max_exp - 6, max_exp - 1, signed=False))
        center = [draw(finite_floats(dt)) for _ in range(3)]
        o = [draw(finite_floats(dt)) if draw(st.booleans()) else _round(r * draw(st.floats(0, 1)), dt)
             for _ in range(3)]
        d = draw(st.lists(finite_floats(dt), min_size=3, max_size=3).filter(any))
    else:
        center = [draw(_magnitude(dt, min_exp - p, min_exp)) for _ in range(3)]
        o = [draw(_magnitude(dt, min_exp - p, min_exp + 3)) for _ in range(3)]
        r = draw(_magnitude(dt, min_exp - p, min_exp, signed=False))
        d = [_round(center[i] - o[i], dt) for i in range(3)] if draw(st.booleans()) else draw(
            st.lists(finite_floats(dt), min_size=3, max_size=3))
    if not any(d):
        d = [1.0, 0.0, 0.0]
    t_min = -math.inf if draw(st.booleans()) else 0.0
    raw = {"center": center, "radius": r, "o": o, "d": d, "t_min": t_min, "t_max": math.inf}
    return _make(raw, "Sphere", dt, "sphere_extreme_" + kind)


@st.composite
def general_sphere(draw, dtype=np.float64):
    """A centre in [-8, 8]^3, a radius in [0, 4], an origin in [-16, 16]^3 aimed near it."""
    dt = np.dtype(dtype)
    r = draw(_uniform(dt, 0, 4))
    center = [draw(_uniform(dt, -8, 8)) for _ in range(3)]
    o = [draw(_uniform(dt, -16, 16)) for _ in range(3)]
    d = [_round(center[i] + 1.25 * r * draw(st.floats(-1, 1)) - o[i], dt) for i in range(3)]
    if not any(d):
        d = [0.0, 1.0, 0.0]
    t_min, t_max = draw(_random_t_range(dt, 64))
    raw = {"center": center, "radius": r, "o": o, "d": d, "t_min": t_min, "t_max": t_max}
    return _make(raw, "Sphere", dt, "general_sphere")


_BY_SHAPE = {
    "Aabb": (general_aabb, aabb_grazing, aabb_near_grazing, aabb_parallel, aabb_extreme),
    "Obb": (general_obb, obb_grazing, obb_parallel),
    "Plane": (general_plane, plane_in_plane, plane_parallel),
    "Sphere": (general_sphere, sphere_tangent, sphere_near_tangent, sphere_parallel, sphere_far_small,
               sphere_extreme),
}


def cases(shape="Aabb", dtype=np.float64):
    """Every strategy of one shape ("Aabb", "Obb", "Plane" or "Sphere"), mixed."""
    return st.one_of([s(dtype) for s in _BY_SHAPE[shape]])
