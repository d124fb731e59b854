"""rayproof: ray against axis-aligned box, oriented box, plane and sphere, exactly.

The kernel's value types come in float64 (Ray, Aabb, Obb, Plane, Sphere, Hit) and
float32 (Ray32, Aabb32, ...); a float32 query runs the kernel's float code on the
float32 numbers as given. Three modes, chosen at run time: ``fast`` (plain floating
point, no promise), ``conservative`` (never misses an exact hit; the interval encloses
the exact one) and ``certified`` (verdict and face exact, t_enter and t_exit faithfully
rounded). The contract is docs/semantics.md.

    import rayproof as rp
    hit = rp.intersect(rp.Ray([-4, 0.5, 0], [1, 0, 0]), rp.Aabb([-1] * 3, [1] * 3), rp.certified)
    hits = rp.intersect_batch(origins, directions, box, rp.certified)   # (N, 3) arrays in

Numbers given as Python floats or lists are rounded once to the shape's type; a NumPy
float array of the other width is refused (TypeError) rather than rounded silently.
"""

import collections
import math
import types as _types

import numpy as np

from . import _rayproof
# reversed (the ray traversed backwards) is left out of __all__: a star import would
# shadow the builtin.
from ._rayproof import (
    Aabb,
    Aabb32,
    Hit,
    Hit32,
    Mode,
    Obb,
    Obb32,
    Plane,
    Plane32,
    Ray,
    Ray32,
    Sphere,
    Sphere32,
    Verdict,
    certified,
    conservative,
    fast,
    normal,
    reversed,
)

__all__ = [
    "Aabb", "Aabb32", "Hit", "Hit32", "HitArrays", "Mode", "Obb", "Obb32", "Plane", "Plane32", "Ray", "Ray32",
    "Sphere", "Sphere32", "Verdict", "certified", "conservative", "fast", "hit_dtype", "intersect",
    "intersect_batch", "normal", "ray_dtype", "rays", "types", "verdict", "verdict_batch",
    "MODES", "SHAPES", "DTYPES",
]

MODES = (fast, conservative, certified)
SHAPES = ("Aabb", "Obb", "Plane", "Sphere")
DTYPES = (np.dtype(np.float64), np.dtype(np.float32))

HitArrays = collections.namedtuple("HitArrays", "verdict t_enter t_exit face")
HitArrays.__doc__ = """Batch answers as separate arrays: verdict codes (int8: int(Verdict.x)),
t_enter and t_exit (the shape's float type) and face (int32)."""


def types(dtype):
    """The classes of one float type: types(np.float32).Ray is Ray32, and so on."""
    dt = np.dtype(dtype)
    if dt not in DTYPES:
        raise TypeError(f"rayproof answers float32 and float64, not {dt}")
    suffix = "32" if dt == np.float32 else ""
    names = ("Ray", "Hit") + SHAPES
    return _types.SimpleNamespace(dtype=dt, **{n: getattr(_rayproof, n + suffix) for n in names})


def ray_dtype(dtype=np.float64):
    """The structured dtype of a ray array: origin (3,), direction (3,), t_min, t_max."""
    dt = np.dtype(dtype)
    return np.dtype([("origin", dt, (3,)), ("direction", dt, (3,)), ("t_min", dt), ("t_max", dt)])


def hit_dtype(dtype=np.float64):
    """The structured dtype of a hit array: verdict (int8 code), t_enter, t_exit, face (int32)."""
    dt = np.dtype(dtype)
    return np.dtype([("verdict", np.int8), ("t_enter", dt), ("t_exit", dt), ("face", np.int32)])


def _mode(mode):
    if isinstance(mode, Mode):
        return mode
    if isinstance(mode, str) and mode in Mode.__members__:
        return Mode.__members__[mode]
    raise TypeError(f"mode must be rayproof.fast, conservative or certified (or its name), not {mode!r}")


def _as(x, dtype, name):
    """x as an array of dtype: NumPy floats of another width are refused, anything else
    (Python numbers, lists, integer arrays) converted, each value rounded once."""
    if isinstance(x, (np.ndarray, np.floating)) and x.dtype.kind == "f" and x.dtype != dtype:
        raise TypeError(
            f"{name} is {x.dtype} but the query is {dtype}: convert it explicitly "
            f"(rayproof does not round one float width to the other behind your back)"
        )
    return np.asarray(x, dtype=dtype)


def rays(origins, directions, t_min=0.0, t_max=math.inf, dtype=np.float64):
    """A structured ray array (ray_dtype) from (..., 3) origins and directions and
    broadcastable t_min, t_max."""
    dt = np.dtype(dtype)
    o, d = _as(origins, dt, "origins"), _as(directions, dt, "directions")
    lo, hi = _as(t_min, dt, "t_min"), _as(t_max, dt, "t_max")
    shape = np.broadcast_shapes(o.shape[:-1], d.shape[:-1], lo.shape, hi.shape)
    out = np.empty(shape, ray_dtype(dt))
    out["origin"], out["direction"], out["t_min"], out["t_max"] = o, d, lo, hi
    return out


def _batch(fn, origins, directions, t_min, t_max, shape, mode):
    dt = np.dtype(shape.dtype)
    o, d = _as(origins, dt, "origins"), _as(directions, dt, "directions")
    lo, hi = _as(t_min, dt, "t_min"), _as(t_max, dt, "t_max")
    if o.ndim < 1 or o.shape[-1] != 3 or d.ndim < 1 or d.shape[-1] != 3:
        raise ValueError("origins and directions must have shape (..., 3)")
    shape_ = np.broadcast_shapes(o.shape[:-1], d.shape[:-1], lo.shape, hi.shape)
    n = math.prod(shape_)
    o = np.broadcast_to(o, shape_ + (3,)).reshape(n, 3)
    d = np.broadcast_to(d, shape_ + (3,)).reshape(n, 3)
    lo = np.broadcast_to(lo, shape_).reshape(n)
    hi = np.broadcast_to(hi, shape_).reshape(n)
    return shape_, fn(o, d, lo, hi, shape, _mode(mode))


def intersect_batch(origins, directions, shape, mode, t_min=0.0, t_max=math.inf):
    """Every ray o + t*d, t in [t_min, t_max], against one shape: (..., 3) origins and
    directions, t_min and t_max broadcast with them, all of the shape's float type.
    Returns HitArrays of the broadcast shape. The kernel's batch form answers each ray
    as intersect() would."""
    batch, (v, te, tx, f) = _batch(_rayproof._intersect_batch, origins, directions, t_min, t_max, shape, mode)
    return HitArrays(v.reshape(batch), te.reshape(batch), tx.reshape(batch), f.reshape(batch))


def verdict_batch(origins, directions, shape, mode, t_min=0.0, t_max=math.inf):
    """The verdicts alone of intersect_batch (int8 codes: int(Verdict.x))."""
    batch, v = _batch(_rayproof._verdict_batch, origins, directions, t_min, t_max, shape, mode)
    return v.reshape(batch)


def _ray_fields(rays_, shape):
    if rays_.dtype.names is None or "t_min" not in rays_.dtype.names or rays_.dtype != ray_dtype(rays_.dtype["t_min"]):
        raise TypeError("a ray array must have rayproof.ray_dtype(...)")
    if rays_.dtype["t_min"] != np.dtype(shape.dtype):
        raise TypeError(f"the rays are {rays_.dtype['t_min']} but the shape is {np.dtype(shape.dtype)}")
    return rays_["origin"], rays_["direction"], rays_["t_min"], rays_["t_max"]


def intersect(ray, shape, mode):
    """intersect(Ray, shape, mode) -> Hit, the kernel's answer for one ray (Ray32 and the
    float32 shapes -> Hit32); intersect(ray array, shape, mode) -> hit array
    (hit_dtype), element by element the same."""
    if isinstance(ray, np.ndarray):
        o, d, lo, hi = _ray_fields(ray, shape)
        h = intersect_batch(o, d, shape, mode, lo, hi)
        out = np.empty(ray.shape, hit_dtype(shape.dtype))
        out["verdict"], out["t_enter"], out["t_exit"], out["face"] = h
        return out
    return _rayproof.intersect(ray, shape, _mode(mode))


def verdict(ray, shape, mode):
    """verdict(Ray, shape, mode) -> Verdict (the verdict of intersect, computed alone);
    verdict(ray array, shape, mode) -> int8 array of codes."""
    if isinstance(ray, np.ndarray):
        o, d, lo, hi = _ray_fields(ray, shape)
        return verdict_batch(o, d, shape, mode, lo, hi)
    return _rayproof.verdict(ray, shape, _mode(mode))
