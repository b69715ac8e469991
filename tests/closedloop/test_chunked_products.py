"""The per-frame products of 4-m loops in float32: chunked sensor operators, controller's R G.

References (outside the code): scipy's float64 sparse product ``A @ x`` and numpy's dense
one, with the standard worst-case bound of a dot product of ``n`` terms (Higham,
*Accuracy and Stability of Numerical Algorithms*, 2nd ed., eq. 3.5): ``|y - A x| <=
n u |A| |x|`` with ``u = 2^-53`` for float64 sums in another order, and ``(n + 2) u``,
``u = 2^-24``, when ``A``'s entries are also rounded to float32. The chunked layout
(four consecutive columns per chunk, zero lanes where no entry falls) is checked on the
cases its cutting handles apart: empty rows, runs longer than a chunk, entries in the
last columns (chunks clamped to the matrix), a matrix narrower than a chunk, duplicate
entries. The loop's sensors of an actuator mirror read these chunks; their measurement
is the scipy product of their operators within the bound.
"""

import numpy as np
import pytest
from scipy import sparse

from closedloop import LoopModel
from closedloop.control.controller import Controller
from closedloop.optics.products import ChunkedSparse

U64 = 2.0 ** -53
U32 = 2.0 ** -24


def _bound(a: sparse.csr_matrix, x: np.ndarray, u: float, extra: int = 0) -> np.ndarray:
    n = np.maximum(np.diff(a.indptr), 1) + extra
    return (n + 1) * u * (abs(a) @ np.abs(x))


def _random_sparse(rng, m: int, n: int, density: float) -> sparse.csr_matrix:
    a = sparse.random(m, n, density=density, random_state=rng, format="csr")
    a.data = rng.standard_normal(a.data.size)
    return a


@pytest.mark.parametrize("shape, density", [((50, 200), 0.05), ((40, 37), 0.5), ((7, 3), 0.6),
                                            ((30, 1000), 0.002)])
def test_chunks_reproduce_scipys_product(shape, density):
    rng = np.random.default_rng(1)
    a = _random_sparse(rng, *shape, density).tolil()
    a[0, :] = 0.0  # an empty row
    a[1, shape[1] - 1] = 2.5  # the last column: a chunk clamped to the matrix
    a = a.tocsr()
    a.eliminate_zeros()
    x = rng.standard_normal(shape[1])
    exact = a @ x
    y64 = ChunkedSparse(a, dtype=np.float64)(x, np.empty(shape[0]))
    assert np.all(np.abs(y64 - exact) <= _bound(a, x, U64))
    assert y64[0] == 0.0
    y32 = ChunkedSparse(a)(x, np.empty(shape[0]))
    assert np.all(np.abs(y32 - exact) <= _bound(a, x, U32, 2))
    # accumulate adds the product to what is there
    out = np.full(shape[0], 3.0)
    ChunkedSparse(a, dtype=np.float64)(x, out, accumulate=True)
    np.testing.assert_allclose(out, 3.0 + exact, rtol=0, atol=1e-12)


def test_chunks_hold_runs_longer_than_a_chunk_and_sum_duplicates():
    # a row of ten consecutive columns (three chunks) and a duplicated entry
    rows = np.array([0] * 10 + [1, 1, 1])
    cols = np.array(list(range(5, 15)) + [2, 2, 9])
    vals = np.arange(1.0, 14.0)
    a = sparse.coo_matrix((vals, (rows, cols)), shape=(2, 16))
    x = np.linspace(-1.0, 2.0, 16)
    c = ChunkedSparse(a, dtype=np.float64)
    assert c.chunk_ptr.tolist() == [0, 3, 5]  # 5-8, 9-12, 13-15 (clamped to 12-15); 2-5, 9-12
    np.testing.assert_allclose(c(x, np.empty(2)), a.tocsr() @ x, rtol=1e-15)
    assert c.nbytes == c.chunk_ptr.nbytes + c.starts.nbytes + c.data.nbytes


def test_an_actuator_mirrors_sensor_reads_float32_chunks(tiny_actuator_loop):
    model = LoopModel(tiny_actuator_loop)
    wfs = model.wfss[0]
    assert wfs._chunked is not None and wfs._csr is None
    assert all(c.data.dtype == np.float32 for c in wfs._chunked)
    rng = np.random.default_rng(2)
    maps = [rng.standard_normal((p.n, p.n)) + 30.0 for p in model.geometry.planes]
    exact = sum(op @ m.ravel() for op, m in zip(wfs.operators, maps, strict=True))
    got = wfs.forward(maps)
    bound = sum(_bound(op.tocsr(), m.ravel(), U32, 2)
                for op, m in zip(wfs.operators, maps, strict=True))
    assert np.all(np.abs(got - exact) <= bound)
    assert not np.array_equal(got, exact)  # it did read float32 values


def test_the_controllers_products_in_float32_only_when_asked():
    rng = np.random.default_rng(3)
    n = 40
    rg = rng.standard_normal((n, n))
    kw = dict(gain=0.5, leak=0.0, delay_frames=0.5, integration_frames=1.0)
    m = rng.standard_normal(n)
    plain, single = Controller(n, sensed=rg, **kw), Controller(n, sensed=rg, float32_from=0.0,
                                                                **kw)
    first = rng.standard_normal(n)
    for c in (plain, single):
        c.step(first)  # a first command, so that the mirror has moved
    seen = plain.seen_commands()
    np.testing.assert_array_equal(seen, single.seen_commands())
    # reference: the POL of pseudo-open-loop control, m + R G seen (float64, numpy)
    _, pol, _ = plain.step(m)
    assert np.array_equal(pol, m + rg @ seen)
    _, pol32, _ = single.step(m)
    bound = (n + 2) * U32 * (np.abs(rg) @ np.abs(seen)) + 4 * U64 * np.abs(m + rg @ seen)
    assert np.all(np.abs(pol32 - (m + rg @ seen)) <= bound)
    assert not np.array_equal(pol32, pol)
