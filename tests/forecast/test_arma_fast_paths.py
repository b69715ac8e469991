"""The ARMA fit's fast paths give the bits of the code paths they replace.

References (outside the fast paths): ``numpy.roots`` for the root test that
``_clearly_inside`` short-cuts, ``numpy.column_stack`` of fancy-indexed lags for
``_lag_matrix``, ``scipy.signal.lfilter`` for the filters of ``css_filters`` and
``arma_innovations``; and the
whole fit re-run with the fast paths swapped for those references (the code before
issue 30), compared bit for bit. Small sizes: the file runs in a few seconds.
"""

import numpy as np
import pytest
from scipy.signal import lfilter

from modalinfo.forecast import ARMAPredictor
from modalinfo.forecast import arma as A  # noqa: N812


def _random_coeffs(rng, degree, radius):
    """``c`` of ``prod (1 - w_k z) = 1 + c_1 z + ...`` with inverse roots up to ``radius``."""
    roots = []
    while len(roots) < degree:
        mod = radius * rng.uniform(0.0, 1.2)
        if degree - len(roots) >= 2 and rng.random() < 0.5:
            w = mod * np.exp(1j * rng.uniform(0.0, np.pi))
            roots += [w, np.conj(w)]
        else:
            roots.append(mod * rng.choice([-1.0, 1.0]))
    return np.real(np.poly(roots))[1:]


def test_clearly_inside_only_when_numpy_roots_are_inside():
    rng = np.random.default_rng(0)
    radius = 1.0 / 1.001
    said_yes = said_no = 0
    for _ in range(3000):
        c = _random_coeffs(rng, int(rng.integers(1, 6)), radius)
        inside = np.abs(np.roots(np.r_[1.0, c])).max() < radius * (1.0 - 1e-5)
        fast = A._clearly_inside(c, radius)
        if fast:
            assert np.abs(np.roots(np.r_[1.0, c])).max() < radius, c
            said_yes += 1
        else:
            assert not inside, c      # a clear case is never sent to the slow path
            said_no += 1
    assert said_yes > 500 and said_no > 500  # both branches were exercised


def test_clearly_inside_on_roots_at_the_limit():
    radius = 1.0 / 1.001
    for w in ([radius], [radius * (1 - 1e-9), 0.3], [0.5 * (1 + 1j), 0.5 * (1 - 1j)]):
        c = np.real(np.poly(w))[1:]
        expected = np.abs(w).max() < radius * (1 - 1e-6)
        assert A._clearly_inside(c, radius) == expected


def test_enforce_fast_path_is_bit_identical(monkeypatch):
    rng = np.random.default_rng(1)
    cases = [_random_coeffs(rng, int(rng.integers(1, 6)), 1.1) for _ in range(500)]
    fast = [A._enforce(c, 1e-3) for c in cases]
    monkeypatch.setattr(A, "_clearly_inside", lambda coeffs, radius: False)
    slow = [A._enforce(c, 1e-3) for c in cases]
    for c, f, s in zip(cases, fast, slow, strict=True):
        assert np.array_equal(f, s), c


def test_lag_matrix_equals_column_stack():
    rng = np.random.default_rng(2)
    a, b = rng.standard_normal(50), rng.standard_normal(50)
    rows = np.arange(7, 50)
    ref = np.column_stack([a[rows - i] for i in range(1, 3)] + [b[rows - i] for i in range(1, 5)])
    out = A._lag_matrix(7, (a, 2), (b, 4))
    assert out.flags.c_contiguous and np.array_equal(out, ref)


@pytest.mark.parametrize("p,q", [(0, 1), (1, 0), (2, 3), (5, 5), (0, 0)])
def test_css_filters_equal_lfilter(p, q):
    from modalinfo.forecast._kernels import css_filters

    rng = np.random.default_rng(3)
    e = rng.standard_normal(3000)
    ar = np.r_[1.0, -_random_coeffs(rng, p, 0.95)] if p else np.ones(1)
    ma = np.r_[1.0, _random_coeffs(rng, q, 0.95)] if q else np.ones(1)
    out = [np.full(e.size, np.nan) for _ in range(4)]
    css_filters(e, ar, ma, *out, np.empty(max(p, 1)), *np.empty((3, max(q, 1))))
    v = lfilter([1.0], ar, e)
    w = lfilter([1.0], ma, e)
    for got, ref in zip(out, (v, w, lfilter([1.0], ma, v), lfilter([1.0], ma, w)),
                        strict=True):
        assert np.array_equal(got, ref)


def _scipy_css_filters(e, ar, ma, v, w, u, y, *scratch):
    """The four lfilter calls that ``css_filters`` replaced."""
    v[:] = lfilter([1.0], ar, e)
    w[:] = lfilter([1.0], ma, e)
    u[:] = lfilter([1.0], ma, v)
    y[:] = lfilter([1.0], ma, w)


def _scipy_innovations(x, phi, theta, e, scratch):
    """The lfilter call that ``arma_innovations`` replaced."""
    e[:] = lfilter(np.r_[1.0, -phi], np.r_[1.0, theta], x)


@pytest.mark.parametrize("order", [(2, 3), "aic"])
def test_fit_bit_identical_without_fast_paths(monkeypatch, order):
    rng = np.random.default_rng(4)
    e = rng.standard_normal((900, 3))
    # an AR root near the unit circle partly cancelled by an MA root (closed-loop-like),
    # a plain ARMA(2, 3) and white noise
    x = np.column_stack([lfilter([1.0, -0.9], [1.0, -0.995], e[:, 0]),
                         lfilter([1.0, -0.5, 0.2, 0.15], [1.0, -1.3, 0.4], e[:, 1]),
                         e[:, 2]])
    make = lambda: ARMAPredictor(order=order, max_order=2)  # noqa: E731
    fast = make().fit(x).params_
    monkeypatch.setattr(A, "_clearly_inside", lambda coeffs, radius: False)
    monkeypatch.setattr(A, "css_filters", _scipy_css_filters)
    monkeypatch.setattr(A, "arma_innovations", _scipy_innovations)
    slow = make().fit(x).params_
    for key in ("mu", "phi", "theta", "orders", "sigma2", "criterion"):
        if slow[key] is None:
            assert fast[key] is None
        else:
            assert np.array_equal(fast[key], slow[key], equal_nan=True), key


@pytest.mark.parametrize("p,q", [(0, 1), (2, 3), (5, 2), (1, 5)])
def test_arma_innovations_equal_lfilter(p, q):
    from modalinfo.forecast._kernels import arma_innovations

    rng = np.random.default_rng(5)
    x = rng.standard_normal(3000)
    phi = -_random_coeffs(rng, p, 0.95) if p else np.zeros(0)
    theta = _random_coeffs(rng, q, 0.95)
    e = np.full(x.size, np.nan)
    arma_innovations(x, phi, theta, e, np.empty((3, max(p, q) + 1)))
    assert np.array_equal(e, lfilter(np.r_[1.0, -phi], np.r_[1.0, theta], x))
