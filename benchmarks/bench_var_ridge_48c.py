"""The `multivariate` preset's relative ridge against alpha 0 / GCV / statsmodels OLS (fix48-c).

Run: OPENBLAS_NUM_THREADS=1 python benchmarks/bench_var_ridge_48c.py [shipped|smooth|all]

Round 47 PART a observed the ``multivariate`` preset (``MultivariatePredictor(order=4)``,
relative ridge ``alpha = 1e-3``) 3.3x worse than persistence at h = 1 on a smooth
synthetic open-loop log where an unregularised VAR gains 25x. For each log, VAR(4) fitted
on the first ``train`` frames (Figure 5's 7000 on the 8000-frame logs) and scored on the
rest, whole-wavefront RMSE gain over persistence (persistence RMSE / the predictor's):

- ``pkg a=...``: :func:`modalinfo.forecast.evaluate` of ``MultivariatePredictor(order=4,
  alpha=a)`` (h = 1, 5; Figure 5's protocol);
- ``np a=...``: the same ridge solved here with numpy (``(Z^T Z + a diag(Z^T Z)) B = Z^T
  Y`` on the centred lags), forecasts iterated here, origins ``train - 1 .. T - h - 1``;
- ``gcv``: the ridge chosen by generalised cross-validation (Golub, Heath & Wahba 1979)
  on the training frames, ``n RSS(a) / (n - tr H(a))^2`` over ``a`` in {0} and 10^-10 ..
  10^0 by half decades, one ``a`` shared by all modes (on unit-norm lag columns, where the
  relative ridge is an ordinary one);
- ``OLS``: statsmodels ``VAR(X).fit(4, trend="c")``, the reference fit, forecasts iterated
  here from its coefficients;
- ``preset``: :func:`modalinfo.forecast.evaluate` of the ``multivariate`` preset
  (``MultivariatePredictor(order=4, alpha="gcv")`` since fix48-d) and its ``alpha_``
  (rows "fix48-d"; the fix48-c rows were run before that column existed).

Logs: ``data/`` (Figure 5's "spectral" ``kaos_like_closed_loop.npz`` and "simulated"
``kaos_closedloop.npz``, and ``kaos_like_open_loop.npz``), and smooth synthetic open-loop
logs (``modalinfo.telemetry.synthetic.open_loop_log``, D = 4 m, r0 = 0.1 m, 1 kHz, one
layer): round 47's (modes Z2-Z7, 10 m/s, seed 2, 3000 frames, train 1500) and three of
8000 frames (train 7000). Table: benchmarks/RESULTS.md, rows "fix48-c".
"""

from __future__ import annotations

import sys
import warnings
from pathlib import Path

import numpy as np

P = 4
ALPHAS = (1e-3, 1e-4, 1e-6, 0.0)
GRID = (0.0, *(10.0 ** np.arange(-10, 0.25, 0.5)))


def _lagged(x, p):
    n = len(x)
    return np.concatenate([x[p - i:n - i] for i in range(1, p + 1)], axis=1), x[p:]


def _gain(x, n_train, mu, coefs, h):
    """Persistence RMSE / iterated VAR RMSE (whole wavefront) at horizon ``h``."""
    xc = x - mu
    origins = np.arange(n_train - 1, len(x) - h)
    hist = [xc[origins - i] for i in range(coefs.shape[0])]  # lag 1 first, (n_o, M) each
    for _ in range(h):
        nxt = sum(hist[i] @ coefs[i] for i in range(coefs.shape[0]))
        hist = [nxt, *hist[:-1]]
    err = hist[0] - xc[origins + h]
    pers = x[origins] - x[origins + h]
    return float(np.sqrt(np.mean(np.sum(pers ** 2, 1)) / np.mean(np.sum(err ** 2, 1))))


def _ridge(x, alpha):
    mu = x.mean(0)
    z, y = _lagged(x - mu, P)
    g = z.T @ z
    b = np.linalg.solve(g + alpha * np.diag(np.diag(g)), z.T @ y)
    return mu, b.reshape(P, x.shape[1], x.shape[1])


def _gcv(x):
    mu = x.mean(0)
    z, y = _lagged(x - mu, P)
    u, s, _ = np.linalg.svd(z / np.sqrt(np.sum(z ** 2, 0)), full_matrices=False)
    uty = u.T @ y
    rss0 = np.sum(y ** 2) - np.sum(uty ** 2)
    n = len(y)
    scores = []
    for a in GRID:
        f = s ** 2 / (s ** 2 + a)
        rss = rss0 + np.sum(((1 - f)[:, None] * uty) ** 2)
        scores.append(n * rss / (n - np.sum(f)) ** 2)
    return GRID[int(np.argmin(scores))]


def _ols(x):
    from statsmodels.tsa.api import VAR

    fit = VAR(x).fit(P, trend="c")
    a = fit.coefs  # a[i, m, k]: lag i + 1 of mode k in mode m
    mu = np.linalg.solve(np.eye(x.shape[1]) - a.sum(0), fit.intercept)
    return mu, np.transpose(a, (0, 2, 1))


def row(name, x, n_train):
    from modalinfo.forecast import MultivariatePredictor, evaluate
    from modalinfo.forecast.presets import make_predictor

    preds = {f"a={a:g}": MultivariatePredictor(order=P, alpha=a) for a in ALPHAS}
    preds["preset"] = make_predictor("multivariate")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ev = evaluate(preds, x, train=n_train, horizons=[1, 5])
    cells = [f"{ev.gain_wavefront[ev.index(k), 0]:.5g} / {ev.gain_wavefront[ev.index(k), 1]:.5g}"
             for k in preds]
    xt = x[:n_train]
    fits = {"np a=1e-3": _ridge(xt, 1e-3), "np a=0": _ridge(xt, 0.0)}
    a_gcv = _gcv(xt)
    fits[f"gcv (a={a_gcv:.2g})"] = _ridge(xt, a_gcv)
    fits["OLS"] = _ols(xt)
    for mu, c in fits.values():
        cells.append(f"{_gain(x, n_train, mu, c, 1):.5g} / {_gain(x, n_train, mu, c, 5):.5g}")
    a_preset = make_predictor("multivariate").fit(xt).alpha_
    print(f"| {name} | {x.shape[1]} | {n_train} | " + " | ".join(cells)
          + f" | {a_gcv:.2g} | {a_preset:.2g} |", flush=True)


def main(which: str = "all") -> None:
    print("| log | modes | train | " + " | ".join(f"pkg a={a:g}" for a in ALPHAS)
          + " | preset | np a=1e-3 | np a=0 | np gcv | statsmodels OLS | gcv a | preset alpha_ |")
    print("|---" * 14 + "|")
    if which in ("shipped", "all"):
        data = Path(__file__).resolve().parent.parent / "data"
        for f in ("kaos_like_closed_loop", "kaos_closedloop", "kaos_like_open_loop"):
            row(f, np.asarray(np.load(data / f"{f}.npz")["coefficients"], float), 7000)
    if which in ("smooth", "all"):
        from modalinfo.telemetry import synthetic

        def smooth(modes, n, wind, seed):
            log = synthetic.open_loop_log(modes, n_frames=n, rate=1000.0, diameter=4.0,
                                          layers=[synthetic.Layer(r0=0.1, wind_speed=wind)],
                                          seed=seed)
            return np.asarray(log.coeffs, float)

        row("smooth, round 47 (Z2-Z7, 10 m/s, seed 2)", smooth(range(2, 8), 3000, 10.0, 2), 1500)
        for seed, wind, modes in ((3, 5.0, range(2, 8)), (4, 20.0, range(2, 12)),
                                  (5, 10.0, range(2, 17))):
            row(f"smooth (Z2-Z{modes[-1]}, {wind:g} m/s, seed {seed})",
                smooth(modes, 8000, wind, seed), 7000)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "all")
