"""Coverage of the histogram CMI interval, and its finite-sample bias rule (leftovers 14-misc).

``conditional_mutual_information_ci(method="histogram")`` (99 resamples) of the TE of
the VAR(1) of ``bench_information_time.py --coverage`` (x_t = 0.6 x_{t-1} + 0.5
y_{t-1} + e, y_t = 0.8 y_{t-1} + f) and of the same variables drawn iid (rows of an
equal-covariance Gaussian, no persistence): per cell, the coverage of the binned
estimand (the estimator at the same bins on two 2e6-row series), the share of calls
warned by the interval's bias rule (``resampling.interval_bias_rule``) and the coverage
among the silent and the warned calls; binomial 95 % ranges are for the counts printed.

    OPENBLAS_NUM_THREADS=1 PYTHONPATH=. python benchmarks/bench_cmi_interval_bias.py \\
        --trials 200 --cells var:1000,var:10000,iid:1000,iid:10000
    # explicit bins per axis: --cells iid:10000:4,var:10000:4
"""

from __future__ import annotations

import argparse
import sys
import time
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_information_time import _bins_per_axis, var1  # noqa: E402

from modalinfo.information import (  # noqa: E402
    conditional_mutual_information,
    conditional_mutual_information_ci,
    transfer_entropy_variables,
)
from modalinfo.information.resampling import BlockBootstrapWarning  # noqa: E402

A, B, C = 0.6, 0.8, 0.5


def rows(kind: str, n: int, seed: int):
    """(x, y, z) of n rows: the VAR(1)'s TE variables, or iid rows of their covariance."""
    if kind == "var":
        return transfer_entropy_variables(*var1(n, A, B, C, seed))
    big = np.column_stack(transfer_entropy_variables(*var1(200_000, A, B, C, 99)))
    cov = np.cov(big, rowvar=False)
    r = np.random.default_rng(seed).multivariate_normal(np.zeros(3), cov, size=n)
    return r[:, :1], r[:, 1:2], r[:, 2:]


def cell(kind: str, n: int, trials: int, bins: int | None = None) -> None:
    k = _bins_per_axis("auto", n, 3) if bins is None else bins
    target = float(np.mean([conditional_mutual_information(
        *rows(kind, 2_000_000, 10_000 + s), bins=k, method="histogram") for s in range(2)]))
    t0 = time.process_time()
    hits = {True: [], False: []}
    for s in range(trials):
        x, y, z = rows(kind, n, 500 + s)
        with warnings.catch_warnings(record=True) as got:
            warnings.simplefilter("always")
            ci = conditional_mutual_information_ci(x, y, z, method="histogram", bins=k,
                                                   n_resamples=99, seed=s)
        warned = any(issubclass(w.category, BlockBootstrapWarning)
                     and "finite-sample bias" in str(w.message) for w in got)
        hits[warned].append(ci.low <= target <= ci.high)
    cover = np.mean(hits[True] + hits[False])
    silent, warned = hits[False], hits[True]
    print(f"{kind:>3} n = {n:>6} ({k} bins, estimand {target:.4f}): coverage {cover:.3f}; "
          f"warned {len(warned)}/{trials}; coverage silent "
          f"{np.mean(silent) if silent else float('nan'):.3f} ({sum(silent)}/{len(silent)}),"
          f" warned {np.mean(warned) if warned else float('nan'):.3f} "
          f"({sum(warned)}/{len(warned)}); {time.process_time() - t0:.0f} s CPU", flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--trials", type=int, default=200)
    parser.add_argument("--cells", default="var:1000,var:10000,iid:1000,iid:10000")
    args = parser.parse_args()
    for spec in args.cells.split(","):  # kind:n or kind:n:bins
        kind, n, *bins = spec.split(":")
        cell(kind, int(n), args.trials, int(bins[0]) if bins else None)


if __name__ == "__main__":
    main()
