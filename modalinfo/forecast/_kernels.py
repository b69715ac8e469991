"""numba kernels of the forecast predictors.

Every kernel processes a block of ``N`` new samples ``x (N, M)`` for ``M``
independent (or jointly modelled) modes, updates the fixed-size recursion state in
place and writes the forecasts made after each sample into ``out``. The same kernel
serves the offline path (a block of the whole history) and the online path (a
block of one sample), so online and offline forecasts are bit-identical: the
floating-point operations are the same, in the same order.

Conventions
-----------
- ``out`` has shape ``(n_out, H, M)``; the forecasts made after sample ``n`` are
  written to ``out[n - N + n_out]`` when that index is ``>= 0`` (so ``n_out = N``
  keeps every forecast and ``n_out = 1`` only the last one).
- ``status`` (1,) int64 OUT: 0 on success, ``n + 1`` when sample ``n`` holds a
  non-finite value (the state is left as it was after sample ``n - 1``).
- Kernels never validate their inputs and never draw random numbers; the wrappers in
  ``base.py`` and the predictor modules do.
"""

from __future__ import annotations

import numpy as np

from modalinfo.common.jit import jit


@jit
def _row_is_finite(x, n):
    for m in range(x.shape[1]):
        if not np.isfinite(x[n, m]):
            return False
    return True


@jit
def arma_filter(x, coef, n_ar, n_ma, state, work, out, status):
    """ARMA(P, Q) one-step innovations recursion and h-step forecasts.

    Parameters and state are packed in two arrays (fewer arguments make the
    per-call overhead of the online ``update`` smaller).

    Parameters
    ----------
    x : (N, M) float64 IN
        New samples.
    coef : (M, 2 + P + Q) IN
        Per mode: the centring ``mu``, the intercept ``c``, then ``phi_1..phi_P``, then
        ``theta_1..theta_Q`` (zero-padded per mode). With ``y = x - mu`` the model is
        ``y[t] = c + sum_i phi_i y[t - i] + e[t] + sum_j theta_j e[t - j]``; ``c`` is
        added as it is (never turned into a mean ``c / (1 - sum phi)``, which is
        ill-conditioned near a random walk), ``c = 0`` for a model about its mean.
    n_ar, n_ma : int
        ``P`` and ``Q``.
    state : (M, P + Q + 1) INOUT
        Per mode: the last ``P`` centred samples (most recent first), the last ``Q``
        innovations (most recent first), then the centred one-step forecast of the
        next sample (which defines the next innovation).
    work : (H,) scratch
    out : (n_out, H, M) OUT
        Forecasts ``x_hat[n + h]``, h = 1..H, after each sample.
    status : (1,) int64 OUT
    """
    n_samples, n_modes = x.shape
    n_out = out.shape[0]
    horizon = out.shape[1]
    i_pred = n_ar + n_ma
    status[0] = 0
    for n in range(n_samples):
        if not _row_is_finite(x, n):
            status[0] = n + 1
            return
        o = n - n_samples + n_out
        for m in range(n_modes):
            mu = coef[m, 0]
            c = coef[m, 1]
            xc = x[n, m] - mu
            e = xc - state[m, i_pred]
            for i in range(n_ar - 1, 0, -1):
                state[m, i] = state[m, i - 1]
            if n_ar > 0:
                state[m, 0] = xc
            for j in range(n_ma - 1, 0, -1):
                state[m, n_ar + j] = state[m, n_ar + j - 1]
            if n_ma > 0:
                state[m, n_ar] = e
            for h in range(horizon):
                s = c
                for i in range(n_ar):
                    k = h - 1 - i
                    if k >= 0:
                        s += coef[m, 2 + i] * work[k]
                    else:
                        s += coef[m, 2 + i] * state[m, -k - 1]
                for j in range(h, n_ma):
                    s += coef[m, 2 + n_ar + j] * state[m, n_ar + j - h]
                work[h] = s
                if o >= 0:
                    out[o, h, m] = s + mu
            state[m, i_pred] = work[0]


@jit
def _activate(z, activation):
    # 0 identity, 1 relu, 2 tanh, 3 logistic (scikit-learn's names and formulas)
    if activation == 1:
        return z if z > 0.0 else 0.0
    if activation == 2:
        return np.tanh(z)
    if activation == 3:
        return 1.0 / (1.0 + np.exp(-z))
    return z


@jit
def mlp_filter(x, x_mean, x_scale, w1, b1, w2, b2, activation, values, work, out, status):
    """Sliding-window one-hidden-layer perceptron, forecasts iterated for h > 1.

    The network of mode ``m`` maps the standardised window
    ``z_i = (x[t - K + 1 + i] - x_mean[m]) / x_scale[m]`` (oldest first, as the
    training patterns) to the standardised next sample,
    ``y = w2[m] . act(w1[m].T z + b1[m]) + b2[m]``, as scikit-learn's MLPRegressor.

    Parameters
    ----------
    x : (N, M) IN
    x_mean, x_scale : (M,) IN
        Standardisation of inputs and output.
    w1 : (M, K, J) IN ; b1 : (M, J) IN ; w2 : (M, J) IN ; b2 : (M,) IN
    activation : int
        0 identity, 1 relu, 2 tanh, 3 logistic.
    values : (M, K) INOUT
        Last ``K`` standardised samples, ``values[m, K - 1]`` the most recent.
    work : (H + K,) scratch
    out : (n_out, H, M) OUT
    status : (1,) int64 OUT
    """
    n_samples, n_modes = x.shape
    n_in = w1.shape[1]
    n_hidden = w1.shape[2]
    n_out = out.shape[0]
    horizon = out.shape[1]
    status[0] = 0
    for n in range(n_samples):
        if not _row_is_finite(x, n):
            status[0] = n + 1
            return
        o = n - n_samples + n_out
        for m in range(n_modes):
            for i in range(n_in - 1):
                values[m, i] = values[m, i + 1]
            values[m, n_in - 1] = (x[n, m] - x_mean[m]) / x_scale[m]
            for i in range(n_in):
                work[i] = values[m, i]
            for h in range(horizon):
                y = b2[m]
                for j in range(n_hidden):
                    a = b1[m, j]
                    for i in range(n_in):
                        a += work[h + i] * w1[m, i, j]
                    y += _activate(a, activation) * w2[m, j]
                work[h + n_in] = y
                if o >= 0:
                    out[o, h, m] = y * x_scale[m] + x_mean[m]


@jit
def var_filter(x, mu, coef, values, work, out, status):
    """Vector autoregression of order P (all modes predict each mode).

    ``x_hat[t + 1] = mu + sum_i coef[i].T (x[t - i] - mu)``, iterated for h > 1.

    Parameters
    ----------
    x : (N, M) IN
    mu : (M,) IN
    coef : (P, M, M) IN
        ``coef[i, k, m]``: weight of lag ``i + 1`` of mode ``k`` in mode ``m``.
    values : (P, M) INOUT
        Last ``P`` centred samples, ``values[0]`` the most recent.
    work : (H, M) scratch
    out : (n_out, H, M) OUT
    status : (1,) int64 OUT
    """
    n_samples, n_modes = x.shape
    n_lags = coef.shape[0]
    n_out = out.shape[0]
    status[0] = 0
    for n in range(n_samples):
        if not _row_is_finite(x, n):
            status[0] = n + 1
            return
        o = n - n_samples + n_out
        for i in range(n_lags - 1, 0, -1):
            for k in range(n_modes):
                values[i, k] = values[i - 1, k]
        for k in range(n_modes):
            values[0, k] = x[n, k] - mu[k]
        _var_forecast(mu, coef, values, work, out, o)


@jit
def _var_forecast(mu, coef, values, work, out, o):
    n_lags, n_modes, _ = coef.shape
    horizon = work.shape[0]
    for h in range(horizon):
        for m in range(n_modes):
            work[h, m] = 0.0
        for i in range(n_lags):
            k_step = h - 1 - i
            for k in range(n_modes):
                if k_step >= 0:
                    v = work[k_step, k]
                else:
                    v = values[-k_step - 1, k]
                for m in range(n_modes):
                    work[h, m] += coef[i, k, m] * v
        if o >= 0:
            for m in range(n_modes):
                out[o, h, m] = work[h, m] + mu[m]


@jit
def rls_var_filter(x, mu, coef, gain_inv, forgetting, values, n_seen, zvec, pz, work, out, status):
    """Vector autoregression adapted every step by recursive least squares.

    On arrival of ``x_t`` (once ``P`` earlier samples are known) the regression
    vector ``z`` of the ``P`` previous centred samples and the target ``x_t - mu``
    update the weights, ``k = Pz / (lambda + z.T P z)``,
    ``W += k (y - W.T z).T``, ``P = (P - k z.T P) / lambda``, then the forecasts are
    iterated as in :func:`var_filter`.

    Parameters
    ----------
    x : (N, M) IN
    mu : (M,) IN
    coef : (P, M, M) INOUT
        Weights; row-major the same memory as ``W (P * M, M)``.
    gain_inv : (P * M, P * M) INOUT
        The RLS matrix ``P`` (inverse of the exponentially weighted Gram matrix).
    forgetting : float
        Forgetting factor ``lambda`` in (0, 1].
    values : (P, M) INOUT
    n_seen : (1,) int64 INOUT
        Samples seen since reset.
    zvec, pz : (P * M,) scratch
    work : (H, M) scratch
    out : (n_out, H, M) OUT
    status : (1,) int64 OUT
    """
    n_samples, n_modes = x.shape
    n_lags = coef.shape[0]
    dim = n_lags * n_modes
    n_out = out.shape[0]
    status[0] = 0
    for n in range(n_samples):
        if not _row_is_finite(x, n):
            status[0] = n + 1
            return
        o = n - n_samples + n_out
        if n_seen[0] >= n_lags:
            for i in range(n_lags):
                for k in range(n_modes):
                    zvec[i * n_modes + k] = values[i, k]
            denom = forgetting
            for a in range(dim):
                s = 0.0
                for b in range(dim):
                    s += gain_inv[a, b] * zvec[b]
                pz[a] = s
                denom += zvec[a] * s
            for a in range(dim):
                pz[a] /= denom
            # gain k = pz (already divided); P <- (P - k (P z).T) / lambda, P symmetric
            for a in range(dim):
                ka = pz[a]
                for b in range(dim):
                    gain_inv[a, b] = (gain_inv[a, b] - ka * pz[b] * denom) / forgetting
            for m in range(n_modes):
                err = x[n, m] - mu[m]
                for i in range(n_lags):
                    for k in range(n_modes):
                        err -= coef[i, k, m] * values[i, k]
                for i in range(n_lags):
                    for k in range(n_modes):
                        coef[i, k, m] += pz[i * n_modes + k] * err
        n_seen[0] += 1
        for i in range(n_lags - 1, 0, -1):
            for k in range(n_modes):
                values[i, k] = values[i - 1, k]
        for k in range(n_modes):
            values[0, k] = x[n, k] - mu[k]
        _var_forecast(mu, coef, values, work, out, o)


#: the largest AR and MA order of the register kernels (:func:`_css_filters_short`,
#: :func:`_innovations_short`): the order search's default ``max_order``
SHORT_ORDER = 5


@jit
def _css_filters_short(e, ar, ma, v, w, u, y):
    """:func:`css_filters` for ``p, q <= 5``, every filter state a local scalar (issue 30).

    The same recursions with the coefficients zero-padded to order 5: a padded stage
    adds ``-(x 0)`` (a signed zero) to the next state, which leaves every non-zero value
    bit for bit as it was (IEEE 754: ``a + (+-0) = a`` for ``a != 0``), so the outputs
    equal :func:`css_filters`' (and scipy's) but for the sign of an exact zero. Scalars
    let the compiler keep the 20 states in registers instead of storing and reloading
    them from the scratch arrays each sample: ~2x faster at (5, 5), 10^4 samples.
    """
    c = np.zeros(SHORT_ORDER + 1)
    d = np.zeros(SHORT_ORDER + 1)
    for k in range(1, ar.shape[0]):
        c[k] = ar[k]
    for k in range(1, ma.shape[0]):
        d[k] = ma[k]
    c1, c2, c3, c4, c5 = c[1], c[2], c[3], c[4], c[5]
    d1, d2, d3, d4, d5 = d[1], d[2], d[3], d[4], d[5]
    v0 = v1 = v2 = v3 = v4 = 0.0
    w0 = w1 = w2 = w3 = w4 = 0.0
    u0 = u1 = u2 = u3 = u4 = 0.0
    y0 = y1 = y2 = y3 = y4 = 0.0
    for t in range(e.shape[0]):
        x = e[t]
        vn = v0 + x
        v0 = v1 - vn * c1
        v1 = v2 - vn * c2
        v2 = v3 - vn * c3
        v3 = v4 - vn * c4
        v4 = -(vn * c5)
        wn = w0 + x
        un = u0 + vn
        yn = y0 + wn
        w0 = w1 - wn * d1
        u0 = u1 - un * d1
        y0 = y1 - yn * d1
        w1 = w2 - wn * d2
        u1 = u2 - un * d2
        y1 = y2 - yn * d2
        w2 = w3 - wn * d3
        u2 = u3 - un * d3
        y2 = y3 - yn * d3
        w3 = w4 - wn * d4
        u3 = u4 - un * d4
        y3 = y4 - yn * d4
        w4 = -(wn * d5)
        u4 = -(un * d5)
        y4 = -(yn * d5)
        v[t] = vn
        w[t] = wn
        u[t] = un
        y[t] = yn


@jit
def _innovations_short(x, phi, theta, e):
    """:func:`arma_innovations` for ``p, q <= 5``, the filter state in local scalars.

    The same direct form II transposed loop with numerator and denominator zero-padded
    to order 5 (issue 30): the padded stages carry signed zeros only, so ``e`` equals
    :func:`arma_innovations`' (and scipy's) bit for bit but for the sign of an exact
    zero; ~1.5x faster, the states no longer stored and reloaded every sample.
    """
    b = np.zeros(SHORT_ORDER + 1)
    a = np.zeros(SHORT_ORDER + 1)
    for k in range(phi.shape[0]):
        b[k + 1] = -phi[k]
    for k in range(theta.shape[0]):
        a[k + 1] = theta[k]
    b1, b2, b3, b4, b5 = b[1], b[2], b[3], b[4], b[5]
    a1, a2, a3, a4, a5 = a[1], a[2], a[3], a[4], a[5]
    z0 = z1 = z2 = z3 = z4 = 0.0
    for t in range(x.shape[0]):
        xn = x[t]
        en = z0 + 1.0 * xn
        z0 = z1 + xn * b1 - en * a1
        z1 = z2 + xn * b2 - en * a2
        z2 = z3 + xn * b3 - en * a3
        z3 = z4 + xn * b4 - en * a4
        z4 = xn * b5 - en * a5
        e[t] = en


@jit
def css_filters(e, ar, ma, v, w, u, y, zv, zw, zu, zy):
    """Run the four all-pole filters of one CSS Newton step in one pass over time.

    ``v = lfilter([1], ar, e)``, ``w = lfilter([1], ma, e)``, ``u = lfilter([1], ma,
    v)`` and ``y = lfilter([1], ma, w)`` (the first and second derivatives of the
    innovations, see ``arma._css_refine``), each bit for bit what scipy returns: scipy's
    direct form II transposed loop (``DOUBLE_filt`` of ``_lfilter.c``) with the
    numerator ``[1]`` zero-padded to the denominator's length ``L``, per sample
    ``y_t = z_0 + 1 x_t``, ``z_k = z_{k+1} + x_t 0 - y_t a_{k+1}``, ``z_{L-2} = x_t 0 -
    y_t a_{L-1}``, and for ``L = 1`` (scipy's convolution path) ``y = x``. The ``x_t 0``
    products are left out: for finite values adding ``+-0`` leaves every other value's
    bits unchanged (IEEE 754), and they cost a fifth of the loop. Checked against scipy in
    ``tests/forecast/test_arma_fast_paths.py``. One pass runs the four independent
    recursions side by side instead of four scipy calls; orders up to
    :data:`SHORT_ORDER` run in :func:`_css_filters_short` (states in registers, the same
    bits).

    Parameters
    ----------
    e : (T,) float64 IN
        Innovations.
    ar, ma : (p + 1,), (q + 1,) float64 IN
        ``[1, -phi_1, ..]`` and ``[1, theta_1, ..]``.
    v, w, u, y : (T,) float64 OUT
    zv, zw, zu, zy : (max(p, 1),), (max(q, 1),) x 3 scratch
        Filter states (zeroed here: the recursions start from zero state).
    """
    n_ar = ar.shape[0] - 1
    n_ma = ma.shape[0] - 1
    if n_ar <= SHORT_ORDER and n_ma <= SHORT_ORDER:
        _css_filters_short(e, ar, ma, v, w, u, y)
        return
    for k in range(zv.shape[0]):
        zv[k] = 0.0
    for k in range(zw.shape[0]):
        zw[k] = 0.0
        zu[k] = 0.0
        zy[k] = 0.0
    for t in range(e.shape[0]):
        x = e[t]
        if n_ar == 0:
            vn = x
        else:
            vn = zv[0] + x
            for k in range(n_ar - 1):
                zv[k] = zv[k + 1] - vn * ar[k + 1]
            zv[n_ar - 1] = -(vn * ar[n_ar])
        if n_ma == 0:
            wn = x
            un = vn
            yn = wn
        else:
            wn = zw[0] + x
            un = zu[0] + vn
            yn = zy[0] + wn
            for k in range(n_ma - 1):
                c = ma[k + 1]
                zw[k] = zw[k + 1] - wn * c
                zu[k] = zu[k + 1] - un * c
                zy[k] = zy[k + 1] - yn * c
            c = ma[n_ma]
            zw[n_ma - 1] = -(wn * c)
            zu[n_ma - 1] = -(un * c)
            zy[n_ma - 1] = -(yn * c)
        v[t] = vn
        w[t] = wn
        u[t] = un
        y[t] = yn


@jit
def arma_innovations(x, phi, theta, e, z):
    """``e = lfilter([1, -phi], [1, theta], x)`` (``theta`` non-empty), scipy's bits.

    scipy's direct form II transposed loop (``DOUBLE_filt`` of ``_lfilter.c``, the path
    ``lfilter`` takes when the denominator has more than one coefficient) with ``b =
    [1, -phi]`` and ``a = [1, theta]`` zero-padded to one length ``L = max(p, q) + 1``:
    ``e_t = z_0 + 1 x_t``, ``z_k = z_{k+1} + x_t b_{k+1} - e_t a_{k+1}``, ``z_{L-2} = x_t
    b_{L-1} - e_t a_{L-1}``: the same operations in the same order (checked against
    scipy in ``tests/forecast/test_arma_fast_paths.py``), without lfilter's per-call
    overhead, for the CSS refinement's many short fits; orders up to
    :data:`SHORT_ORDER` run in :func:`_innovations_short` (the same bits).

    Parameters
    ----------
    x : (T,) float64 IN
        Centred series.
    phi : (p,) float64 IN
    theta : (q,) float64 IN, q >= 1
    e : (T,) float64 OUT
        Innovations from zero state.
    z : (max(p, q) + 1,) x 3 float64 scratch
        Rows: the padded numerator, the padded denominator, the filter state.
    """
    n = max(phi.shape[0], theta.shape[0])
    if n <= SHORT_ORDER:
        _innovations_short(x, phi, theta, e)
        return
    for k in range(n + 1):
        z[0, k] = 0.0
        z[1, k] = 0.0
        z[2, k] = 0.0
    z[0, 0] = 1.0
    z[1, 0] = 1.0
    for k in range(phi.shape[0]):
        z[0, k + 1] = -phi[k]
    for k in range(theta.shape[0]):
        z[1, k + 1] = theta[k]
    for t in range(x.shape[0]):
        xn = x[t]
        en = z[2, 0] + 1.0 * xn
        for k in range(n - 1):
            z[2, k] = z[2, k + 1] + xn * z[0, k + 1] - en * z[1, k + 1]
        z[2, n - 1] = xn * z[0, n] - en * z[1, n]
        e[t] = en


@jit
def _lagged_sum(x, lag_x, z, lag_z, start):
    """``sum_{t >= max(start, lag_x, lag_z)} x_{t - lag_x} z_{t - lag_z}`` over ``t < len(z)``."""
    lo = max(start, lag_x, lag_z)
    n = z.shape[0]
    return np.dot(x[lo - lag_x:n - lag_x], z[lo - lag_z:n - lag_z])  # BLAS ddot


@jit
def _range_sum(x, z, lag, lo, hi):
    """``sum_{lo <= t < hi} x_t z_{t - lag}``, one term after the other (a few terms)."""
    s = 0.0
    for t in range(lo, hi):
        s += x[t] * z[t - lag]
    return s


@jit
def css_newton_terms(e, ar, ma, start, v, w, u, y, zv, zw, zu, zy, toep, gram, grad, cross):
    """Run the filters and form the normal-equation terms of one CSS Newton step.

    Runs :func:`css_filters` (``v, w, u, y`` from ``e``), then forms the terms that
    ``arma._css_refine`` needs, with the design row ``d_t = (v_{t-1..t-p},
    w_{t-1..t-q})`` (``p = len(ar) - 1``, ``q = len(ma) - 1``) summed over ``t >=
    start``: ``gram = sum_t d_t d_t^T``, ``grad = sum_t d_t e_t`` and the lagged cross
    products ``cross[0, L] = sum_{t >= max(start, L)} e_t u_{t-L}`` (L = 2..p+q) and
    ``cross[1, L] = sum_{t >= max(start, L)} e_t y_{t-L}`` (L = 2..2q) of the Hessian's
    residual terms (each distinct lag once).

    The Gram matrix is Toeplitz but for its ends (issue 30): the entry of lags ``(s, s +
    d)`` of series ``a, b`` is ``sum_{tau = start - s}^{n - 1 - s} a_tau b_{tau - d}``, so
    every entry of one lag difference ``d`` shares the range ``tau in [start - 1, n - 1 -
    max(p, q)]``, summed once by BLAS ``ddot`` (``toep``: ``p`` sums of ``v v``, ``q`` of
    ``w w``, ``q`` of ``v_tau w_{tau - d}``, ``p - 1`` of ``w_tau v_{tau - d}``), and
    each entry adds its own ``s - 1`` first and ``max(p, q) - s`` last terms one by one:
    ``2 (p + q) - 1`` long sums instead of ``(p + q) (p + q + 1) / 2`` (47 instead of 83
    long sums in all at (5, 5)). Every entry is still the sum of exactly its own
    products, in another order than the BLAS products of a design matrix, so equal to
    them within a dot product's rounding bound (``tests/forecast/test_arma_fast_paths.py``).

    Parameters
    ----------
    e : (T,) float64 IN
        Innovations.
    ar, ma : (p + 1,), (q + 1,) float64 IN
    start : int
        First time index summed (``>= max(p, q)``; ``T >= start + max(p, q)``).
    v, w, u, y : (T,) float64 OUT
    zv, zw, zu, zy : scratch of :func:`css_filters`
    toep : (4, max(p, q, 1)) float64 scratch
        The shared long sums of the Gram matrix.
    gram : (p + q, p + q) float64 OUT
    grad : (p + q,) float64 OUT
    cross : (2, max(p + q, 2 q) + 1) float64 OUT
    """
    css_filters(e, ar, ma, v, w, u, y, zv, zw, zu, zy)
    p = ar.shape[0] - 1
    q = ma.shape[0] - 1
    k = p + q
    n = e.shape[0]
    smax = max(p, q)
    lo = start - 1          # the range every Gram entry covers
    hi = n - smax
    for d in range(p):
        toep[0, d] = np.dot(v[lo:hi], v[lo - d:hi - d])  # BLAS ddot
    for d in range(q):
        toep[1, d] = np.dot(w[lo:hi], w[lo - d:hi - d])
        if p > 0:
            toep[2, d] = np.dot(v[lo:hi], w[lo - d:hi - d])
    if q > 0:
        for d in range(1, p):
            toep[3, d] = np.dot(w[lo:hi], v[lo - d:hi - d])
    for a in range(k):
        for b in range(a, k):
            if b < p:                   # v lag a + 1 with v lag b + 1
                s, d, xa, zb, row = a + 1, b - a, v, v, 0
            elif a >= p:                # w lag a - p + 1 with w lag b - p + 1
                s, d, xa, zb, row = a - p + 1, b - a, w, w, 1
            elif b - p >= a:            # v lag i with w lag j >= i
                s, d, xa, zb, row = a + 1, b - p - a, v, w, 2
            else:                       # v lag i with w lag j < i
                s, d, xa, zb, row = b - p + 1, a + p - b, w, v, 3
            total = toep[row, d]
            total += _range_sum(xa, zb, d, start - s, lo)
            total += _range_sum(xa, zb, d, hi, n - s)
            gram[a, b] = total
            gram[b, a] = total
    for a in range(k):
        xa = v if a < p else w
        la = a + 1 if a < p else a - p + 1
        grad[a] = _lagged_sum(xa, la, e, 0, start)
    for r in range(cross.shape[0]):
        for c in range(cross.shape[1]):
            cross[r, c] = 0.0
    if q > 0:
        for lag in range(2, k + 1):
            cross[0, lag] = _lagged_sum(u, lag, e, 0, start)
        for lag in range(2, 2 * q + 1):
            cross[1, lag] = _lagged_sum(y, lag, e, 0, start)


@jit
def clearly_inside(coeffs, radius, safe):
    """Tell whether every inverse root of ``1 + c_1 z + ...`` is inside ``radius (1 - safe)``.

    Schur-Cohn's step-down test (Levinson-Durbin run backwards: every reflection
    coefficient of the monic polynomial ``prod (s - w_k / r)`` strictly inside the unit
    disc iff all its roots are) on the inverse roots scaled by ``r = radius (1 - safe)``,
    with the reflection coefficients also kept ``safe`` from 1. It answers "yes" only
    when the roots are inside by a margin far above the rounding of a root finder, so
    where it answers "yes" :func:`enforce_roots`'s root test would also keep ``coeffs``.
    """
    r = radius * (1.0 - safe)
    n = coeffs.shape[0]
    a = np.empty(n)
    scale = 1.0
    for k in range(n):
        scale *= r
        a[k] = coeffs[k] / scale
    b = np.empty(n)
    while n > 0:
        k_refl = a[n - 1]
        if not abs(k_refl) < 1.0 - safe:
            return False
        den = 1.0 - k_refl * k_refl
        for i in range(n - 1):
            b[i] = (a[i] - k_refl * a[n - 2 - i]) / den
        for i in range(n - 1):
            a[i] = b[i]
        n -= 1
    return True


@jit
def enforce_roots(coeffs, margin, safe, out):
    """``out``: ``coeffs`` with every inverse root inside modulus ``1 / (1 + margin)``.

    Inverse roots ``w`` of ``1 + c_1 z + ... + c_n z^n = prod (1 - w_k z)`` with ``|w| >=
    1`` are reflected (``w -> 1 / conj(w)``) and every modulus is capped at the limit;
    the polynomial is rebuilt as ``np.poly`` does (sequential convolution with ``(1,
    -w_k)``, real part). Coefficients that :func:`clearly_inside` passes, or whose
    roots are all inside the limit, are copied unchanged. ``out`` may be ``coeffs``.
    """
    n = coeffs.shape[0]
    if n == 0:
        return
    limit = 1.0 / (1.0 + margin)
    if clearly_inside(coeffs, limit, safe):
        for k in range(n):
            out[k] = coeffs[k]
        return
    poly = np.empty(n + 1, dtype=np.complex128)
    poly[0] = 1.0
    for k in range(n):
        poly[k + 1] = coeffs[k]
    w = np.roots(poly)
    inside = True
    for k in range(w.shape[0]):
        if not abs(w[k]) < limit:
            inside = False
    if inside:
        for k in range(n):
            out[k] = coeffs[k]
        return
    rebuilt = np.zeros(n + 1, dtype=np.complex128)
    rebuilt[0] = 1.0
    for k in range(w.shape[0]):
        mod = abs(w[k])
        new_mod = 1.0 / max(mod, 1e-300) if mod >= 1.0 else mod
        new_mod = min(new_mod, limit)
        root = w[k] / max(mod, 1e-300) * new_mod if mod > 0 else w[k]
        for i in range(k + 1, 0, -1):  # (1, a_1, ..) * (1, -root), in place from the back
            rebuilt[i] = rebuilt[i] - root * rebuilt[i - 1]
    for k in range(n):
        out[k] = rebuilt[k + 1].real
    # np.roots drops zero roots for trailing zero coefficients only to add them back,
    # so w has n entries and the rebuilt polynomial has degree n


@jit
def _solve_small(a, b, x, work):
    """Solve ``a x = b`` (k <= ~20) by Gaussian elimination with partial pivoting.

    Returns False for a singular matrix (an exactly zero pivot, LAPACK ``getrf``'s
    test). ``work`` is a ``(k, k + 1)`` scratch.
    """
    k = b.shape[0]
    for i in range(k):
        for j in range(k):
            work[i, j] = a[i, j]
        work[i, k] = b[i]
    for c in range(k):
        piv = c
        best = abs(work[c, c])
        for r in range(c + 1, k):
            if abs(work[r, c]) > best:
                best = abs(work[r, c])
                piv = r
        if best == 0.0:
            return False
        if piv != c:
            for j in range(c, k + 1):
                tmp = work[c, j]
                work[c, j] = work[piv, j]
                work[piv, j] = tmp
        for r in range(c + 1, k):
            f = work[r, c] / work[c, c]
            for j in range(c, k + 1):
                work[r, j] -= f * work[c, j]
    for i in range(k - 1, -1, -1):
        s = work[i, k]
        for j in range(i + 1, k):
            s -= work[i, j] * x[j]
        x[i] = s / work[i, i]
    return True


@jit
def _sum_squares(e, burn):
    return np.dot(e[burn:], e[burn:])  # BLAS ddot, as numpy's e @ e


@jit
def _innovations_pair(x, phi_a, theta_a, e_a, phi_b, theta_b, e_b):
    """:func:`_innovations_short` of two models in one pass over ``x`` (orders <= 5).

    Each recursion is :func:`_innovations_short`'s, operation for operation (the same
    bits); running two in one loop lets the processor overlap the two latency-bound
    chains (one pass ~1.4x the cost of one model instead of 2x, issue 30).
    """
    b = np.zeros((2, SHORT_ORDER + 1))
    a = np.zeros((2, SHORT_ORDER + 1))
    for k in range(phi_a.shape[0]):
        b[0, k + 1] = -phi_a[k]
    for k in range(theta_a.shape[0]):
        a[0, k + 1] = theta_a[k]
    for k in range(phi_b.shape[0]):
        b[1, k + 1] = -phi_b[k]
    for k in range(theta_b.shape[0]):
        a[1, k + 1] = theta_b[k]
    b1, b2, b3, b4, b5 = b[0, 1], b[0, 2], b[0, 3], b[0, 4], b[0, 5]
    a1, a2, a3, a4, a5 = a[0, 1], a[0, 2], a[0, 3], a[0, 4], a[0, 5]
    g1, g2, g3, g4, g5 = b[1, 1], b[1, 2], b[1, 3], b[1, 4], b[1, 5]
    h1, h2, h3, h4, h5 = a[1, 1], a[1, 2], a[1, 3], a[1, 4], a[1, 5]
    z0 = z1 = z2 = z3 = z4 = 0.0
    s0 = s1 = s2 = s3 = s4 = 0.0
    for t in range(x.shape[0]):
        xn = x[t]
        en = z0 + 1.0 * xn
        fn = s0 + 1.0 * xn
        z0 = z1 + xn * b1 - en * a1
        s0 = s1 + xn * g1 - fn * h1
        z1 = z2 + xn * b2 - en * a2
        s1 = s2 + xn * g2 - fn * h2
        z2 = z3 + xn * b3 - en * a3
        s2 = s3 + xn * g3 - fn * h3
        z3 = z4 + xn * b4 - en * a4
        s3 = s4 + xn * g4 - fn * h4
        z4 = xn * b5 - en * a5
        s4 = xn * g5 - fn * h5
        e_a[t] = en
        e_b[t] = fn


# slots of a fit's scalar state in the batch driver (_fit_* below)
_SSE, _LAM, _PRED, _ITER, _TERMS, _CUR = 0, 1, 2, 3, 4, 5


@jit
def _fit_start(xc, phi0, theta0, margin, safe, burn, lambdas):
    """Start one CSS fit of :func:`css_newton_batch`; return its state tuple.

    The start's AR and MA roots are enforced (:func:`enforce_roots`), then its
    innovations and their sum of squares after ``burn`` are formed.
    """
    p = phi0.shape[0]
    q = theta0.shape[0]
    k = p + q
    n = xc.shape[0]
    phi = np.empty(p)
    for i in range(p):
        phi[i] = -phi0[i]
    enforce_roots(phi, margin, safe, phi)
    for i in range(p):
        phi[i] = -phi[i]
    theta = theta0.copy()
    enforce_roots(theta, margin, safe, theta)
    zf = np.empty((3, max(p, q) + 1))
    ee = np.empty((2, n))
    arma_innovations(xc, phi, theta, ee[0], zf)
    f = np.zeros(6)
    f[_SSE] = _sum_squares(ee[0], burn)
    f[_LAM] = lambdas[0]
    f[_TERMS] = 1.0
    return (f, phi, theta, np.empty(p), np.empty(q), ee, np.empty((4, n)),
            np.empty(max(p, 1)), np.empty((3, q)), np.empty((k, k)), np.empty(k),
            np.empty((k, k)), np.empty((k, k)), np.empty((2, max(k, 2 * q) + 1)),
            np.empty((4, max(p, q, 1))), np.empty(k), np.empty((k, k + 1)),
            np.empty(p + 1), np.empty(q + 1), zf)


@jit
def _fit_propose(st, margin, safe, burn, n_iter, lambdas):
    """Next trial of a fit (True), or False when the fit stops here.

    At the start of an iteration (after an accepted step, or the start) the Newton
    terms (:func:`css_newton_terms`, :func:`_newton_hessian`), unless ``n_iter`` steps
    were accepted; then the damping ladder: the Marquardt-damped system ``(H + lambda
    diag(gram)) step = grad`` solved, lambda x10 while it is singular or the step is
    not a descent direction, and the candidate made causal and invertible
    (:func:`enforce_roots`). False when lambda passes ``lambdas[2]`` (no damping
    lowered the sum of squares).
    """
    (f, phi, theta, phi_new, theta_new, ee, vwuy, z_ar, z_ma, gram, grad, hess, lhs,
     cross, toep, step, work, ar, ma, zf) = st
    p = phi.shape[0]
    q = theta.shape[0]
    k = p + q
    if f[_TERMS] != 0.0:
        if f[_ITER] >= n_iter:
            return False
        ar[0] = 1.0
        for i in range(p):
            ar[i + 1] = -phi[i]
        ma[0] = 1.0
        for j in range(q):
            ma[j + 1] = theta[j]
        start = max(p, q, burn)
        css_newton_terms(ee[int(f[_CUR])], ar, ma, start, vwuy[0], vwuy[1], vwuy[2],
                         vwuy[3], z_ar, z_ma[0], z_ma[1], z_ma[2], toep, gram, grad, cross)
        _newton_hessian(gram, cross, p, q, hess)
        f[_TERMS] = 0.0
    lam = f[_LAM]
    while lam <= lambdas[2]:
        for a in range(k):
            for b in range(k):
                lhs[a, b] = hess[a, b]
            lhs[a, a] += lam * max(gram[a, a], 1e-300)
        if not _solve_small(lhs, grad, step, work):
            lam *= 10.0
            continue
        predicted = 0.0
        for a in range(k):
            predicted += step[a] * grad[a]
        if not predicted > 0.0:
            lam *= 10.0
            continue
        for i in range(p):
            phi_new[i] = -(phi[i] + step[i])
        enforce_roots(phi_new, margin, safe, phi_new)
        for i in range(p):
            phi_new[i] = -phi_new[i]
        for j in range(q):
            theta_new[j] = theta[j] + step[p + j]
        enforce_roots(theta_new, margin, safe, theta_new)
        f[_LAM] = lam
        f[_PRED] = predicted
        return True
    f[_LAM] = lam
    return False


@jit
def _fit_judge(st, burn, lambdas, tols):
    """Accept or reject a fit's trial (its innovations in the spare buffer).

    A trial that does not lower the sum of squares is rejected (lambda x10); an accepted
    one becomes the fit (lambda / 10, not below ``lambdas[1]``). Returns False when the
    fit has converged: predicted decrease at most ``tols[0]`` of the sum of squares or
    largest coefficient change at most ``tols[1]``.
    """
    f, phi, theta, phi_new, theta_new, ee = st[0], st[1], st[2], st[3], st[4], st[5]
    cur = int(f[_CUR])
    sse_new = _sum_squares(ee[1 - cur], burn)
    if not sse_new < f[_SSE]:
        f[_LAM] *= 10.0
        return True
    moved = 0.0
    for i in range(phi.shape[0]):
        moved = max(moved, abs(phi_new[i] - phi[i]))
        phi[i] = phi_new[i]
    for j in range(theta.shape[0]):
        moved = max(moved, abs(theta_new[j] - theta[j]))
        theta[j] = theta_new[j]
    f[_CUR] = 1 - cur
    f[_SSE] = sse_new
    f[_LAM] = max(f[_LAM] / 10.0, lambdas[1])
    f[_ITER] += 1.0
    f[_TERMS] = 1.0
    return not (f[_PRED] <= tols[0] * sse_new or moved <= tols[1])


@jit
def _newton_hessian(gram, cross, p, q, hess):
    """``hess``: the Gram matrix plus the residual terms (see ``arma._css_refine``)."""
    k = p + q
    for a in range(k):
        for b in range(k):
            hess[a, b] = gram[a, b]
    for i in range(p):
        for j in range(q):
            c = cross[0, i + j + 2]
            hess[i, p + j] += c
            hess[p + j, i] += c
    for j in range(q):
        for jj in range(j, q):
            c = 2.0 * cross[1, j + jj + 2]
            hess[p + j, p + jj] += c
            if jj != j:
                hess[p + jj, p + j] += c


@jit
def _next_trial(xc, phi0, theta0, orders, nxt, margin, safe, burn, n_iter, lambdas, tols,
                phi_out, theta_out, sse_out, st, index):
    """Run fit ``index``'s state machine to its next trial, storing it when it ends.

    Returns ``(state, index, nxt, pending)``: when a fit ends its result is written and
    the next unstarted fit (``nxt``) takes the slot; ``index = -1`` once none is left.
    """
    while index >= 0:
        if _fit_propose(st, margin, safe, burn, n_iter, lambdas):
            return st, index, nxt, True
        p, q = orders[index, 0], orders[index, 1]
        for i in range(p):
            phi_out[index, i] = st[1][i]
        for j in range(q):
            theta_out[index, j] = st[2][j]
        sse_out[index] = st[0][_SSE]
        if nxt >= orders.shape[0]:
            return st, -1, nxt, False
        index = nxt
        nxt += 1
        p, q = orders[index, 0], orders[index, 1]
        st = _fit_start(xc, phi0[index, :p], theta0[index, :q], margin, safe, burn, lambdas)
    return st, index, nxt, False


@jit
def css_newton_batch(xc, phi0, theta0, orders, margin, safe, burn, n_iter, lambdas, tols,
                     phi_out, theta_out, sse_out):
    """Damped Newton minimisation of the CSS (``arma._css_refine``) for several orders.

    Each fit is a small state machine (:func:`_fit_start`, :func:`_fit_propose`,
    :func:`_fit_judge`): per step the Newton terms, the damping ladder, the trial's
    innovations and its acceptance. Two fits advance side by side and their trial
    innovations, the latency-bound part of a step, are computed in one pass
    (:func:`_innovations_pair`, issue 30): the same operations as one fit alone
    (:func:`arma_innovations`), so every fit's bits are those it has alone
    (:func:`css_newton`). With two or more fits the orders must be ``p, q <=
    SHORT_ORDER``; ``q >= 1`` always.

    Parameters
    ----------
    xc : (T,) float64 IN
    phi0, theta0 : (K, >= max p), (K, >= max q) float64 IN
        Starts, row ``i`` zero-padded beyond ``orders[i]``.
    orders : (K, 2) int64 IN
        ``(p, q)`` of every fit.
    margin, safe : float
        Root margin (:func:`enforce_roots`) and Schur-Cohn's safety (:func:`clearly_inside`).
    burn : int
        Innovations left out of the sum of squares.
    n_iter : int
        Most accepted steps per fit.
    lambdas : (3,) float64
        ``(lambda_0, lambda_min, lambda_max)`` of the damping.
    tols : (2,) float64
        ``(ftol, xtol)`` of the stopping rule (:func:`_fit_judge`).
    phi_out, theta_out : like ``phi0``, ``theta0`` OUT
    sse_out : (K,) float64 OUT
        Each fit's sum of squares after ``burn``.
    """
    n_fits = orders.shape[0]
    if n_fits == 0:
        return
    sa = _fit_start(xc, phi0[0, :orders[0, 0]], theta0[0, :orders[0, 1]], margin, safe,
                    burn, lambdas)
    ia = 0
    ib = -1
    sb = sa
    nxt = 1
    if n_fits > 1:
        sb = _fit_start(xc, phi0[1, :orders[1, 0]], theta0[1, :orders[1, 1]], margin,
                        safe, burn, lambdas)
        ib = 1
        nxt = 2
    pend_b = False
    pend_a = False
    while True:
        sa, ia, nxt, pend_a = _next_trial(xc, phi0, theta0, orders, nxt, margin, safe, burn,
                                          n_iter, lambdas, tols, phi_out, theta_out,
                                          sse_out, sa, ia)
        if ib >= 0:
            sb, ib, nxt, pend_b = _next_trial(xc, phi0, theta0, orders, nxt, margin, safe,
                                              burn, n_iter, lambdas, tols, phi_out,
                                              theta_out, sse_out, sb, ib)
        else:
            pend_b = False
        if not pend_a and not pend_b:
            return
        if pend_a and pend_b:
            _innovations_pair(xc, sa[3], sa[4], sa[5][1 - int(sa[0][_CUR])],
                              sb[3], sb[4], sb[5][1 - int(sb[0][_CUR])])
        elif pend_a:
            arma_innovations(xc, sa[3], sa[4], sa[5][1 - int(sa[0][_CUR])], sa[19])
        else:
            arma_innovations(xc, sb[3], sb[4], sb[5][1 - int(sb[0][_CUR])], sb[19])
        if pend_a and not _fit_judge(sa, burn, lambdas, tols):
            sa[0][_ITER] = n_iter          # converged: the next proposal ends it
            sa[0][_TERMS] = 1.0
        if pend_b and not _fit_judge(sb, burn, lambdas, tols):
            sb[0][_ITER] = n_iter
            sb[0][_TERMS] = 1.0


@jit
def css_newton(xc, phi, theta, margin, safe, burn, n_iter, lambdas, tols):
    """One CSS fit (see ``arma._css_refine``): :func:`css_newton_batch` of one order.

    ``phi`` (p,) and ``theta`` (q >= 1,) are the start, overwritten with the result (any
    orders); returns the sum of squares of the innovations after ``burn``. Arguments as
    :func:`css_newton_batch`'s.
    """
    p = phi.shape[0]
    q = theta.shape[0]
    orders = np.empty((1, 2), dtype=np.int64)
    orders[0, 0] = p
    orders[0, 1] = q
    phi0 = np.empty((1, p))
    theta0 = np.empty((1, q))
    for i in range(p):
        phi0[0, i] = phi[i]
    for j in range(q):
        theta0[0, j] = theta[j]
    phi_out = np.empty((1, p))
    theta_out = np.empty((1, q))
    sse = np.empty(1)
    css_newton_batch(xc, phi0, theta0, orders, margin, safe, burn, n_iter, lambdas, tols,
                     phi_out, theta_out, sse)
    for i in range(p):
        phi[i] = phi_out[0, i]
    for j in range(q):
        theta[j] = theta_out[0, j]
    return sse[0]
