"""False-positive rate of every surrogate test of modalinfo (issue 28, item 3).

Run: nice -n 5 /work/main/.venv/bin/python benchmarks/bench_surrogate_fpr.py
     [--trials 1000] [--n 500] [--surrogates 99] [--jobs 1] [--tests ...] [--phis ...]

Null: x and y are independent stationary AR(1) series (coefficient phi = 0.9 and
0.99, unit innovations, stationary start), n samples. Every trial draws one pair and
runs every test on it with the Gaussian estimator (the cheapest) and N surrogates:

``mi_circular``
    :func:`modalinfo.information.mutual_information_permutation_test`,
    ``permutation="circular"`` (time-shifted surrogates of y), statistic I(x; y).
``mi_shuffle``
    The same with ``permutation="shuffle"``: documented as exact for iid pairs only
    (anti-conservative on autocorrelated series); listed to show by how much.
``cmi_circular``
    :func:`modalinfo.information.conditional_mutual_information_test` of the transfer
    entropy form ``I(y_t; x_(t-1) | y_(t-1))``, circular surrogates.
``te_map``
    :func:`modalinfo.information.transfer_entropy_map` of the pair (lag 1, history 1,
    2 cells): a false positive is any cell with a step-down maxT p-value <= alpha.
``select``
    :func:`modalinfo.information.select_inputs` of y at horizon 1 with candidates
    ``y_t`` and ``x_t`` (``max_lag=1``, x given as ``extra``): the first step picks
    ``y_t`` (the whole true model); a false positive is the second step (``x_t``)
    passing, i.e. its p-value <= alpha (the search runs at alpha = 0.10 and records
    the second step's p-value, selected or not).

With N surrogates an exact test at level alpha rejects with probability
``floor(alpha (N + 1)) / (N + 1)`` (alpha itself for N = 199, 99). The table gives
each rate with its binomial standard error ``sqrt(a (1 - a) / trials)`` at the exact
level a, and the deviation in standard errors. Seeds: trial k of coefficient index i
uses ``default_rng([i, k])`` for the data and ``[i, k, 1 + test]`` for the test, so
the table is reproducible bit for bit. Single-threaded BLAS.
"""

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import math  # noqa: E402
import time  # noqa: E402
from concurrent.futures import ProcessPoolExecutor  # noqa: E402

import numpy as np  # noqa: E402
from _common import int_options  # noqa: E402
from scipy.signal import lfilter  # noqa: E402

from modalinfo.information import (  # noqa: E402
    conditional_mutual_information_test,
    mutual_information_permutation_test,
    select_inputs,
    transfer_entropy_map,
)

PHIS = (0.9, 0.99)
ALPHAS = (0.05, 0.10)
TESTS = ("mi_circular", "mi_shuffle", "cmi_circular", "te_map", "select")


def ar1(phi: float, n: int, rng: np.random.Generator) -> np.ndarray:
    """Stationary AR(1) with unit innovations: x_t = phi x_(t-1) + e_t."""
    x_prev = rng.standard_normal() / math.sqrt(1.0 - phi * phi)
    return lfilter([1.0], [1.0, -phi], rng.standard_normal(n), zi=[phi * x_prev])[0]


def one_trial(args: tuple) -> dict[str, float]:
    """p-value of every test on trial k of coefficient index i."""
    i, k, n, n_surr, tests = args
    rng = np.random.default_rng([i, k])
    phi = PHIS[i]
    x, y = ar1(phi, n, rng), ar1(phi, n, rng)
    out: dict[str, float] = {}
    for t, name in enumerate(TESTS):
        if name not in tests:
            continue
        seed = np.random.default_rng([i, k, 1 + t])
        if name in ("mi_circular", "mi_shuffle"):
            res = mutual_information_permutation_test(
                x, y, "gaussian", n_permutations=n_surr, permutation=name[3:], seed=seed)
            out[name] = res.pvalue
        elif name == "cmi_circular":
            res = conditional_mutual_information_test(
                y[1:], x[:-1], y[:-1], method="gaussian", n_surrogates=n_surr, seed=seed)
            out[name] = res.pvalue
        elif name == "te_map":
            te = transfer_entropy_map(np.column_stack([x, y]), lags=1, history=1,
                                      n_surrogates=n_surr, seed=seed)
            out[name] = float(np.nanmin(te.pvalue))
        else:
            sel = select_inputs(y[:, None], 0, horizon=1, max_lag=1, extra=x[:, None],
                                alpha=max(ALPHAS), n_surrogates=n_surr, max_inputs=2,
                                intervals=False, seed=seed)
            extra = [s.pvalue for s in sel.inputs if s.mode.startswith("extra:")]
            if extra:
                out[name] = extra[0]
            elif len(sel.inputs) == 1:
                out[name] = sel.last_pvalue  # the second step's p-value, not significant
            else:  # the first step failed: no second step was tested
                out[name] = math.inf
    return out


def main() -> None:
    ap = int_options(__doc__, trials=1000, n=500, surrogates=99, jobs=1)
    ap.add_argument("--tests", nargs="+", default=list(TESTS), choices=TESTS)
    ap.add_argument("--phis", nargs="+", type=float, default=list(PHIS), choices=PHIS)
    a = ap.parse_args()
    print(f"n = {a.n}, {a.surrogates} surrogates, {a.trials} trials per coefficient, "
          f"Gaussian estimator")
    print(f"{'test':13s} {'phi':>5s} " + " ".join(
        f"{'FPR@' + format(al, 'g'):>9s} {'se':>6s} {'dev/se':>6s}" for al in ALPHAS))
    for i, phi in enumerate(PHIS):
        if phi not in a.phis:
            continue
        t0 = time.perf_counter()
        jobs = [(i, k, a.n, a.surrogates, tuple(a.tests)) for k in range(a.trials)]
        if a.jobs > 1:
            with ProcessPoolExecutor(a.jobs) as pool:
                rows = list(pool.map(one_trial, jobs, chunksize=20))
        else:
            rows = [one_trial(j) for j in jobs]
        for name in a.tests:
            p = np.array([r[name] for r in rows])
            cells = []
            for al in ALPHAS:
                level = math.floor(al * (a.surrogates + 1) + 1e-9) / (a.surrogates + 1)
                rate = float(np.mean(p <= al + 1e-12))
                se = math.sqrt(level * (1.0 - level) / p.size)
                cells.append(f"{rate:9.4f} {se:6.4f} {(rate - level) / se:+6.1f}")
            print(f"{name:13s} {phi:5.2f} " + " ".join(cells))
        print(f"  ({time.perf_counter() - t0:.0f} s wall for phi = {phi})", flush=True)


if __name__ == "__main__":
    main()
