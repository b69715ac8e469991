"""Coverage of the Gaussian-method MI interval on iid Gaussian pairs (leftovers 19-ci, c11).

Reference: the exact MI of a bivariate Gaussian pair of correlation rho,
``-0.5 ln(1 - rho^2)`` nats (Cover & Thomas 2006, Example 8.5.1). Per cell (n, rho) and
seed s: x, y iid Gaussian pairs drawn from ``default_rng(1000 + s)``; one call
``mutual_information_ci(x, y, method="gaussian", n_resamples=R, seed=s)`` (default block
bootstrap, default "normal" interval); from its bootstrap distribution the bench also
builds, on the same replicates:

- ``plain``: the estimate -+ z s_boot on the MI scale (the interval before leftovers 19-ci);
- ``pct`` / ``basic``: percentile and reverse-percentile intervals;
- ``fz``: estimate and replicates mapped to Fisher's z of the equivalent correlation,
  ``z = atanh(sqrt(1 - exp(-2 I)))``, z -+ 1.96 sd(z_boot), mapped back (what the
  function returns for method="gaussian" after leftovers 19-ci: ``func``);
- ``fz_an``: the same with the analytic iid spread 1 / sqrt(n - 3) (no bootstrap; not
  valid for autocorrelated series, shown as a reference).

Printed per cell: coverage of each interval at 0.95 (binomial standard error
sqrt(0.95 x 0.05 / seeds): 0.011 at 400 seeds), the mean bootstrap spread of the MI
against the standard deviation of the estimates over the seeds, and the time.

    OPENBLAS_NUM_THREADS=1 PYTHONPATH=. nice python benchmarks/bench_gaussian_ci_left19.py \\
        --n 100,1000 --rho 0.3,0.6,0.9 --seeds 400 --resamples 199
"""

from __future__ import annotations

import argparse
import math
import time
import warnings

import numpy as np
from scipy import stats

from modalinfo.information import mutual_information_ci


def to_z(i: np.ndarray | float) -> np.ndarray:
    """Fisher's z of the correlation whose Gaussian MI is ``i`` nats (``i >= 0``)."""
    return np.arctanh(np.sqrt(-np.expm1(-2.0 * np.maximum(i, 0.0))))


def from_z(z: np.ndarray | float) -> np.ndarray:
    """The Gaussian MI [nats] of the correlation ``tanh(z)``; 0 for z <= 0."""
    return -0.5 * np.log1p(-np.tanh(np.maximum(z, 0.0)) ** 2)


def cell(n: int, rho: float, seeds: int, resamples: int) -> dict[str, float]:
    truth = -0.5 * math.log(1.0 - rho * rho)
    q = stats.norm.ppf(0.975)
    keys = ("func", "plain", "pct", "basic", "fz", "fz_an")
    hits = dict.fromkeys(keys, 0)
    est, spread = [], []
    for s in range(seeds):
        rng = np.random.default_rng(1000 + s)
        x = rng.standard_normal(n)
        y = rho * x + math.sqrt(1.0 - rho * rho) * rng.standard_normal(n)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # the block-bootstrap caution at n = 100
            r = mutual_information_ci(x, y, method="gaussian", n_resamples=resamples, seed=s)
        d, th = r.bootstrap_distribution, r.estimate
        est.append(th)
        spread.append(np.std(d, ddof=1))
        lo, hi = np.quantile(d, [0.025, 0.975])
        zt, zd = to_z(th), to_z(d)
        hz = q * np.std(zd, ddof=1)
        ha = q / math.sqrt(n - 3)
        bounds = {
            "func": (r.low, r.high),
            "plain": (th - q * spread[-1], th + q * spread[-1]),
            "pct": (lo, hi),
            "basic": (2 * th - hi, 2 * th - lo),
            "fz": (from_z(zt - hz), from_z(zt + hz)),
            "fz_an": (from_z(zt - ha), from_z(zt + ha)),
        }
        for k, (a, b) in bounds.items():
            hits[k] += a <= truth <= b
    out = {k: hits[k] / seeds for k in keys}
    out["s_boot"] = float(np.mean(spread))
    out["sd_est"] = float(np.std(est, ddof=1))
    return out


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--n", default="100,1000,10000")
    p.add_argument("--rho", default="0.3,0.6,0.9")
    p.add_argument("--seeds", type=int, default=400)
    p.add_argument("--resamples", type=int, default=199)
    a = p.parse_args()
    print("| n | rho | R | func | plain | pct | basic | fz | fz_an | s_boot | sd_est | time [s] |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for n in (int(v) for v in a.n.split(",")):
        for rho in (float(v) for v in a.rho.split(",")):
            t = time.perf_counter()
            c = cell(n, rho, a.seeds, a.resamples)
            print(f"| {n} | {rho} | {a.resamples} | {c['func']:.3f} | {c['plain']:.3f} | "
                  f"{c['pct']:.3f} | {c['basic']:.3f} | {c['fz']:.3f} | {c['fz_an']:.3f} | "
                  f"{c['s_boot']:.4f} | {c['sd_est']:.4f} | {time.perf_counter() - t:.0f} |",
                  flush=True)


if __name__ == "__main__":
    main()
