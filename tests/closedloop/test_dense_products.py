"""The loop's large dense products in float32 (``closedloop.optics.products``).

References (outside the code): numpy's float64 matrix-vector product, and the standard
worst-case bound of a float32 dot product of ``n`` terms (Higham, *Accuracy and
Stability of Numerical Algorithms*, 2nd ed., eq. 3.5, with the inputs' own rounding to
float32): ``|y32 - y| <= (n + 2) u |A| |x|``, ``u = 2^-24``. In the loop the float32
error is a measurement error of relative size ``<= (n + 2) u`` (n = 104 slopes here:
6.3e-6) that the integrator filters; the residual variances of a run may move by a few
times that relative to themselves, so 1e-3 leaves a margin of ~100 over the bound
(measured 2.5e-7). The float64 path keeps the bits of ``A @ x`` (every earlier preset's
matrices are below the threshold). The Gram pseudo-inverse is checked against
``numpy.linalg.pinv``.
"""

import numpy as np
import pytest

from closedloop import LoopModel, simulate
from closedloop.optics import products
from closedloop.optics.products import DenseProduct

U32 = 2.0 ** -24


def test_small_matrices_keep_the_float64_bits():
    rng = np.random.default_rng(1)
    a, x = rng.standard_normal((300, 200)), rng.standard_normal(200)
    p = DenseProduct(a)
    assert not p.single and 8 * a.size < products.FLOAT32_MIN_BYTES
    y = p(x)
    assert y.dtype == np.float64 and np.array_equal(y, a @ x)


def test_large_matrices_run_in_float32_within_the_dot_product_bound():
    rng = np.random.default_rng(2)
    n = 1250
    a, x = rng.standard_normal((800, n)), rng.standard_normal(n)
    assert 8 * a.size >= products.FLOAT32_MIN_BYTES  # 8 MB: the default switches
    p = DenseProduct(a)
    assert p.single and p.matrix.dtype == np.float32
    y = p(x)
    assert y.dtype == np.float64
    exact = a @ x
    bound = (n + 2) * U32 * (np.abs(a) @ np.abs(x))
    assert np.all(np.abs(y - exact) <= bound)
    assert not np.array_equal(y, exact)  # it did run in float32


def test_the_threshold_is_read_when_the_product_is_made(monkeypatch):
    a = np.ones((4, 4))
    monkeypatch.setattr(products, "FLOAT32_MIN_BYTES", 8 * 16)
    assert DenseProduct(a).single
    assert not DenseProduct(a, min_bytes=np.inf).single


def test_the_loop_in_float32_moves_the_residual_by_rounding_only(tiny_actuator_loop, monkeypatch):
    model64 = LoopModel(tiny_actuator_loop)
    assert not model64._products[0].single and not model64.dms[0]._strokes.single
    run64 = simulate(tiny_actuator_loop, 0.03, model=model64, progress=False)
    monkeypatch.setattr(products, "FLOAT32_MIN_BYTES", 0)  # every product in float32
    model32 = LoopModel(tiny_actuator_loop)
    assert model32._products[0].single and model32.dms[0]._strokes.single
    run32 = simulate(tiny_actuator_loop, 0.03, model=model32, progress=False)
    v64, v32 = np.asarray(run64.residual_variance), np.asarray(run32.residual_variance)
    assert not np.array_equal(v32, v64)
    # measured largest relative change 2.5e-7 (30 frames)
    assert np.max(np.abs(v32 - v64) / v64) < 1e-3
    # the float64 model is untouched by the switch: its run repeats bit for bit
    again = simulate(tiny_actuator_loop, 0.03, model=model64, progress=False)
    assert np.array_equal(run64.logs["dm0.commands"].coeffs, again.logs["dm0.commands"].coeffs)


@pytest.mark.parametrize("shape", [(300, 120), (120, 300)])
def test_the_gram_pseudo_inverse_is_numpys(shape):
    # singular values from 1 to 1e-5, none within 10 % of the cut (1e-3): kept sets agree;
    # the Gram squares the kept condition number (<= 1e6): error <= 1e6 eps = 2.2e-10 of
    # the largest entry, asserted with a margin of 10
    rng = np.random.default_rng(3)
    m, n = shape
    k = min(m, n)
    u, _ = np.linalg.qr(rng.standard_normal((m, k)))
    v, _ = np.linalg.qr(rng.standard_normal((n, k)))
    sv = np.geomspace(1.0, 1e-5, k)
    sv[np.abs(sv / 1e-3 - 1) < 0.1] *= 2.0
    a = (u * sv) @ v.T
    ref = np.linalg.pinv(a, rcond=1e-3)
    got, kept = products.gram_pinv(a, lambda s0: 1e-3 * s0)
    assert got.shape == ref.shape and kept == int(np.sum(sv > 1e-3 * sv.max()))
    assert np.max(np.abs(got - ref)) <= 2.2e-9 * np.max(np.abs(ref))
