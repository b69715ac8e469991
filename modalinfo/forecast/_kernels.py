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
    coef : (M, 1 + P + Q) IN
        Per mode: the mean ``mu``, then ``phi_1..phi_P``, then ``theta_1..theta_Q``
        (zero-padded per mode).
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
                s = 0.0
                for i in range(n_ar):
                    k = h - 1 - i
                    if k >= 0:
                        s += coef[m, 1 + i] * work[k]
                    else:
                        s += coef[m, 1 + i] * state[m, -k - 1]
                for j in range(h, n_ma):
                    s += coef[m, 1 + n_ar + j] * state[m, n_ar + j - h]
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



@jit
def css_filters(e, ar, ma, v, w, u, y, zv, zw, zu, zy):
    """Run the four all-pole filters of one CSS Newton step in one pass over time.

    ``v = lfilter([1], ar, e)``, ``w = lfilter([1], ma, e)``, ``u = lfilter([1], ma,
    v)`` and ``y = lfilter([1], ma, w)`` (the first and second derivatives of the
    innovations, see ``arma._css_refine``), each bit for bit what scipy returns: scipy's
    direct form II transposed loop (``DOUBLE_filt`` of ``_lfilter.c``) with the
    numerator ``[1]`` zero-padded to the denominator's length ``L``, per sample
    ``y_t = z_0 + 1 x_t``, ``z_k = z_{k+1} + x_t 0 - y_t a_{k+1}``, ``z_{L-2} = x_t 0 -
    y_t a_{L-1}`` (the ``x 0`` products are kept: they are what scipy computes), and
    for ``L = 1`` (scipy's convolution path) ``y = x``. Checked against scipy in
    ``tests/forecast/test_kernels.py``. One pass runs the four independent recursions
    side by side instead of four scipy calls.

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
            vn = zv[0] + 1.0 * x
            for k in range(n_ar - 1):
                zv[k] = zv[k + 1] + x * 0.0 - vn * ar[k + 1]
            zv[n_ar - 1] = x * 0.0 - vn * ar[n_ar]
        if n_ma == 0:
            wn = x
            un = vn
            yn = wn
        else:
            wn = zw[0] + 1.0 * x
            un = zu[0] + 1.0 * vn
            yn = zy[0] + 1.0 * wn
            for k in range(n_ma - 1):
                c = ma[k + 1]
                zw[k] = zw[k + 1] + x * 0.0 - wn * c
                zu[k] = zu[k + 1] + vn * 0.0 - un * c
                zy[k] = zy[k + 1] + wn * 0.0 - yn * c
            c = ma[n_ma]
            zw[n_ma - 1] = x * 0.0 - wn * c
            zu[n_ma - 1] = vn * 0.0 - un * c
            zy[n_ma - 1] = wn * 0.0 - yn * c
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
    overhead, for the CSS refinement's many short fits.

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
