"""Forecast benchmark: our ARMA / linear predictors against statsmodels.

Run::

    /work/venv/bin/python benchmarks/bench_forecast.py [--quick]

1. ARMA(2, 3) fit on 7000 samples + 1000 rolling one-step forecasts: ours (Hannan-
   Rissanen + CSS Gauss-Newton, then the numba recursion) versus statsmodels'
   default ``ARIMA(order=(2, 0, 3)).fit()`` followed by one fixed-parameter filtering
   pass over the 8000 samples; one-step RMSE of both.
2. Yule-Walker AR(p) (ours) versus the statsmodels ARMA(2, 3) forecasts: RMSE, speed.
3. Online update cost per step (ARMA(2, 3), paper linear) with M = 27 and M = 1, after
   1e3, 1e4 and 1e5 samples of history (must not grow), versus statsmodels'
   ``ARIMAResults.append`` (refilters the whole history every step).

Timings are medians over repeats; the machine is shared, so ratios are what matters.
"""

from __future__ import annotations

import argparse
import functools
import time
import warnings

import numpy as np
from _common import timed
from scipy.signal import lfilter

from modalinfo.forecast import ARMAPredictor, LinearPredictor

PHI = np.array([1.3, -0.4])
THETA = np.array([-0.5, 0.2, 0.15])


def _series(n, seed=0, m=1):
    rng = np.random.default_rng(seed)
    e = rng.standard_normal((n + 1000, m))
    return np.ascontiguousarray(lfilter(np.r_[1.0, THETA], np.r_[1.0, -PHI], e, axis=0)[1000:])


_median_time = functools.partial(timed, warm=False)  # wall time, every call timed


def bench_fit_and_forecast(repeats_ours, repeats_sm):
    from statsmodels.tsa.arima.model import ARIMA

    x = _series(8000)[:, 0]
    n_train = 7000

    def ours():
        pred = ARMAPredictor(order=(2, 3), horizon=1).fit(x[:n_train])
        path, _ = pred._forecast_path(x[:, None], 1)
        return path[n_train - 1 : -1, 0, 0]

    def sm():
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            res = ARIMA(x[:n_train], order=(2, 0, 3)).fit()
            full = ARIMA(x, order=(2, 0, 3)).filter(res.params)
        return full.predict(start=n_train, end=x.size - 1)

    ours()  # compile / warm caches
    t_ours, f_ours = _median_time(ours, repeats_ours)
    t_sm, f_sm = _median_time(sm, repeats_sm)
    r_ours = np.sqrt(np.mean((x[n_train:] - f_ours) ** 2))
    r_sm = np.sqrt(np.mean((x[n_train:] - f_sm) ** 2))
    print("## 1. ARMA(2,3) fit on 7000 samples + 1000 rolling one-step forecasts")
    print(f"ours (HR + CSS, numba recursion): {t_ours * 1e3:8.2f} ms   RMSE {r_ours:.5f}")
    print(f"statsmodels ARIMA.fit + filter:   {t_sm * 1e3:8.2f} ms   RMSE {r_sm:.5f}")
    print(f"speed-up {t_sm / t_ours:.0f}x ; RMSE ratio ours/statsmodels {r_ours / r_sm:.5f}")
    print()
    return x, n_train, r_sm, t_sm


def bench_yule_walker(x, n_train, r_sm, t_sm, repeats):
    print("## 2. Yule-Walker AR(p) versus the statsmodels ARMA(2,3) forecasts")
    for p in (2, 4, 8):
        def yw(p=p):
            pred = ARMAPredictor(order=(p, 0), horizon=1).fit(x[:n_train])
            path, _ = pred._forecast_path(x[:, None], 1)
            return path[n_train - 1 : -1, 0, 0]

        yw()
        t, f = _median_time(yw, repeats)
        r = np.sqrt(np.mean((x[n_train:] - f) ** 2))
        print(f"YW AR({p}): {t * 1e3:7.3f} ms  RMSE {r:.5f} ({(r / r_sm - 1) * 100:+.2f}% vs "
              f"statsmodels ARMA(2,3) ML), speed-up {t_sm / t:.0f}x")
    print()


def _update_cost(pred, x, n_history, n_steps):
    pred.reset()
    for row in x[:n_history]:
        pred.update(row)
    t0 = time.perf_counter()
    for row in x[n_history : n_history + n_steps]:
        pred.update(row)
    return (time.perf_counter() - t0) / n_steps


def bench_update(quick):
    print("## 3. Online update cost per step (median of 5 blocks)")
    histories = (1000, 10000) if quick else (1000, 10000, 100000)
    n_steps = 2000
    for m in (27, 1):
        x = _series(max(histories) + n_steps + 10, seed=1, m=m)
        for name, pred in (("ARMA(2,3)", ARMAPredictor(order=(2, 3))),
                           ("linear a=2,b=-1", LinearPredictor())):
            pred.fit(x[:5000])
            row = []
            for n_hist in histories:
                costs = [_update_cost(pred, x, n_hist, n_steps) for _ in range(5)]
                c = float(np.median(costs))
                row.append(f"history {n_hist:>6}: {c * 1e6:6.2f} us/step "
                           f"({c * 1e6 / m:5.2f} us/mode)")
            print(f"M={m:2d} {name:16s} " + " | ".join(row))
    # the other predictors, for information (M = 27, history 1000)
    from modalinfo.forecast import (
        MultivariatePredictor,
        NeuralNetPredictor,
        RLSMultivariatePredictor,
    )

    x = _series(5000 + n_steps + 10, seed=2, m=27)
    for name, pred in (("NN 10-10-1", NeuralNetPredictor(n_patterns=200, max_iter=50)),
                       ("VAR(4) batch", MultivariatePredictor(order=4)),
                       ("VAR(4) RLS", RLSMultivariatePredictor(order=4))):
        pred.fit(x[:3000])
        c = float(np.median([_update_cost(pred, x, 1000, n_steps) for _ in range(3)]))
        print(f"M=27 {name:16s} history   1000: {c * 1e6:7.2f} us/step "
              f"({c * 1e6 / 27:5.2f} us/mode)")
    print()


def bench_statsmodels_append(n_steps):
    from statsmodels.tsa.arima.model import ARIMA

    x = _series(8000)[:, 0]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = ARIMA(x[:7000], order=(2, 0, 3)).fit()
        t0 = time.perf_counter()
        for t in range(7000, 7000 + n_steps):
            res = res.append(x[t : t + 1], refit=False)
            res.forecast(1)
        per = (time.perf_counter() - t0) / n_steps
    print(f"statsmodels ARIMAResults.append + forecast(1), M=1, history ~7000: "
          f"{per * 1e3:.2f} ms/step")
    return per


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--quick", action="store_true")
    args = parser.parse_args()
    x, n_train, r_sm, t_sm = bench_fit_and_forecast(3 if args.quick else 7,
                                                    1 if args.quick else 3)
    bench_yule_walker(x, n_train, r_sm, t_sm, 5)
    bench_update(args.quick)
    bench_statsmodels_append(10 if args.quick else 30)


if __name__ == "__main__":
    main()
