"""The NumPy batch forms against the scalar ones, element by element and bit for bit,
for every shape, mode and float type: the rays of several drawn cases against one
shape, through intersect_batch, verdict_batch and a structured ray array. (The kernel's
batch form runs the scalar form's code path; this checks that the rays reach it
unchanged and the answers come back unchanged.)"""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import rayproof as rp
from rayproof import strategies as rs


def bits(x, dtype):
    return np.asarray(x, dtype=dtype).view(np.uint32 if np.dtype(dtype) == np.float32 else np.uint64)


@pytest.mark.parametrize("mode", rp.MODES, ids=str)
@pytest.mark.parametrize("dtype", [np.float64, np.float32])
@pytest.mark.parametrize("shape", rp.SHAPES)
def test_batch_equals_scalar(shape, dtype, mode):
    @settings(max_examples=25)
    @given(st.lists(rs.cases(shape, dtype), min_size=1, max_size=12))
    def check(drawn):
        target = drawn[0].shape
        rays = [c.ray for c in drawn]
        o = np.array([r.origin for r in rays])
        d = np.array([r.direction for r in rays])
        lo = np.array([r.t_min for r in rays], dtype=dtype)
        hi = np.array([r.t_max for r in rays], dtype=dtype)
        assert o.dtype == np.dtype(dtype)
        scalar = [rp.intersect(r, target, mode) for r in rays]
        batch = rp.intersect_batch(o, d, target, mode, lo, hi)
        assert batch.t_enter.dtype == np.dtype(dtype) and batch.t_exit.dtype == np.dtype(dtype)
        assert [int(h.verdict) for h in scalar] == batch.verdict.tolist()
        assert (bits([h.t_enter for h in scalar], dtype) == bits(batch.t_enter, dtype)).all()
        assert (bits([h.t_exit for h in scalar], dtype) == bits(batch.t_exit, dtype)).all()
        assert [h.face for h in scalar] == batch.face.tolist()
        verdicts = [int(rp.verdict(r, target, mode)) for r in rays]
        assert verdicts == rp.verdict_batch(o, d, target, mode, lo, hi).tolist()
        assert verdicts == [int(h.verdict) for h in scalar]
        structured = rp.intersect(rp.rays(o, d, lo, hi, dtype=dtype), target, mode)
        assert structured["verdict"].tolist() == batch.verdict.tolist()
        assert (bits(structured["t_enter"], dtype) == bits(batch.t_enter, dtype)).all()
        assert (bits(structured["t_exit"], dtype) == bits(batch.t_exit, dtype)).all()
        assert structured["face"].tolist() == batch.face.tolist()

    check()


def test_batch_over_many_chunks_and_strided_input():
    # More rays than one chunk of the binding's buffer, from a strided view.
    n = 10000
    rng = np.random.default_rng(7)
    o = rng.uniform(-4, 4, size=(n, 6))[:, ::2]
    d = rng.uniform(-1, 1, size=(n, 3))
    box = rp.Aabb([-1, -1, -1], [1, 1, 1])
    batch = rp.intersect_batch(o, d, box, rp.certified)
    picks = [0, 4095, 4096, 8191, 8192, n - 1]
    for i in picks:
        h = rp.intersect(rp.Ray(o[i], d[i]), box, rp.certified)
        assert (int(h.verdict), h.t_enter, h.t_exit, h.face) == (
            batch.verdict[i], batch.t_enter[i], batch.t_exit[i], batch.face[i])
    assert 0 < (batch.verdict == int(rp.Verdict.hit)).sum() < n
