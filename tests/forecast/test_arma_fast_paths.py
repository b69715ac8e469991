"""The ARMA fit's fast paths against the code paths they replace.

References (outside the kernels): ``numpy.roots`` / ``numpy.poly`` for the root test
that ``_kernels.clearly_inside`` short-cuts and for ``enforce_roots``; ``numpy.column_stack``
of fancy-indexed lags for ``_lag_matrix`` and, with ``numpy.linalg.lstsq``, for the
order search's shared Hannan-Rissanen regressions; ``scipy.signal.lfilter`` for the filters of
``css_filters`` and ``arma_innovations`` (bit for bit, in their register kernels for orders
up to 5 and their general loops above); the BLAS products of an explicit
design matrix for ``css_newton_terms`` (within the float error bound of a dot product,
``n eps sum |x_i y_i|``); and the whole CSS refinement as it was before issue 30's
fused kernel (lfilter, numpy's solve and roots, written out below), whose fits the
kernel's must match within the stopping rule's tolerance (the summation order
differs, so not bit for bit); the order search's batch driver (two fits side by side)
against ``css_newton`` (the same driver with one fit, its innovations by
``arma_innovations`` alone) one fit at a time, bit for bit. Small sizes: the file runs in a
few seconds.
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


def _numpy_enforce(coeffs, margin):
    """The root test of ``_enforce`` before issue 30, on numpy's root finder."""
    if coeffs.size == 0:
        return coeffs
    w = np.roots(np.concatenate([[1.0], coeffs]))
    limit = 1.0 / (1.0 + margin)
    mod = np.abs(w)
    if np.all(mod < limit):
        return coeffs
    new_mod = np.minimum(np.where(mod >= 1.0, 1.0 / np.maximum(mod, 1e-300), mod), limit)
    w = np.where(mod > 0, w / np.maximum(mod, 1e-300) * new_mod, w)
    return np.real(np.poly(w))[1:]


def test_enforce_matches_numpy_roots():
    rng = np.random.default_rng(1)
    cases = [_random_coeffs(rng, int(rng.integers(1, 6)), 1.1) for _ in range(500)]
    changed = 0
    for c in cases:
        got, ref = A._enforce(c, 1e-3), _numpy_enforce(c, 1e-3)
        # both root finders are backward stable: the rebuilt coefficients agree to a
        # few hundred eps of their size (a 1e-8 error would be a wrong root)
        np.testing.assert_allclose(got, ref, rtol=0, atol=1e-11 * (1 + np.abs(c).sum()))
        if not np.array_equal(ref, c):
            changed += 1
            assert np.abs(np.roots(np.r_[1.0, got])).max() < 1 / 1.001 * (1 + 1e-9)
        else:
            assert np.array_equal(got, c)   # kept coefficients are returned unchanged
    assert 50 < changed < 450          # both paths exercised


def test_lag_matrix_equals_column_stack():
    rng = np.random.default_rng(2)
    a, b = rng.standard_normal(50), rng.standard_normal(50)
    rows = np.arange(7, 50)
    ref = np.column_stack([a[rows - i] for i in range(1, 3)] + [b[rows - i] for i in range(1, 5)])
    out = A._lag_matrix(7, (a, 2), (b, 4))
    assert out.flags.c_contiguous and np.array_equal(out, ref)


def test_shared_regressions_equal_each_order_least_squares():
    rng = np.random.default_rng(7)
    x = lfilter([1.0, -0.5, 0.2], [1.0, -1.3, 0.4], rng.standard_normal(2000))
    xc = (x - x.mean()) / x.std()
    long_order = 30
    z = lfilter(np.r_[1.0, -A._yule_walker(A.sample_autocovariance(xc, 31), 30)], [1.0], xc)
    shared = A._SharedRegressions(xc, z, long_order, 4, 5)
    for p in range(5):
        for q in range(1, 6):
            rows = np.arange(long_order + max(p, q), xc.size)   # B&D 5.1.4, step 2
            design = np.column_stack([xc[rows - i] for i in range(1, p + 1)]
                                     + [z[rows - j] for j in range(1, q + 1)])
            ref = np.linalg.lstsq(design, xc[rows], rcond=None)[0]
            phi, theta = shared.solve(p, q)
            # normal equations of a design with condition number < 1e3: ~1e-12 apart
            np.testing.assert_allclose(np.r_[phi, theta], ref, rtol=0, atol=1e-9)


# orders up to 5 run in the register kernel (_css_filters_short, _innovations_short), larger
# ones in the general loop: both against scipy
@pytest.mark.parametrize("p,q", [(0, 1), (1, 0), (2, 3), (5, 5), (0, 0), (6, 2), (3, 7)])
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


@pytest.mark.parametrize("p,q", [(0, 1), (2, 3), (5, 5), (3, 1), (6, 2)])
def test_css_newton_terms_equal_the_design_products(p, q):
    from modalinfo.forecast._kernels import css_newton_terms

    rng = np.random.default_rng(6)
    n, start = 2000, 50
    e = rng.standard_normal(n)
    ar = np.r_[1.0, _random_coeffs(rng, p, 0.8)] if p else np.ones(1)
    ma = np.r_[1.0, _random_coeffs(rng, q, 0.8)]  # inverse roots below 0.96: stable
    v, w, u, y = (np.empty(n) for _ in range(4))
    k = p + q
    gram, grad = np.empty((k, k)), np.empty(k)
    cross = np.full((2, max(k, 2 * q) + 1), np.nan)
    css_newton_terms(e, ar, ma, start, v, w, u, y, np.empty(max(p, 1)),
                     *np.empty((3, q)), np.empty((4, max(p, q))), gram, grad, cross)
    rv, rw = lfilter([1.0], ar, e), lfilter([1.0], ma, e)
    ru, ry = lfilter([1.0], ma, rv), lfilter([1.0], ma, rw)
    rows = np.arange(start, n)
    design = np.column_stack([rv[rows - i] for i in range(1, p + 1)]
                             + [rw[rows - j] for j in range(1, q + 1)])
    eps = np.finfo(float).eps
    # a dot product of n terms is exact to n eps sum |x_i y_i| (Higham 2002, eq. 3.5)
    ad = np.abs(design)
    np.testing.assert_array_less(np.abs(gram - design.T @ design), n * eps * (ad.T @ ad) + 1e-300)
    np.testing.assert_array_less(np.abs(grad - design.T @ e[start:]),
                                 n * eps * (ad.T @ np.abs(e[start:])) + 1e-300)
    for row, series, lags in ((0, ru, range(2, k + 1)), (1, ry, range(2, 2 * q + 1))):
        for lag in lags:
            ref = e[start:] @ series[start - lag:n - lag]
            bound = n * eps * (np.abs(e[start:]) @ np.abs(series[start - lag:n - lag]))
            assert abs(cross[row, lag] - ref) <= bound, (row, lag)


def _lagged(e, z, start, lag):
    lo = max(start, lag)
    return float(e[lo:] @ z[lo - lag:z.size - lag])


def _former_css_refine(xc, phi, theta, margin, burn, n_iter):
    """``arma._css_refine`` as it was before issue 30 (lfilter, BLAS, numpy's solve)."""
    p, q = phi.size, theta.size
    enf_ar = lambda c: -_numpy_enforce(-c, margin)  # noqa: E731
    innov = lambda f, t: lfilter(np.r_[1.0, -f], np.r_[1.0, t], xc)  # noqa: E731
    phi, theta = enf_ar(phi), _numpy_enforce(theta, margin)
    e = innov(phi, theta)
    sse = float(e[burn:] @ e[burn:])
    start = max(p, q, burn)
    lam = A._LAMBDA0
    rows = np.arange(start, xc.size)
    for _ in range(n_iter):
        ar, ma = np.r_[1.0, -phi], np.r_[1.0, theta]
        v, w = lfilter([1.0], ar, e), lfilter([1.0], ma, e)
        u, y = lfilter([1.0], ma, v), lfilter([1.0], ma, w)
        design = np.column_stack([v[rows - i] for i in range(1, p + 1)]
                                 + [w[rows - j] for j in range(1, q + 1)])
        gram = design.T @ design
        grad = design.T @ e[start:]
        hess = gram.copy()
        for i in range(p):
            for j in range(q):
                c = _lagged(e, u, start, i + j + 2)
                hess[i, p + j] += c
                hess[p + j, i] += c
        for j in range(q):
            for jj in range(j, q):
                c = 2.0 * _lagged(e, y, start, j + jj + 2)
                hess[p + j, p + jj] += c
                if jj != j:
                    hess[p + jj, p + j] += c
        damp = np.diag(np.maximum(np.diag(gram), 1e-300))
        accepted = False
        while lam <= A._LAMBDA_MAX:
            try:
                step = np.linalg.solve(hess + lam * damp, grad)
            except np.linalg.LinAlgError:
                lam *= 10.0
                continue
            if not step @ grad > 0.0:
                lam *= 10.0
                continue
            phi_new, theta_new = enf_ar(phi + step[:p]), _numpy_enforce(theta + step[p:], margin)
            e_new = innov(phi_new, theta_new)
            sse_new = float(e_new[burn:] @ e_new[burn:])
            if sse_new < sse:
                accepted = True
                break
            lam *= 10.0
        if not accepted:
            break
        moved = max(np.abs(phi_new - phi).max(initial=0.0),
                    np.abs(theta_new - theta).max(initial=0.0))
        predicted = float(step @ grad)
        phi, theta, e, sse = phi_new, theta_new, e_new, sse_new
        lam = max(lam / 10.0, A._LAMBDA_MIN)
        if predicted <= A._FTOL * sse or moved <= A._XTOL:
            break
    return phi, theta, sse / (xc.size - burn)


def _closed_loop_like(n=900, seed=4):
    rng = np.random.default_rng(seed)
    e = rng.standard_normal((n, 2))
    # an AR root near the unit circle partly cancelled by an MA root (closed-loop-like)
    # and a plain ARMA(2, 3): both identified, so their CSS minima are well defined
    return np.column_stack([lfilter([1.0, -0.9], [1.0, -0.995], e[:, 0]),
                            lfilter([1.0, -0.5, 0.2, 0.15], [1.0, -1.3, 0.4], e[:, 1])])


@pytest.mark.parametrize("order", [(2, 3), "aic"])
def test_fit_matches_the_former_refinement(monkeypatch, order):
    x = _closed_loop_like()
    make = lambda: ARMAPredictor(order=order, max_order=2)  # noqa: E731
    fast = make().fit(x).params_
    monkeypatch.setattr(A, "_css_refine", _former_css_refine)
    # the order search refines its candidates in one batch call: route it to the former
    # refinement too, one start at a time
    monkeypatch.setattr(A, "_css_refine_all", lambda xc, starts, margin, burn, n_iter: {
        order: _former_css_refine(xc, phi, theta, margin, burn, n_iter)
        for order, (phi, theta) in starts.items()})
    slow = make().fit(x).params_
    # the stopping rule (relative decrease 1e-13, step 1e-10) fixes the minimum to
    # ~sqrt(1e-13) of the coefficients' scale on these well-conditioned fits; sigma^2,
    # second order in the coefficients there, to ~1e-13 (rounding of the sums aside)
    assert np.array_equal(fast["orders"], slow["orders"])
    np.testing.assert_allclose(fast["phi"], slow["phi"], rtol=0, atol=1e-5)
    np.testing.assert_allclose(fast["theta"], slow["theta"], rtol=0, atol=1e-5)
    np.testing.assert_allclose(fast["sigma2"], slow["sigma2"], rtol=1e-11)
    assert np.array_equal(fast["mu"], slow["mu"])
    if order == "aic":
        np.testing.assert_allclose(fast["criterion"], slow["criterion"], rtol=1e-11)


@pytest.mark.parametrize("p,q", [(0, 1), (2, 3), (5, 2), (1, 5), (6, 1), (2, 7)])
def test_arma_innovations_equal_lfilter(p, q):
    from modalinfo.forecast._kernels import arma_innovations

    rng = np.random.default_rng(5)
    x = rng.standard_normal(3000)
    phi = -_random_coeffs(rng, p, 0.95) if p else np.zeros(0)
    theta = _random_coeffs(rng, q, 0.95)
    e = np.full(x.size, np.nan)
    arma_innovations(x, phi, theta, e, np.empty((3, max(p, q) + 1)))
    assert np.array_equal(e, lfilter(np.r_[1.0, -phi], np.r_[1.0, theta], x))


def test_css_newton_batch_is_css_newton_fit_by_fit():
    """Two fits side by side give each fit the bits it has alone (``css_newton``).

    Odd and even numbers of fits (a slot left alone, fits ending at different steps),
    ``n_iter`` 0 (the enforced start), 2 (stopped by the cap) and 50, starts with roots
    outside the unit circle (enforced first), on a closed-loop-like series.
    """
    from modalinfo.forecast._kernels import css_newton, css_newton_batch

    rng = np.random.default_rng(11)
    xc = _closed_loop_like(n=1200)[:, 0]
    xc = (xc - xc.mean()) / xc.std()
    orders = np.array([(p, q) for p in range(6) for q in range(1, 6)], dtype=np.int64)
    phi0 = rng.uniform(-0.6, 0.6, (orders.shape[0], 5))
    theta0 = rng.uniform(-0.6, 0.6, (orders.shape[0], 5))
    phi0[3, :2], theta0[7, :1] = (1.5, -0.2), (-1.4,)   # non-causal / non-invertible starts
    lambdas, tols = np.array([A._LAMBDA0, A._LAMBDA_MIN, A._LAMBDA_MAX]), np.array(
        [A._FTOL, A._XTOL])
    for n_iter, pick in ((50, slice(None)), (50, slice(0, 7)), (2, slice(5, 13)),
                         (0, slice(0, 1))):
        sub = orders[pick]
        phi_out, theta_out = np.full((sub.shape[0], 5), np.nan), np.full((sub.shape[0], 5),
                                                                         np.nan)
        sse = np.full(sub.shape[0], np.nan)
        css_newton_batch(xc, phi0[pick], theta0[pick], sub, 1e-3, A._SAFE, 50, n_iter,
                         lambdas, tols, phi_out, theta_out, sse)
        for i, (p, q) in enumerate(sub):
            phi, theta = phi0[pick][i, :p].copy(), theta0[pick][i, :q].copy()
            ref = css_newton(xc, phi, theta, 1e-3, A._SAFE, 50, n_iter, lambdas, tols)
            assert sse[i] == ref, (n_iter, p, q)
            assert np.array_equal(phi_out[i, :p], phi) and np.array_equal(theta_out[i, :q],
                                                                          theta)


def test_innovations_pair_equal_lfilter():
    from modalinfo.forecast._kernels import _innovations_pair

    rng = np.random.default_rng(12)
    x = rng.standard_normal(2000)
    phi_a, theta_a = -_random_coeffs(rng, 5, 0.95), _random_coeffs(rng, 2, 0.95)
    phi_b, theta_b = np.zeros(0), _random_coeffs(rng, 5, 0.95)
    e_a, e_b = np.full(x.size, np.nan), np.full(x.size, np.nan)
    _innovations_pair(x, phi_a, theta_a, e_a, phi_b, theta_b, e_b)
    assert np.array_equal(e_a, lfilter(np.r_[1.0, -phi_a], np.r_[1.0, theta_a], x))
    assert np.array_equal(e_b, lfilter([1.0], np.r_[1.0, theta_b], x))
