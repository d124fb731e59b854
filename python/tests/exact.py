"""The exact answers the tests judge rayproof by, in rational arithmetic
(fractions.Fraction holds every finite float exactly): the slab test of the Aabb and the
Obb, the plane, the sphere (its roots compared with floats exactly, never computed), and
the faithful-rounding relation of the contract."""

import math
from fractions import Fraction

import numpy as np

INF = math.inf


def q(x):
    """A finite float as the exact rational it denotes; +-inf stays a float (Python
    compares Fractions with infinities exactly)."""
    x = float(x)
    return x if math.isinf(x) else Fraction(x)


def qv(v):
    return [Fraction(float(x)) for x in v]


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def sub(a, b):
    return [x - y for x, y in zip(a, b)]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def neighbour(x, dtype, up):
    dt = np.dtype(dtype)
    with np.errstate(over="ignore"):
        return float(np.nextafter(dt.type(x), dt.type(INF if up else -INF)))


def faithful_by(x, cmp, dtype):
    """x is a faithful rounding of the exact value v given by cmp(r) = sign(r - v) for
    rationals r: v itself, or one of the two values of dtype enclosing it (beyond the
    largest finite value they are max and inf)."""
    x = float(x)
    if math.isnan(x):
        return False
    if not math.isinf(x) and float(np.dtype(dtype).type(x)) != x:
        return False  # not a value of dtype at all
    if math.isinf(x):
        big = Fraction(float(np.finfo(np.dtype(dtype)).max))
        return cmp(big) < 0 if x > 0 else cmp(-big) > 0
    c = cmp(Fraction(x))
    if c == 0:
        return True
    n = neighbour(x, dtype, c < 0)
    if math.isinf(n):
        return True  # v lies beyond the largest finite value, x is that value
    return cmp(Fraction(n)) == -c


def faithful(x, exact, dtype):
    """faithful_by for a rational exact value (or an infinite end, which must be met)."""
    if isinstance(exact, float):
        return float(x) == exact
    return faithful_by(x, lambda r: (r > exact) - (r < exact), dtype)


def slab_interval(o, d, lo, hi, t_min, t_max):
    """The exact set of t in [t_min, t_max] with lo_i <= o_i + t d_i <= hi_i on every axis
    (rationals; t_min, t_max may be +-inf): None when empty, else (t_enter, t_exit,
    face) with the contract's face: -1 when the point at t_min is in the box, otherwise
    2 axis + side (side 0 entering at lo, 1 at hi) of the lowest axis whose entry
    realizes t_enter."""
    enter, leave, entries = t_min, t_max, []
    for i in range(3):
        if d[i] == 0:
            if not lo[i] <= o[i] <= hi[i]:
                return None
            continue
        a, b = (lo[i] - o[i]) / d[i], (hi[i] - o[i]) / d[i]
        if d[i] < 0:
            a, b = b, a
        entries.append((a, 2 * i + (0 if d[i] > 0 else 1)))
        enter, leave = max(enter, a), min(leave, b)
    if enter > leave:
        return None
    if all(a <= t_min for a, _ in entries):
        return enter, leave, -1
    return enter, leave, min(f for a, f in entries if a == enter)


def aabb_exact(ray, box):
    return slab_interval(qv(ray.origin), qv(ray.direction), qv(box.lo), qv(box.hi), q(ray.t_min), q(ray.t_max))


def obb_exact(ray, obb):
    """The Obb's slabs in its own frame: (o - c).a_i + t d.a_i in [-h_i, h_i]."""
    axes = [qv(obb.axes[:, i]) for i in range(3)]
    rel = sub(qv(ray.origin), qv(obb.center))
    d = qv(ray.direction)
    h = qv(obb.half_extent)
    return slab_interval([dot(rel, a) for a in axes], [dot(d, a) for a in axes], [-x for x in h], h,
                         q(ray.t_min), q(ray.t_max))


def plane_exact(ray, plane):
    n = qv(plane.normal)
    num = q(plane.offset) - dot(n, qv(ray.origin))
    den = dot(n, qv(ray.direction))
    t_min, t_max = q(ray.t_min), q(ray.t_max)
    if den == 0:
        return (t_min, t_max, -1) if num == 0 else None
    t = num / den
    return (t, t, -1) if t_min <= t <= t_max else None


class SphereExact:
    """|o + t d - c|^2 <= r^2 as a t^2 + 2 b t + cc <= 0; its roots (-b -+ sqrt(disc)) / a
    compared with rationals exactly."""

    def __init__(self, ray, sphere):
        d, rel = qv(ray.direction), sub(qv(ray.origin), qv(sphere.center))
        self.a, self.b = dot(d, d), dot(d, rel)
        self.cc = dot(rel, rel) - q(sphere.radius) ** 2
        self.disc = self.b * self.b - self.a * self.cc
        self.t_min, self.t_max = q(ray.t_min), q(ray.t_max)

    def cmp_root(self, x, sign):
        """sign(x - root), root = (-b + sign sqrt(disc)) / a, for a rational x or +-inf."""
        if isinstance(x, float):
            return 1 if x > 0 else -1
        y = self.a * x + self.b  # compare y with sign * sqrt(disc)
        if sign > 0:
            return -1 if y < 0 else (y * y > self.disc) - (y * y < self.disc)
        return 1 if y > 0 else (y * y < self.disc) - (y * y > self.disc)

    def hits(self):
        return self.disc >= 0 and self.cmp_root(self.t_max, -1) >= 0 and self.cmp_root(self.t_min, 1) <= 0

    def enter_cmp(self):
        """cmp(r) = sign(r - t_enter): t_min when it is past the smaller root, else that root."""
        if not isinstance(self.t_min, float) and self.cmp_root(self.t_min, -1) >= 0:
            return lambda r: (r > self.t_min) - (r < self.t_min)
        return lambda r: self.cmp_root(r, -1)

    def exit_cmp(self):
        if not isinstance(self.t_max, float) and self.cmp_root(self.t_max, 1) <= 0:
            return lambda r: (r > self.t_max) - (r < self.t_max)
        return lambda r: self.cmp_root(r, 1)
