"""The Python interface itself: hand-computed answers of every shape, the float32
path (float32 numbers used as they are, answered by the float kernel), the refusal of a
NumPy float of the other width, the batch interface's shapes and broadcasting, modes
by value and by name, normal() and reversed()."""

import math

import numpy as np
import pytest

import exact
import rayproof as rp

BOX = ([-1, -1, -1], [1, 1, 1])


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
def test_hand_computed_answers(dtype):
    t = rp.types(dtype)
    ray = t.Ray([-4, 0.5, 0], [1, 0, 0])
    for mode in rp.MODES:
        hit = rp.intersect(ray, t.Aabb(*BOX), mode)
        assert isinstance(hit, t.Hit) and hit and hit.t_enter <= 3 and hit.t_exit >= 5  # conservative widens
    hit = rp.intersect(ray, t.Aabb(*BOX), rp.certified)
    assert (hit.t_enter, hit.t_exit, hit.face) == (3, 5, 0)
    assert np.array_equal(rp.normal(t.Aabb(*BOX), hit, ray), [-1, 0, 0])
    assert rp.normal(t.Aabb(*BOX), hit, ray).dtype == np.dtype(dtype)
    obb = t.Obb([0, 0, 0], np.diag([2, 1, 1]).astype(dtype), [1, 1, 1])  # x half extent 1/2
    hit = rp.intersect(ray, obb, rp.certified)
    assert (hit.verdict, hit.t_enter, hit.t_exit, hit.face) == (rp.Verdict.hit, 3.5, 4.5, 0)
    hit = rp.intersect(ray, t.Plane([1, 0, 0], 2), rp.certified)
    assert (hit.t_enter, hit.t_exit, hit.face) == (6, 6, -1)
    hit = rp.intersect(ray, t.Sphere([0, 0.5, 0], 1), rp.certified)
    assert (hit.t_enter, hit.t_exit) == (3, 5)
    assert rp.intersect(t.Ray([-4, 2, 0], [1, 0, 0]), t.Sphere([0, 0, 0], 1), rp.certified).verdict == rp.Verdict.miss
    assert rp.intersect(t.Ray([0, 0, 0], [0, 0, 0]), t.Aabb(*BOX), rp.certified).verdict == rp.Verdict.invalid
    assert rp.intersect(t.Ray([0, 0, 0], [1, 0, 0], 2, 1), t.Aabb(*BOX), rp.fast).verdict == rp.Verdict.invalid
    back = rp.intersect(rp.reversed(ray), t.Aabb(*BOX), rp.certified)
    assert (back.t_enter, back.t_exit, back.face) == (-5, -3, 1)
    assert rp.verdict(ray, t.Aabb(*BOX), "certified") == rp.Verdict.hit


def test_float32_queries_run_the_float_kernel_on_float32_numbers():
    # t = 1/3: the float kernel's certified t is a float32 next to 1/3; a double kernel
    # would answer a double that is not a float32.
    hit = rp.intersect(rp.Ray32([0, 0, 0], [3, 0, 0]), rp.Aabb32([1, -1, -1], [2, 1, 1]), rp.certified)
    assert float(np.float32(hit.t_enter)) == hit.t_enter
    assert exact.faithful(hit.t_enter, exact.Fraction(1, 3), np.float32)
    # float32 numbers are kept bit for bit, -0 included.
    v = np.array([0.1, -0.0, 3e-45], dtype=np.float32)
    r = rp.Ray32(v, v[::-1].copy())
    assert r.origin.dtype == np.float32 and r.origin.tobytes() == v.tobytes()
    # Python floats are rounded once to nearest float32.
    assert rp.Ray32([0.1, 0, 0], [1, 0, 0]).origin[0] == np.float32(0.1)
    assert rp.Sphere32([0, 0, 0], 0.1).radius == float(np.float32(0.1))


def test_a_float_of_the_other_width_is_refused():
    with pytest.raises(TypeError):
        rp.Ray32(np.zeros(3), [1, 0, 0])
    with pytest.raises(TypeError):
        rp.Aabb(np.zeros(3, np.float32), [1, 1, 1])
    with pytest.raises(TypeError):
        rp.Sphere32([0, 0, 0], np.float64(1))
    with pytest.raises(TypeError):
        rp.intersect_batch(np.zeros((2, 3)), np.ones((2, 3)), rp.Aabb32(*BOX), rp.certified)
    with pytest.raises(TypeError):
        rp.intersect(rp.rays(np.zeros((2, 3)), [1, 0, 0]), rp.Aabb32(*BOX), rp.certified)
    with pytest.raises(TypeError):
        rp.intersect(rp.Ray32([0, 0, 0], [1, 0, 0]), rp.Aabb(*BOX), rp.certified)
    with pytest.raises(TypeError):
        rp.intersect(rp.Ray([0, 0, 0], [1, 0, 0]), rp.Aabb(*BOX), "exact")


def test_batch_shapes_and_broadcasting():
    box = rp.Aabb(*BOX)
    origins = np.zeros((2, 4, 3))
    origins[..., 0] = -4
    origins[1, :, 1] = 2  # the second row misses
    hits = rp.intersect_batch(origins, [1, 0, 0], box, rp.certified, t_max=[10, 10, 10, 4])
    assert hits.verdict.shape == (2, 4) and hits.t_enter.dtype == np.float64 and hits.face.dtype == np.int32
    assert hits.verdict.tolist() == [[1, 1, 1, 1], [0, 0, 0, 0]]
    assert hits.t_exit[0].tolist() == [5, 5, 5, 4]
    assert rp.verdict_batch(origins, [1, 0, 0], box, rp.fast).tolist() == hits.verdict.tolist()
    rays = rp.rays(origins, [1, 0, 0], t_max=[10, 10, 10, 4])
    assert rays.dtype == rp.ray_dtype(np.float64)
    structured = rp.intersect(rays, box, rp.certified)
    assert structured.dtype == rp.hit_dtype(np.float64) and structured.shape == (2, 4)
    assert structured["t_exit"].tolist() == hits.t_exit.tolist()
    assert rp.verdict(rays, box, rp.certified).tolist() == hits.verdict.tolist()
    with pytest.raises(ValueError):
        rp.intersect_batch(np.zeros((3, 2)), np.ones((3, 2)), box, rp.certified)
    empty = rp.intersect_batch(np.zeros((0, 3)), np.ones((0, 3)), box, rp.certified)
    assert empty.verdict.shape == (0,)


def test_value_types():
    r = rp.Ray([1, 2, 3], [0, 0, 1], -math.inf, 5)
    assert (r.t_min, r.t_max) == (-math.inf, 5)
    r.direction = [0, 1, 0]
    assert r.direction.tolist() == [0, 1, 0]
    assert "0x1p+0" in repr(r)
    obb = rp.Obb([0, 0, 0], [[1, 2, 0], [0, 1, 0], [0, 0, 1]], [1, 1, 1])
    assert obb.axes[:, 1].tolist() == [2, 1, 0]  # axes are the columns
    assert rp.Hit(rp.Verdict.hit, 1, 2, 3) == rp.Hit(rp.Verdict.hit, 1, 2, 3)
    assert not rp.Hit()
    assert rp.types(np.float32).Sphere is rp.Sphere32 and rp.Sphere32.dtype == np.float32
